//! The divergence of the relative viscosity at jamming in homogeneous shear (thesis section
//! 4.2.6; docs/physics.md section 10): `eta_r = (1 - phi/phi_J)^(-lambda)`, and its
//! least-squares fit to measured `(phi, eta_r)`.
//!
//! The fit minimises the squared error of `ln eta_r` (the points span a decade or more, so
//! relative errors weigh them evenly). For a given `phi_J` the best `lambda` is linear
//! least squares through the origin, `lambda = -sum(x y) / sum(x^2)` with
//! `x = ln(1 - phi/phi_J)`, `y = ln eta_r`; `phi_J` itself minimises the remaining error
//! over `(max phi, PHI_J_MAX)` by Brent's method (`argmin`).
use crate::error::{Result, SurrogateError};
use crate::rheology::brent;

/// The seeds' values at high Peclet number (thesis section 4.2.6).
pub const SEEDS_LAW: JammingLaw = JammingLaw {
    phi_j: 0.642,
    lambda: 1.5,
};

/// The seeds' jamming fraction at Pe -> 0 (paper Fig. 6a, thesis Fig. 4.9a): their
/// hydrodynamic viscosity plus the Green-Kubo Brownian one.
pub const SEEDS_LOW_PECLET_PHI_J: f64 = 0.587;

/// Largest `phi_J` searched: random close packing of bidisperse spheres lies below it.
pub const PHI_J_MAX: f64 = 0.74;
/// A fitted `phi_J` this close to [`PHI_J_MAX`] is the search's edge, not a minimum: the
/// points show no divergence below it.
const PHI_J_EDGE: f64 = 1e-3;
/// Distinct volume fractions the fit of the law's two parameters needs.
pub const MIN_VOLUME_FRACTIONS: usize = 3;

/// `eta_r = (1 - phi/phi_J)^(-lambda)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JammingLaw {
    pub phi_j: f64,
    pub lambda: f64,
}

/// Squared error of `ln eta_r` over `phi_J`, with the best `lambda` for each.
struct LogError<'a> {
    phi: &'a [f64],
    ln_eta: &'a [f64],
}

impl LogError<'_> {
    fn lambda(&self, phi_j: f64) -> f64 {
        let (xy, xx) = self
            .phi
            .iter()
            .zip(self.ln_eta)
            .fold((0.0, 0.0), |(xy, xx), (p, y)| {
                let x = (1.0 - p / phi_j).ln();
                (xy + x * y, xx + x * x)
            });
        -xy / xx
    }

    /// The squared error of `ln eta_r` at `phi_j` with its best `lambda`.
    fn cost(&self, phi_j: f64) -> f64 {
        let lambda = self.lambda(phi_j);
        self.phi
            .iter()
            .zip(self.ln_eta)
            .map(|(p, y)| (y + lambda * (1.0 - p / phi_j).ln()).powi(2))
            .sum()
    }
}

impl JammingLaw {
    /// The relative viscosity at `phi` (infinite at and beyond `phi_J`).
    pub fn eta_r(&self, phi: f64) -> f64 {
        if phi < self.phi_j {
            (1.0 - phi / self.phi_j).powf(-self.lambda)
        } else {
            f64::INFINITY
        }
    }

    /// Least-squares fit (see the module notes) to at least three points with distinct
    /// `phi` in (0, PHI_J_MAX) and `eta_r > 1`; an error where the best `phi_J` is the
    /// search's upper edge (points that do not rise like a divergence below it, e.g. a
    /// viscosity that falls with `phi` between two of them).
    pub fn fit(phi: &[f64], eta_r: &[f64]) -> Result<JammingLaw> {
        let law = Self::fit_to_edge(phi, eta_r)?;
        if law.at_edge() {
            let points: Vec<String> = phi
                .iter()
                .zip(eta_r)
                .map(|(phi, eta_r)| format!("{eta_r:.2} at {phi:.3}"))
                .collect();
            return Err(SurrogateError::InvalidArgument(format!(
                "phi_J runs to the edge of its search ({PHI_J_MAX}): eta_r = {} does not \
                 diverge below it",
                points.join(", ")
            )));
        }
        Ok(law)
    }

