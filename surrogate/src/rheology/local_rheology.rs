//! The physics backbone of the surrogate: a local rheology fitted on the training rows, which
//! the trees then correct (they learn the residual), so that a prediction outside the
//! training range follows the constitutive law instead of the trees' flat edge.
//!
//! Two laws of the local state, both of the local viscous number `J = eta |gdot| / P`:
//! - flow curve `mu(J) = A J^b`: the power-law branch of a frictionless dense suspension
//!   (the macroscopic friction grows sub-linearly with J). A yield term `mu_c > 0` is left
//!   out on purpose: in these inhomogeneous flows the bins at a velocity extremum have
//!   `mu -> 0` as `J -> 0` (the shear stress changes sign there), which a yield term cannot
//!   follow;
//! - jamming law, thesis eq 6.7: `J / mu = alpha (phi_J - phi_loc)^2`, i.e.
//!   `phi_loc = phi_J - sqrt(J / (alpha mu))`, evaluated with the flow curve's `mu(J)`.
//!
//! Fitting: `b` minimises the squared error of `mu` over `[B_MIN, B_MAX]` (Brent's method,
//! `argmin`), with `A` the least-squares prefactor for each `b`; `phi_J` and `alpha` come from
//! the straight line of `phi_loc` against `sqrt(J / mu)` (measured `mu`), whose intercept is
//! `phi_J` and slope `-1 / sqrt(alpha)`. Rows with `J <= 0` or `mu <= 0` carry no
//! information on a power law and are left out of the fit.

use schema::columns as col;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SurrogateError};
use crate::rheology::brent;

/// Smallest and largest flow-curve exponent searched.
const B_MIN: f64 = 0.01;
const B_MAX: f64 = 3.0;

/// Fitted local rheology: `mu(J) = A J^b`, `phi_loc(J) = phi_J - sqrt(J / (alpha mu(J)))`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LocalRheology {
    /// `A`, the flow curve's prefactor.
    pub mu_prefactor: f64,
    /// `b`, the flow curve's exponent.
    pub mu_exponent: f64,
    /// `phi_J`, the jamming volume fraction of eq 6.7.
    pub phi_j: f64,
    /// `alpha` of eq 6.7.
    pub alpha: f64,
}

/// Squared error of `mu = A J^b` over `b`, with the best `A` for each `b`.
struct FlowCurveCost<'a> {
    j: &'a [f64],
    mu: &'a [f64],
}

impl FlowCurveCost<'_> {
    /// The least-squares prefactor for exponent `b`.
    fn prefactor(&self, b: f64) -> f64 {
        let (num, den) = self
            .j
            .iter()
            .zip(self.mu)
            .fold((0.0, 0.0), |(n, d), (&j, &m)| {
                let x = j.powf(b);
                (n + m * x, d + x * x)
            });
        num / den
    }

    /// The squared error of `mu` with exponent `b` and its best prefactor.
    fn cost(&self, b: f64) -> f64 {
        let a = self.prefactor(b);
        self.j
            .iter()
            .zip(self.mu)
            .map(|(&j, &m)| (m - a * j.powf(b)).powi(2))
            .sum()
    }
}

impl LocalRheology {
    /// Fits both laws on rows of `(J, phi_loc, mu)`.
    pub fn fit(j: &[f64], phi_loc: &[f64], mu: &[f64]) -> Result<Self> {
        let rows: Vec<usize> = (0..j.len())
            .filter(|&i| j[i] > 0.0 && mu[i] > 0.0)
            .collect();
        if rows.len() < 3 {
            return Err(SurrogateError::InvalidArgument(format!(
                "the local-rheology backbone needs at least 3 rows with J > 0 and mu > 0, found {}",
                rows.len()
            )));
        }
        let pick = |v: &[f64]| -> Vec<f64> { rows.iter().map(|&i| v[i]).collect() };
        let (j, phi_loc, mu) = (pick(j), pick(phi_loc), pick(mu));
        let cost = FlowCurveCost { j: &j, mu: &mu };
        let mu_exponent = brent::minimise(
            |b| cost.cost(b),
            B_MIN,
            B_MAX,
            "fitting the flow curve mu(J)",
        )?;
        let mu_prefactor = cost.prefactor(mu_exponent);
        let x: Vec<f64> = j.iter().zip(&mu).map(|(j, m)| (j / m).sqrt()).collect();
        let (intercept, slope) = straight_line(&x, &phi_loc);
        if slope.is_nan() || slope >= 0.0 {
            return Err(SurrogateError::InvalidArgument(format!(
                "phi_loc does not fall with sqrt(J / mu) in these rows (slope {slope:.3e}): \
                 the jamming law (eq 6.7) does not describe them"
            )));
        }
        let law = LocalRheology {
            mu_prefactor,
            mu_exponent,
            phi_j: intercept,
            alpha: 1.0 / (slope * slope),
        };
        law.check().map_err(|m| {
            SurrogateError::InvalidArgument(format!("{m}: eq 6.7 does not describe these rows"))
        })?;
        Ok(law)
    }

