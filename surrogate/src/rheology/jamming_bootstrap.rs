//! How far the points' own errors move the jamming law: a parametric bootstrap.
//!
//! The seeds' spread ([`crate::rheology::flow_curve_fit::SeededJammingFit`]) misses an
//! error that every seed shares, such as that of the Green-Kubo Brownian viscosity, which
//! is measured once per volume fraction and added to every seed's hydrodynamic viscosity.
//! Here each draw puts every point at `eta_r + se z` (`z` standard normal, independent
//! between points) and fits [`JammingLaw`] again; the quantiles of the fitted `phi_J` and
//! `lambda` over the draws, and the share of draws the law cannot fit (mostly points that
//! do not diverge below the search's edge), say what the points can and cannot decide.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::error::{Result, SurrogateError};
use crate::rheology::jamming_law::JammingLaw;

/// One point of a flow curve with its error: realised `phi`, `eta_r` and its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointWithError {
    pub phi: f64,
    pub eta_r: f64,
    pub se: f64,
}

/// The 16th, 50th and 84th percentiles of a fitted parameter over the draws that fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quantiles {
    pub p16: f64,
    pub median: f64,
    pub p84: f64,
}

/// The parametric bootstrap of the jamming law.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JammingBootstrap {
    pub draws: usize,
    /// Draws the law could be fitted to.
    pub fitted: usize,
    /// `None` when no draw could be fitted.
    pub phi_j: Option<Quantiles>,
    pub lambda: Option<Quantiles>,
    /// The fitted `phi_J` of every draw that fit, ascending.
    #[serde(skip)]
    phi_j_fitted: Vec<f64>,
}

impl JammingBootstrap {
    /// `draws` (>= 1) refits of the law to `points` moved within their errors, seeded by
    /// `seed`; a draw that puts a point at `eta_r <= 1` or that the law cannot fit counts as
    /// not fitted.
    pub fn run(points: &[PointWithError], draws: usize, seed: u64) -> Result<Self> {
        if draws == 0 {
            return Err(SurrogateError::InvalidArgument(
                "a bootstrap of the jamming law needs at least one draw".to_owned(),
            ));
        }
        if let Some(p) = points.iter().find(|p| !(p.se >= 0.0 && p.se.is_finite())) {
            return Err(SurrogateError::InvalidArgument(format!(
                "the point at phi = {} has no usable standard error ({})",
                p.phi, p.se
            )));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let phi: Vec<f64> = points.iter().map(|p| p.phi).collect();
        let (mut phi_j, mut lambda) = (Vec::new(), Vec::new());
        for _ in 0..draws {
            let eta: Vec<f64> = points
                .iter()
                .map(|p| p.eta_r + p.se * standard_normal(&mut rng))
                .collect();
            if let Ok(law) = JammingLaw::fit(&phi, &eta) {
                phi_j.push(law.phi_j);
                lambda.push(law.lambda);
            }
        }
        phi_j.sort_by(f64::total_cmp);
        Ok(JammingBootstrap {
            draws,
            fitted: phi_j.len(),
            phi_j: quantiles(phi_j.clone()),
            lambda: quantiles(lambda),
            phi_j_fitted: phi_j,
        })
    }

    /// The share of all draws (fitted or not) whose fitted `phi_J` is at most `phi_j`.
    pub fn share_at_most(&self, phi_j: f64) -> f64 {
        self.phi_j_fitted.partition_point(|&p| p <= phi_j) as f64 / self.draws as f64
    }
}

/// A standard normal deviate (Box-Muller, the cosine branch; `1 - u` keeps the logarithm
/// finite).
fn standard_normal(rng: &mut impl Rng) -> f64 {
    let (u1, u2): (f64, f64) = (rng.gen(), rng.gen());
    (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The 16th, 50th and 84th percentiles of `values` (nearest rank), `None` when empty.
fn quantiles(mut values: Vec<f64>) -> Option<Quantiles> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let at = |q: f64| values[((q * values.len() as f64) as usize).min(values.len() - 1)];
    Some(Quantiles {
        p16: at(0.16),
        median: at(0.5),
        p84: at(0.84),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on_law(law: JammingLaw, relative_se: f64) -> Vec<PointWithError> {
        [0.45, 0.50, 0.55, 0.58]
            .iter()
            .map(|&phi| {
                let eta_r = law.eta_r(phi);
                PointWithError {
                    phi,
                    eta_r,
                    se: relative_se * eta_r,
                }
            })
            .collect()
    }

    #[test]
    fn exact_points_give_the_law_and_errors_widen_its_range() {
        let law = JammingLaw {
            phi_j: 0.62,
            lambda: 1.8,
        };
        let exact = JammingBootstrap::run(&on_law(law, 0.0), 20, 1).unwrap();
        assert_eq!(exact.fitted, 20);
        let q = exact.phi_j.unwrap();
        assert_eq!(
            (exact.share_at_most(0.619), exact.share_at_most(0.621)),
            (0.0, 1.0)
        );
        assert!(
            (q.median - 0.62).abs() < 1e-4 && q.p84 - q.p16 < 1e-6,
            "{q:?}"
        );
        // 5 % per point: the median stays near the law, the range opens but stays narrow;
        // 30 %: wider still. 400 draws put the 16th and 84th percentiles within about 0.05
        // standard deviations of their limits, far below the factors tested.
        let ranges: Vec<f64> = [0.05, 0.3]
            .iter()
            .map(|&r| {
                let b = JammingBootstrap::run(&on_law(law, r), 400, 2).unwrap();
                let q = b.phi_j.unwrap();
                assert!((q.median - 0.62).abs() < 0.01, "{r}: {q:?}");
                q.p84 - q.p16
            })
            .collect();
        assert!(
            ranges[0] > 1e-3 && ranges[1] > 2.0 * ranges[0],
            "{ranges:?}"
        );
    }

    #[test]
    fn draws_that_cannot_diverge_are_counted_not_fitted() {
        // A flat curve (eta_r 3 at every phi) has no divergence below the search's edge.
        let flat: Vec<PointWithError> = [0.45, 0.50, 0.55]
            .iter()
            .map(|&phi| PointWithError {
                phi,
                eta_r: 3.0,
                se: 0.01,
            })
            .collect();
        let b = JammingBootstrap::run(&flat, 50, 3).unwrap();
        assert!(b.fitted < 50, "{b:?}");
        // The share counts the unfitted draws in its denominator.
        assert_eq!(b.share_at_most(1.0), b.fitted as f64 / 50.0);
        assert!(JammingBootstrap::run(&flat, 0, 3).is_err());
        let mut bad = flat.clone();
        bad[0].se = f64::NAN;
        assert!(JammingBootstrap::run(&bad, 5, 3).is_err());
    }

    #[test]
    fn the_deviates_have_unit_variance() {
        // 20000 deviates: the sample variance's standard error is sqrt(2 / n) = 0.01, so
        // 0.04 is four of them; the mean's is 0.007.
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let z: Vec<f64> = (0..20000).map(|_| standard_normal(&mut rng)).collect();
        let mean = z.iter().sum::<f64>() / z.len() as f64;
        let var = z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (z.len() - 1) as f64;
        assert!(
            mean.abs() < 0.03 && (var - 1.0).abs() < 0.04,
            "{mean} {var}"
        );
    }
}
