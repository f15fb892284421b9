//! The time scales and dimensionless groups of a Brownian scene (thesis section 3.8,
//! paper eqs 2.28-2.31; docs/physics.md section 11), with `a` the small radius.
use serde::Serialize;
use std::f64::consts::PI;

/// Largest inertia-diffusion ratio `tau_I / tau_B` the seeds state as negligible (thesis
/// section 3.8); their own Table 4.1 runs at 0.17, where the long-time diffusion still
/// agreed (thesis section 4.2.4).
pub const INERTIA_DIFFUSION_LIMIT: f64 = 0.01;

/// Thermal energy and what it sets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ThermalScales {
    /// Thermal energy `kT` (units of energy: eta a^3 / time).
    pub kt: f64,
    /// Brownian time `tau_B = eta a^3 / kT`.
    pub tau_b: f64,
    /// Inertial (viscous relaxation) time `tau_I = rho a^2 / eta`.
    pub tau_i: f64,
    /// `tau_I / tau_B = rho kT / (eta^2 a)`.
    pub inertia_diffusion: f64,
    /// Peclet number `6 pi eta a^3 gdot_max / kT = 6 pi tau_B gdot_max`; absent without
    /// flow.
    pub peclet: Option<f64>,
}

impl ThermalScales {
    /// Scales at thermal energy `kt > 0` for fluid viscosity `eta`, particle density
    /// `rho`, small radius `a` and largest shear rate `gdot_max` (0 without flow).
    pub fn new(kt: f64, eta: f64, rho: f64, a: f64, gdot_max: f64) -> Self {
        let tau_b = eta * a.powi(3) / kt;
        let tau_i = rho * a * a / eta;
        Self {
            kt,
            tau_b,
            tau_i,
            inertia_diffusion: tau_i / tau_b,
            peclet: (gdot_max > 0.0).then_some(6.0 * PI * tau_b * gdot_max),
        }
    }

    /// The warning when inertia is not negligible against diffusion.
    pub fn warning(&self) -> Option<String> {
        (self.inertia_diffusion > INERTIA_DIFFUSION_LIMIT).then(|| {
            format!(
                "inertia-diffusion ratio tau_I/tau_B = rho kT/(eta^2 a) = {:.3} > {INERTIA_DIFFUSION_LIMIT}: \
                 the seeds' limit for negligible inertia (thesis 3.8; their Table 4.1 runs at 0.17)",
                self.inertia_diffusion
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Thesis Table 4.1 (a = 1, rho = eta = 0.1): kT = 0.017 gives tau_B = 5.9 and
    /// tau_I = 1; at gdot = 9e-3, Pe = 1.0; kT = 1.7e-6 at the same rate gives Pe = 1e4.
    #[test]
    fn table_4_1_scales() {
        let s = ThermalScales::new(0.017, 0.1, 0.1, 1.0, 9.0e-3);
        assert!((s.tau_b - 5.88).abs() < 0.01, "{}", s.tau_b);
        assert!((s.tau_i - 1.0).abs() < 1e-12);
        assert!((s.peclet.unwrap() - 1.0).abs() < 0.01, "{:?}", s.peclet);
        assert!(s.warning().is_some_and(|w| w.contains("0.170")));
        let high = ThermalScales::new(1.7e-6, 0.1, 0.1, 1.0, 9.0e-3);
        assert!((high.peclet.unwrap() / 1e4 - 1.0).abs() < 0.01);
        assert!(high.warning().is_none());
        assert_eq!(ThermalScales::new(0.017, 0.1, 0.1, 1.0, 0.0).peclet, None);
    }
}