    /// `Err(what is wrong)` unless the law is one of a flowing suspension: `A > 0`, `b` in
    /// the searched `[B_MIN, B_MAX]`, `0 < phi_J <= PHI_LOC_MAX` (no packing is denser) and
    /// `alpha > 0`, all finite.
    pub fn check(&self) -> std::result::Result<(), String> {
        let LocalRheology {
            mu_prefactor,
            mu_exponent,
            phi_j,
            alpha,
        } = *self;
        let max = crate::data::physical_range::PHI_LOC_MAX;
        let problem = if !(mu_prefactor.is_finite() && mu_prefactor > 0.0) {
            format!("flow-curve prefactor A = {mu_prefactor}, not positive")
        } else if !(B_MIN..=B_MAX).contains(&mu_exponent) {
            format!("flow-curve exponent b = {mu_exponent}, outside [{B_MIN}, {B_MAX}]")
        } else if !(phi_j > 0.0 && phi_j <= max) {
            format!("phi_J = {phi_j} (eq 6.7), outside (0, {max}]")
        } else if !(alpha.is_finite() && alpha > 0.0) {
            format!("alpha = {alpha} (eq 6.7), not positive")
        } else {
            return Ok(());
        };
        Err(format!("the local-rheology backbone has {problem}"))
    }

    /// `mu(J) = A J^b` (0 for `J <= 0`).
    pub fn mu(&self, j: f64) -> f64 {
        if j > 0.0 {
            self.mu_prefactor * j.powf(self.mu_exponent)
        } else {
            0.0
        }
    }

    /// `phi_loc(J) = phi_J - sqrt(J / (alpha mu(J)))` (eq 6.7; `phi_J` for `J <= 0`).
    pub fn phi_loc(&self, j: f64) -> f64 {
        let mu = self.mu(j);
        if mu > 0.0 {
            self.phi_j - (j / (self.alpha * mu)).sqrt()
        } else {
            self.phi_j
        }
    }

    /// The law's value of output `name` (`mu` or `phi_loc`) at `J`.
    pub fn output(&self, name: &str, j: f64) -> Result<f64> {
        match name {
            col::MU => Ok(self.mu(j)),
            col::PHI_LOC => Ok(self.phi_loc(j)),
            other => Err(SurrogateError::InvalidArgument(format!(
                "the local-rheology backbone predicts mu and phi_loc, not `{other}`"
            ))),
        }
    }
}

/// Least-squares straight line `y = intercept + slope x`.
fn straight_line(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (sxy, sxx) = x.iter().zip(y).fold((0.0, 0.0), |(sxy, sxx), (&a, &b)| {
        (sxy + (a - mx) * (b - my), sxx + (a - mx) * (a - mx))
    });
    let slope = sxy / sxx;
    (my - slope * mx, slope)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_the_laws_it_was_given() {
        let truth = LocalRheology {
            mu_prefactor: 3.6,
            mu_exponent: 0.44,
            phi_j: 0.66,
            alpha: 2.0,
        };
        let j: Vec<f64> = (0..60).map(|k| 1e-4 * 1.15f64.powi(k)).collect();
        let mu: Vec<f64> = j.iter().map(|&j| truth.mu(j)).collect();
        let phi_loc: Vec<f64> = j.iter().map(|&j| truth.phi_loc(j)).collect();
        let fit = LocalRheology::fit(&j, &phi_loc, &mu).unwrap();
        for (got, want) in [
            (fit.mu_prefactor, truth.mu_prefactor),
            (fit.mu_exponent, truth.mu_exponent),
            (fit.phi_j, truth.phi_j),
            (fit.alpha, truth.alpha),
        ] {
            assert!((got - want).abs() < 1e-4 * want, "{fit:?}");
        }
    }

    #[test]
    fn impossible_laws_are_named() {
        let good = LocalRheology {
            mu_prefactor: 2.6,
            mu_exponent: 0.38,
            phi_j: 0.65,
            alpha: 4.5,
        };
        assert!(good.check().is_ok());
        for (law, expected) in [
            (
                LocalRheology {
                    phi_j: -5.0,
                    ..good
                },
                "phi_J = -5",
            ),
            (LocalRheology { phi_j: 0.9, ..good }, "phi_J = 0.9"),
            (
                LocalRheology {
                    mu_prefactor: 0.0,
                    ..good
                },
                "prefactor A = 0",
            ),
            (
                LocalRheology {
                    mu_exponent: 7.0,
                    ..good
                },
                "exponent b = 7",
            ),
            (
                LocalRheology {
                    alpha: f64::NAN,
                    ..good
                },
                "alpha = NaN",
            ),
        ] {
            let err = law.check().unwrap_err();
            assert!(err.contains(expected), "{err}");
        }
    }

    #[test]
    fn refuses_data_without_a_jamming_law() {
        let j = [0.01, 0.02, 0.04, 0.08];
        let mu = [0.5, 0.6, 0.7, 0.8];
        let rising = [0.50, 0.52, 0.54, 0.56];
        let err = LocalRheology::fit(&j, &rising, &mu).unwrap_err();
        assert!(err.to_string().contains("eq 6.7"), "{err}");
        let err = LocalRheology::fit(&[0.0, 0.0, 0.01], &rising[..3], &mu[..3]).unwrap_err();
        assert!(err.to_string().contains("at least 3 rows"), "{err}");
    }
}
