//! The time scales and dimensionless groups of a Brownian scene (thesis section 3.8,
//! paper eqs 2.28-2.31; docs/physics.md section 11), with `a` the small radius.
use crate::error::SimError;
use crate::input::scene_file::FluidSection;
use crate::input::scene_limits::show;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Largest inertia-diffusion ratio `tau_I / tau_B` the seeds state as negligible (thesis
/// section 3.8); their own Table 4.1 runs at 0.17, where the long-time diffusion still
/// agreed (thesis section 4.2.4).
pub const INERTIA_DIFFUSION_LIMIT: f64 = 0.01;

/// Largest thermal overlap `sqrt(kT / k_n) / a` without a warning. Thesis Table 4.1 has
/// 1.3e-3; the shipped colloidal curves reach 4.3e-3 (Pe = 1 through kT at gdot = 0.01,
/// eta = 1, k_n = 1e4). Measured here (reports/mixtures/README.md): a colloid-grain mixture
/// at phi 0.565 with Pe_c lowered through kT blew up at 0.014 and 0.025 (Pe_c 0.1 and 0.03)
/// and ran at 0.008 (Pe_c 0.3).
pub const THERMAL_OVERLAP_LIMIT: f64 = 0.01;

/// The warning when the contacts are soft against the thermal energy: the overlap
/// `sqrt(kT / k_n)` of a Hookean contact of stiffness `k_n` at thermal energy `kt`, over the
/// smallest radius present `a`, above [`THERMAL_OVERLAP_LIMIT`].
pub fn soft_contact_warning(kt: f64, k_n: f64, a: f64) -> Option<String> {
    let overlap = (kt / k_n).sqrt() / a;
    (overlap > THERMAL_OVERLAP_LIMIT).then(|| {
        format!(
            "thermal overlap sqrt(kT/k_n)/a = {overlap:.3} > {THERMAL_OVERLAP_LIMIT}: contacts are \
             soft against kT (thesis Table 4.1: 0.0013; mixtures blew up at 0.014); raise \
             forces.k_n, or lower Pe through the shear rate at a fixed kT, as Table 4.1 does \
             below Pe = 1"
        )
    })
}

/// The warning when inertia is not negligible against diffusion: the inertia-diffusion
/// ratio `rho kT / (eta^2 a)` of the smallest radius present `a` (the largest ratio of the
/// scene; a grains-only scene of a mixture grid is judged by its grains, not by the colloid
/// radius its Pe_c refers to) above [`INERTIA_DIFFUSION_LIMIT`].
pub fn inertia_warning(kt: f64, eta: f64, rho: f64, a: f64) -> Option<String> {
    let ratio = ThermalScales::new(kt, eta, rho, a, 0.0).inertia_diffusion;
    (ratio > INERTIA_DIFFUSION_LIMIT).then(|| {
        format!(
            "inertia-diffusion ratio tau_I/tau_B = rho kT/(eta^2 a) = {ratio:.3} > {INERTIA_DIFFUSION_LIMIT}: \
             the seeds' limit for negligible inertia (thesis 3.8; their Table 4.1 runs at 0.17)"
        )
    })
}

/// Thermal energy and what it sets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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

/// Peclet number `Pe = 6 pi eta a^3 gdot / kT` (paper section 2.6, thesis eq 2.4) of a
/// sphere of radius `a` in fluid of viscosity `eta` sheared at `gdot` at thermal energy `kt`.
pub fn peclet_number(eta: f64, a: f64, gdot: f64, kt: f64) -> f64 {
    6.0 * PI * eta * a.powi(3) * gdot / kt
}

/// Largest relative disagreement accepted between a given `fluid.peclet` and the one the
/// given shear rate and thermal energy imply (room for decimal round-off of a written-out
/// scene).
const PECLET_TOLERANCE: f64 = 1e-9;

/// Completes a homogeneous-shear fluid section given by its Peclet number `fluid.peclet`
/// (small radius `a`): with `fluid.shear_rate`, sets `kT = 6 pi eta a^3 gdot / Pe` (Pe
/// through the thermal energy at a fixed rate); with `fluid.kT`, sets
/// `shear_rate = Pe kT / (6 pi eta a^3)` (Pe through the rate at a fixed thermal energy;
/// thesis Table 4.1 does the first above Pe = 1 and the second below). With all three given
/// they must agree. Without `fluid.peclet` nothing changes.
pub fn complete_from_peclet(fluid: &mut FluidSection, a: f64) -> Result<(), SimError> {
    let Some(pe) = fluid.peclet else {
        return Ok(());
    };
    let field = |m: String| SimError::field("fluid.peclet", m);
    if !(pe.is_finite() && pe > 0.0) {
        return Err(field(format!(
            "must be a positive finite number, got {}",
            show(pe)
        )));
    }
    if !fluid.profile.is_empty() {
        return Err(field(
            "sets homogeneous shear (with fluid.shear_rate or fluid.kT); for a profile give \
             fluid.kT instead"
                .into(),
        ));
    }
    let (eta, kt) = (fluid.eta, fluid.kt);
    match fluid.shear_rate {
        Some(gdot) if kt > 0.0 => {
            let implied = peclet_number(eta, a, gdot, kt);
            if (implied / pe - 1.0).abs() > PECLET_TOLERANCE {
                return Err(field(format!(
                    "{pe} disagrees with fluid.shear_rate = {gdot} and fluid.kT = {kt}, which \
                     give Pe = 6 pi eta a^3 gdot / kT = {implied}: give two of the three"
                )));
            }
        }
        Some(gdot) => fluid.kt = peclet_number(eta, a, gdot, 1.0) / pe,
        None if kt > 0.0 => fluid.shear_rate = Some(pe * kt / peclet_number(eta, a, 1.0, 1.0)),
        None => {
            return Err(field(
                "needs fluid.shear_rate (Pe then sets kT) or fluid.kT (Pe then sets the shear \
                 rate)"
                    .into(),
            ))
        }
    }
    Ok(())
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
            peclet: (gdot_max > 0.0).then(|| peclet_number(eta, a, gdot_max, kt)),
        }
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
        assert!((s.inertia_diffusion - 0.17).abs() < 1e-12);
        let high = ThermalScales::new(1.7e-6, 0.1, 0.1, 1.0, 9.0e-3);
        assert!((high.peclet.unwrap() / 1e4 - 1.0).abs() < 0.01);
        assert_eq!(ThermalScales::new(0.017, 0.1, 0.1, 1.0, 0.0).peclet, None);
    }

    /// Table 4.1's inertia (ratio 0.17) warns; Pe = 1e4 through kT (1.7e-6) does not; a
    /// radius 20 at Table 4.1's kT (0.0085) does not, so a scene is judged by its smallest
    /// radius, not by the one its Peclet number refers to.
    #[test]
    fn inertia_warns_by_the_smallest_radius() {
        let w = inertia_warning(0.017, 0.1, 0.1, 1.0).expect("a warning");
        assert!(w.contains("0.170") && !w.contains("  "), "{w}");
        assert!(inertia_warning(1.7e-6, 0.1, 0.1, 1.0).is_none());
        assert!(inertia_warning(0.017, 0.1, 0.1, 20.0).is_none());
        assert!(inertia_warning(0.017, 0.1, 0.1, 10.0).is_some());
    }

    /// Table 4.1's contacts (kT = 0.017, k_n = 1e4: overlap 1.3e-3 a) pass; the same kT
    /// against k_n = 100 (0.013 a) warns, and a radius 2 halves the relative overlap.
    #[test]
    fn soft_contacts_warn_against_the_thermal_energy() {
        assert!(soft_contact_warning(0.017, 1e4, 1.0).is_none());
        let w = soft_contact_warning(0.017, 100.0, 1.0).expect("a warning");
        assert!(w.contains("0.013") && !w.contains("  "), "{w}");
        assert!(soft_contact_warning(0.017, 100.0, 2.0).is_none());
    }

    fn fluid(text: &str) -> FluidSection {
        toml::from_str(text).expect("a fluid section")
    }

    /// Thesis Table 4.1 again, through `fluid.peclet`: at gdot = 9e-3 and eta = 0.1, Pe = 1
    /// needs kT = 0.017 (to the table's 1 %), and Pe = 1e4 kT = 1.7e-6; at kT = 0.017,
    /// Pe = 0.01 needs gdot = 9.0e-5.
    #[test]
    fn peclet_sets_the_thermal_energy_or_the_shear_rate() {
        let mut f = fluid("eta = 0.1\nshear_rate = 9.0e-3\npeclet = 1.0");
        complete_from_peclet(&mut f, 1.0).unwrap();
        assert!((f.kt / 0.017 - 1.0).abs() < 0.01, "{}", f.kt);
        let mut f = fluid("eta = 0.1\nshear_rate = 9.0e-3\npeclet = 1e4");
        complete_from_peclet(&mut f, 1.0).unwrap();
        assert!((f.kt / 1.7e-6 - 1.0).abs() < 0.01, "{}", f.kt);
        let mut f = fluid("eta = 0.1\nkT = 0.017\npeclet = 0.01");
        complete_from_peclet(&mut f, 1.0).unwrap();
        let gdot = f.shear_rate.unwrap();
        assert!((gdot / 9.0e-5 - 1.0).abs() < 0.01, "{gdot}");
        // The completed section is self-consistent: read back with all three, accepted.
        let s = ThermalScales::new(f.kt, f.eta, 0.1, 1.0, gdot);
        assert!((s.peclet.unwrap() / 0.01 - 1.0).abs() < 1e-12);
        complete_from_peclet(&mut f, 1.0).unwrap();
    }

    #[test]
    fn peclet_refuses_what_it_cannot_complete() {
        let refused = |text: &str, what: &str| {
            let e = complete_from_peclet(&mut fluid(text), 1.0)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("fluid.peclet") && e.contains(what) && !e.contains("  "),
                "{text}: {e}"
            );
        };
        refused("peclet = 1.0", "needs fluid.shear_rate");
        refused("peclet = -1.0\nshear_rate = 0.01", "positive");
        refused("peclet = 1.0\nprofile = \"0.1*y\"", "for a profile");
        refused("peclet = 2.0\nshear_rate = 0.01\nkT = 0.01", "disagrees");
    }
}