    /// Whether `phi_J` is the search's upper edge rather than a minimum: the points it was
    /// fitted to do not diverge below [`PHI_J_MAX`].
    pub fn at_edge(&self) -> bool {
        self.phi_j > PHI_J_MAX - PHI_J_EDGE
    }

    /// [`JammingLaw::fit`] without refusing a `phi_J` at the search's edge
    /// ([`JammingLaw::at_edge`] tells).
    pub fn fit_to_edge(phi: &[f64], eta_r: &[f64]) -> Result<JammingLaw> {
        if let Some(k) =
            (0..phi.len()).find(|&k| !(phi[k] > 0.0 && phi[k] < PHI_J_MAX && eta_r[k] > 1.0))
        {
            return Err(SurrogateError::InvalidArgument(format!(
                "cannot fit the jamming law to phi = {}, eta_r = {}: needs 0 < phi < {PHI_J_MAX} and eta_r > 1",
                phi[k],
                eta_r[k]
            )));
        }
        let phi_top = phi.iter().cloned().fold(0.0, f64::max);
        let mut distinct = phi.to_vec();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        if distinct.len() < MIN_VOLUME_FRACTIONS {
            return Err(SurrogateError::InvalidArgument(format!(
                "the jamming law needs points at {MIN_VOLUME_FRACTIONS} or more volume fractions, got {phi:?}"
            )));
        }
        let ln_eta: Vec<f64> = eta_r.iter().map(|e| e.ln()).collect();
        let cost = LogError {
            phi,
            ln_eta: &ln_eta,
        };
        let lower = phi_top + 1e-6 * (PHI_J_MAX - phi_top);
        let phi_j = brent::minimise(
            |phi_j| cost.cost(phi_j),
            lower,
            PHI_J_MAX,
            "fitting phi_J of the jamming law",
        )?;
        Ok(JammingLaw {
            phi_j,
            lambda: cost.lambda(phi_j),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_the_law_from_exact_points_and_from_noisy_ones() {
        let truth = JammingLaw {
            phi_j: 0.63,
            lambda: 1.7,
        };
        let phi: Vec<f64> = (0..8).map(|k| 0.45 + 0.02 * k as f64).collect();
        let exact: Vec<f64> = phi.iter().map(|&p| truth.eta_r(p)).collect();
        let fit = JammingLaw::fit(&phi, &exact).unwrap();
        assert!(
            (fit.phi_j - 0.63).abs() < 1e-5 && (fit.lambda - 1.7).abs() < 1e-3,
            "{fit:?}"
        );
        // +-3 % alternating noise moves the fit only a little.
        let noisy: Vec<f64> = exact
            .iter()
            .enumerate()
            .map(|(k, e)| e * if k % 2 == 0 { 1.03 } else { 0.97 })
            .collect();
        let fit = JammingLaw::fit(&phi, &noisy).unwrap();
        assert!(
            (fit.phi_j - 0.63).abs() < 0.01 && (fit.lambda - 1.7).abs() < 0.2,
            "{fit:?}"
        );
    }

    #[test]
    fn refuses_points_it_cannot_fit() {
        assert!(JammingLaw::fit(&[0.5, 0.5, 0.5], &[10.0, 11.0, 12.0]).is_err());
        let message = JammingLaw::fit(&[0.4, 0.5, 0.55], &[3.0, 0.5, 12.0])
            .unwrap_err()
            .to_string();
        assert!(message.contains("eta_r = 0.5"), "{message}");
        // A viscosity flat between the two lower volume fractions (the Green-Kubo estimate
        // of reports/brownian at phi 0.45 and 0.50) has its least-squares phi_J at the
        // search's edge: refused, not reported as 0.74.
        let message = JammingLaw::fit(&[0.45, 0.5, 0.55], &[11.95, 12.5, 30.4])
            .unwrap_err()
            .to_string();
        assert!(message.contains("edge of its search"), "{message}");
        assert!(message.contains("12.50 at 0.500"), "{message}");
    }
}
