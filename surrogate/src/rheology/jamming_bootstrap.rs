//! How far the points' own errors move the jamming law: a parametric bootstrap.
//!
//! The seeds' spread ([`crate::rheology::flow_curve_fit::SeededJammingFit`]) misses an
//! error that every seed shares, such as that of the Green-Kubo Brownian viscosity, which
//! is measured once per volume fraction and added to every seed's hydrodynamic viscosity.
//! Here each draw puts every point at `eta_r + se z` (`z` standard normal, independent
//! between points) and fits [`JammingLaw`] again; the quantiles of the fitted `phi_J` and
//! `lambda` over the draws say what the points can and cannot decide. A draw whose points
//! do not diverge below the search's edge
//! ([`PHI_J_MAX`](crate::rheology::jamming_law::PHI_J_MAX)) counts as `phi_J` beyond it, so
//! the quantiles of `phi_J` are over all draws and can lie beyond the edge; `lambda` is
//! only defined for the draws that diverge.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::error::{Result, SurrogateError};
use crate::rheology::jamming_law::JammingLaw;
use crate::rheology::statistics::nearest_rank_quantile;

/// One point of a flow curve with its error: realised `phi`, `eta_r` and its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointWithError {
    pub phi: f64,
    pub eta_r: f64,
    pub se: f64,
}

/// The 16th, 50th and 84th percentiles (nearest rank) of a parameter over the draws;
/// infinite for `phi_J` beyond the search's edge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quantiles {
    pub p16: f64,
    pub median: f64,
    pub p84: f64,
}

impl Quantiles {
    fn of(sorted: &[f64]) -> Option<Quantiles> {
        Some(Quantiles {
            p16: nearest_rank_quantile(sorted, 0.16)?,
            median: nearest_rank_quantile(sorted, 0.5)?,
            p84: nearest_rank_quantile(sorted, 0.84)?,
        })
    }
}

/// The parametric bootstrap of the jamming law.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JammingBootstrap {
    pub draws: usize,
    /// Draws whose points diverge below [`PHI_J_MAX`](crate::rheology::jamming_law::PHI_J_MAX).
    pub diverging: usize,
    /// Draws whose points do not ([`JammingLaw::at_edge`]).
    pub beyond_edge: usize,
    /// Draws the law cannot be fitted to at all (a point drawn at `eta_r <= 1`).
    pub invalid: usize,
    /// Over the diverging and beyond-edge draws, the latter at infinity; `None` without any.
    pub phi_j: Option<Quantiles>,
    /// Over the diverging draws; `None` without any.
    pub lambda: Option<Quantiles>,
    /// The `phi_J` of the diverging draws, ascending.
    #[serde(skip)]
    phi_j_diverging: Vec<f64>,
}

impl JammingBootstrap {
    /// `draws` (>= 1) refits of the law to `points` (finite, `se >= 0`) moved within their
    /// errors, seeded by `seed`.
    pub fn run(points: &[PointWithError], draws: usize, seed: u64) -> Result<Self> {
        if draws == 0 {
            return Err(SurrogateError::InvalidArgument(
                "a bootstrap of the jamming law needs at least one draw".to_owned(),
            ));
        }
        if let Some(p) = points.iter().find(|p| {
            !(p.phi.is_finite() && p.eta_r.is_finite() && p.se.is_finite() && p.se >= 0.0)
        }) {
            return Err(SurrogateError::InvalidArgument(format!(
                "cannot draw the point eta_r = {} ± {} at phi = {}: each needs a finite value \
                 and a finite, non-negative standard error",
                p.eta_r, p.se, p.phi
            )));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let phi: Vec<f64> = points.iter().map(|p| p.phi).collect();
        let (mut phi_j, mut lambda) = (Vec::new(), Vec::new());
        let (mut beyond_edge, mut invalid) = (0, 0);
        for _ in 0..draws {
            let eta: Vec<f64> = points
                .iter()
                .map(|p| p.eta_r + p.se * standard_normal(&mut rng))
                .collect();
            match JammingLaw::fit_to_edge(&phi, &eta) {
                Ok(law) if law.at_edge() => beyond_edge += 1,
                Ok(law) => {
                    phi_j.push(law.phi_j);
                    lambda.push(law.lambda);
                }
                Err(_) => invalid += 1,
            }
        }
        phi_j.sort_by(f64::total_cmp);
        lambda.sort_by(f64::total_cmp);
        let with_edge: Vec<f64> = phi_j
            .iter()
            .copied()
            .chain(std::iter::repeat_n(f64::INFINITY, beyond_edge))
            .collect();
        Ok(JammingBootstrap {
            draws,
            diverging: phi_j.len(),
            beyond_edge,
            invalid,
            phi_j: Quantiles::of(&with_edge),
            lambda: Quantiles::of(&lambda),
            phi_j_diverging: phi_j,
        })
    }

    /// The share of all draws whose points diverge at `phi_J <= phi_j`.
    pub fn share_at_most(&self, phi_j: f64) -> f64 {
        self.phi_j_diverging.partition_point(|&p| p <= phi_j) as f64 / self.draws as f64
    }
}

/// A standard normal deviate (Box-Muller, the cosine branch; `1 - u` keeps the logarithm
/// finite).
fn standard_normal(rng: &mut impl Rng) -> f64 {
    let (u1, u2): (f64, f64) = (rng.gen(), rng.gen());
    (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
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
        assert_eq!(
            (exact.diverging, exact.beyond_edge, exact.invalid),
            (20, 0, 0)
        );
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
    fn draws_that_cannot_diverge_are_counted_beyond_the_edge() {
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
        assert_eq!(b.diverging + b.beyond_edge + b.invalid, 50);
        // The share counts the other draws in its denominator, and the quantiles of phi_J
        // put them beyond the edge.
        assert_eq!(b.share_at_most(1.0), b.diverging as f64 / 50.0);
        // About half the draws fall with phi somewhere, more than the 16 % that put the
        // 84th percentile beyond the edge.
        assert!(b.beyond_edge > 8, "{b:?}");
        assert_eq!(b.phi_j.unwrap().p84, f64::INFINITY, "{b:?}");
        assert!(JammingBootstrap::run(&flat, 0, 3).is_err());
        for (k, value) in [(0, f64::NAN), (1, -0.1)] {
            let mut bad = flat.clone();
            bad[0].se = value;
            assert!(JammingBootstrap::run(&bad, 5, 3).is_err(), "se {k}");
        }
        let mut bad = flat.clone();
        bad[1].eta_r = f64::NAN;
        let e = JammingBootstrap::run(&bad, 5, 3).unwrap_err().to_string();
        assert!(e.contains("finite value"), "{e}");
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
