//! Bands around a solved profile: where u, phi_loc and mu of the flow lie at a stated level,
//! calibrated on families the models did not see (docs/physics.md section 8).
//!
//! Each bin `k` of a solution gets a scale per observable, from the closure's own intervals
//! ([`crate::closure::Closure::interval`]) at the solved state:
//! - `phi_loc`: the half-width of the closure's phi_loc interval at the bin;
//! - `mu`: the mean of the half-widths of its mu interval at the bin's two faces (where the
//!   balance evaluates mu);
//! - `u`: the linear response of the solution to the closure's uncertainty, `|delta u_k|` with
//!   `delta x = -J^-1 (R(x; closure at its upper ends) - R(x; closure))`, `J` the Jacobian of
//!   the balance `R` at the solution, once with mu and once with phi_loc at the upper end of
//!   their intervals, added in quadrature.
//!
//! The band is `value +- m s_k`, with `m` the split-conformal margin of the scores
//! `|simulated - solved| / s` of the bins of every training scene, solved with the models
//! of the fold that held its profile family out ([`BandCalibration`], written by `suspflow
//! train` as `bands.json`). A closure without intervals (the local law) has unit scales for
//! phi_loc and mu and the forcing's largest |u_inf| for u: a band of constant width.

use std::path::{Path, PathBuf};

use nalgebra::DVector;
use schema::Observable;
use serde::{Deserialize, Serialize};
use surrogate::{check_level, conformal_quantile, physical_range};

use crate::closure::{Closure, ClosureInterval, Descriptor};
use crate::error::{Result, SolverError};
use crate::problem::ProfileProblem;
use crate::solution::ProfileSolution;

/// The observables a band is drawn around, in this order wherever three values are listed.
pub const BANDED: [Observable; 3] = [Observable::U, Observable::PhiLoc, Observable::Mu];

/// Each bin's scale of the three [`BANDED`] observables, in their units.
#[derive(Debug, Clone, PartialEq)]
pub struct BandScales {
    pub per_observable: [Vec<f64>; 3],
}

/// The bands of a solved profile at a level: lower and upper ends per [`BANDED`] observable.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileBands {
    pub level: f64,
    pub lower: [Vec<f64>; 3],
    pub upper: [Vec<f64>; 3],
}

impl ProfileBands {
    /// `value +- margin * scale` per bin and observable, clipped into phi_loc's and mu's
    /// physical ranges.
    pub fn new(
        solution: &ProfileSolution,
        scales: &BandScales,
        margins: [f64; 3],
        level: f64,
    ) -> Self {
        let ends = |sign: f64| -> [Vec<f64>; 3] {
            std::array::from_fn(|i| {
                let values = solution
                    .column(BANDED[i])
                    .expect("a solve gives u, phi_loc and mu per bin");
                let range = physical_range(BANDED[i].name());
                values
                    .iter()
                    .zip(&scales.per_observable[i])
                    .map(|(&v, &s)| {
                        let end = v + sign * margins[i] * s;
                        range.map_or(end, |r| end.clamp(r.min, r.max))
                    })
                    .collect()
            })
        };
        ProfileBands {
            level,
            lower: ends(-1.0),
            upper: ends(1.0),
        }
    }

    /// The mean of each observable's band width relative to the mean of its magnitude along
    /// the profile: `mean(upper - lower) / mean(|value|)`, one dimensionless number per
    /// [`BANDED`] observable (how `suspflow propose` ranks scenes).
    pub fn relative_widths(&self, solution: &ProfileSolution) -> [f64; 3] {
        std::array::from_fn(|i| {
            let values = solution.column(BANDED[i]).unwrap_or(&[]);
            let n = values.len().max(1) as f64;
            let width: f64 = self.upper[i]
                .iter()
                .zip(&self.lower[i])
                .map(|(u, l)| u - l)
                .sum::<f64>()
                / n;
            let scale = values.iter().map(|v| v.abs()).sum::<f64>() / n;
            width / scale.max(f64::MIN_POSITIVE)
        })
    }
}

/// The closure moved to the upper end of its interval in one output (0: phi_loc, 1: mu).
struct AtUpperEnd<'a> {
    closure: &'a dyn Closure,
    output: usize,
    level: f64,
}

impl Closure for AtUpperEnd<'_> {
    fn evaluate(&self, j: f64, descriptor: f64, phi: f64) -> Result<(f64, f64)> {
        let (phi_loc, mu) = self.closure.evaluate(j, descriptor, phi)?;
        Ok(
            match self.closure.interval(j, descriptor, phi, self.level)? {
                Some(i) if self.output == 0 => (i[0].1, mu),
                Some(i) => (phi_loc, i[1].1),
                None => (phi_loc, mu),
            },
        )
    }

    fn evaluate_output(&self, j: f64, descriptor: f64, phi: f64, output: usize) -> Result<f64> {
        if output == self.output {
            if let Some(i) = self.closure.interval(j, descriptor, phi, self.level)? {
                return Ok(i[output].1);
            }
        }
        self.closure.evaluate_output(j, descriptor, phi, output)
    }

    fn descriptor(&self) -> Descriptor<'_> {
        self.closure.descriptor()
    }
}

impl ProfileProblem {
    /// Each bin's band scales for the solution `s` of `closure` (module documentation), the
    /// closure's intervals taken at `level`.
    pub fn band_scales(
        &self,
        closure: &dyn Closure,
        s: &ProfileSolution,
        level: f64,
    ) -> Result<BandScales> {
        check_level(level)?;
        let (layout, x) = self.state_of(closure, s)?;
        let n = layout.n;
        let floor = self.floor();
        let zeros = self.zeros(closure, layout, &x);
        let half = |i: Option<ClosureInterval>, output: usize| {
            i.map(|i| 0.5 * (i[output].1 - i[output].0))
        };
        let mut phi_scale = Vec::with_capacity(n);
        let mut face_mu = Vec::with_capacity(n);
        for k in 0..n {
            let (j, second, _, _) = self.bin_state(closure, layout, &x, k, floor, &zeros);
            let Some(w) = half(closure.interval(j, second, self.phi, level)?, 0) else {
                return Ok(self.constant_scales());
            };
            phi_scale.push(w);
            let (j, second, _, _) = self.face_state(closure, layout, &x, k, floor, &zeros);
            face_mu.push(half(closure.interval(j, second, self.phi, level)?, 1).unwrap_or(0.0));
        }
        let mu_scale = (0..n)
            .map(|k| 0.5 * (face_mu[(k + n - 1) % n] + face_mu[k]))
            .collect();
        let [from_phi, from_mu] = self.responses(closure, s, level)?;
        let u_scale = from_phi
            .iter()
            .zip(&from_mu)
            .map(|(a, b)| f64::hypot(*a, *b))
            .collect();
        Ok(BandScales {
            per_observable: [u_scale, phi_scale, mu_scale],
        })
    }

    /// The linear response of the solution `s`'s bin velocities to `closure` moved to the
    /// upper end of its interval at `level`, in phi_loc and in mu in turn:
    /// `delta u = -(J^-1 (R(x; upper) - R(x)))_u` with `J` the balance's Jacobian at `s`.
    /// Zero for a closure without intervals.
    pub fn responses(
        &self,
        closure: &dyn Closure,
        s: &ProfileSolution,
        level: f64,
    ) -> Result<[Vec<f64>; 2]> {
        let (layout, x) = self.state_of(closure, s)?;
        let floor = self.floor();
        let zeros = self.zeros(closure, layout, &x);
        let base = self.evaluate(closure, layout, &x, floor, Some(&zeros))?;
        let lu = self.jacobian(closure, layout, &x, &base, floor)?.lu();
        let response = |output: usize| -> Result<Vec<f64>> {
            let moved = AtUpperEnd {
                closure,
                output,
                level,
            };
            let e = self.evaluate(&moved, layout, &x, floor, Some(&zeros))?;
            let dx = lu.solve(&(&base.r - &e.r)).ok_or_else(|| {
                SolverError::InvalidArgument(
                    "the balance's Jacobian at the solution is singular: no band".to_owned(),
                )
            })?;
            Ok(dx.rows(0, layout.n).iter().copied().collect())
        };
        Ok([response(0)?, response(1)?])
    }

    /// The state vector of solution `s` of `closure`: `u`, `ln P` and, for the nonlocal
    /// closure, `ln Theta`.
    fn state_of<'a>(
        &self,
        closure: &'a dyn Closure,
        s: &ProfileSolution,
    ) -> Result<(crate::newton::Layout<'a>, DVector<f64>)> {
        let layout = self.layout(closure);
        let n = layout.n;
        if s.u.len() != n || (layout.balance.is_some() && s.theta.len() != n) {
            return Err(SolverError::InvalidArgument(format!(
                "a solution of {} bins ({} Theta) for a problem of {n} with this closure",
                s.u.len(),
                s.theta.len()
            )));
        }
        let mut x = DVector::zeros(layout.len());
        x.rows_mut(0, n).copy_from_slice(&s.u);
        x[layout.ln_p()] = s.pressure.ln();
        if layout.balance.is_some() {
            for (k, t) in s.theta.iter().enumerate() {
                x[layout.theta(k)] = t.ln();
            }
        }
        Ok((layout, x))
    }

    /// The scales of a closure without intervals: the forcing's largest |u_inf| for u, 1 for
    /// phi_loc and mu.
    fn constant_scales(&self) -> BandScales {
        let n = self.n_bins();
        let u_max = self.u_inf.iter().fold(0.0, |a: f64, &b| a.max(b.abs()));
        BandScales {
            per_observable: [vec![u_max; n], vec![1.0; n], vec![1.0; n]],
        }
    }
}

/// How the bands of one closure were calibrated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClosureBands {
    /// The closure's name (`learned`, `local`, `nonlocal`, `extremum`).
    pub closure: String,
    /// Per [`BANDED`] observable, every calibration bin's score `|simulated - solved| / s`,
    /// ascending.
    pub scores: [Vec<f64>; 3],
    /// Scenes solved and left out because the solve stalled.
    pub scenes: usize,
    pub failed: usize,
    /// At 90 %, per [`BANDED`] observable: the fraction of the calibration bins inside the
    /// band that the other families' scores give them (cross-conformal), and the mean band
    /// width relative to the mean |value| of each scene, averaged over scenes.
    pub fold_coverage: [f64; 3],
    pub fold_relative_width: [f64; 3],
}

/// The calibration of the bands of every closure: `<models>/bands.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BandCalibration {
    /// The training data (FNV-1a 64 hash) the models and the folds came from.
    pub training_fnv1a_64: schema::Fingerprint,
    /// The hyper-parameters of each mapping's models (the shipped ones and the folds'):
    /// bands calibrated with other models are refused.
    pub models: Vec<(String, surrogate::HyperParameters)>,
    /// What each fold held out and how many there were.
    pub held_out: String,
    pub folds: usize,
    pub closures: Vec<ClosureBands>,
    pub code_version: String,
}

impl BandCalibration {
    /// `<dir>/bands.json`.
    pub fn path(dir: &Path) -> PathBuf {
        dir.join("bands.json")
    }

    /// Writes `<dir>/bands.json`.
    pub fn save(&self, dir: &Path) -> Result<()> {
        let path = Self::path(dir);
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| SolverError::InvalidArgument(e.to_string()))?;
        std::fs::write(&path, text + "\n")
            .map_err(|e| SolverError::InvalidArgument(format!("writing {}: {e}", path.display())))
    }

    /// Reads `<dir>/bands.json`, or `None` when there is none.
    pub fn load(dir: &Path) -> Result<Option<Self>> {
        let path = Self::path(dir);
        let text = match std::fs::read_to_string(&path) {
            Ok(text) => text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => {
                return Err(SolverError::InvalidArgument(format!(
                    "reading {}: {e}",
                    path.display()
                )))
            }
        };
        serde_json::from_str(&text).map(Some).map_err(|e| {
            SolverError::InvalidArgument(format!(
                "{} is not a band calibration: {e}",
                path.display()
            ))
        })
    }

    /// Why these bands do not belong to the model `meta` of the closure's mapping, if they do
    /// not: another training table or other hyper-parameters.
    pub fn mismatch(&self, meta: &surrogate::ModelMeta) -> Option<String> {
        let params = self
            .models
            .iter()
            .find(|(m, _)| *m == meta.mapping)
            .map(|(_, p)| p);
        if meta.training_data.fnv1a_64 != self.training_fnv1a_64 {
            Some(format!(
                "the bands were calibrated on data {}, model `{}` was trained on {}",
                self.training_fnv1a_64, meta.mapping, meta.training_data.fnv1a_64
            ))
        } else if params != Some(&meta.hyper_parameters) {
            Some(format!(
                "the bands were calibrated with other hyper-parameters of `{}` than its model's",
                meta.mapping
            ))
        } else {
            None
        }
    }

    /// The margins at `level` of closure `name`'s bands, per [`BANDED`] observable; `None`
    /// when the calibration has no scores for it.
    pub fn margins(&self, name: &str, level: f64) -> Result<Option<[f64; 3]>> {
        check_level(level)?;
        Ok(self
            .closures
            .iter()
            .find(|c| c.closure == name)
            .map(|c| std::array::from_fn(|i| conformal_quantile(&c.scores[i], level))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_are_value_plus_minus_margin_times_scale_clipped_to_the_physical_range() {
        let s = ProfileSolution {
            u: vec![0.1, -0.1],
            phi_loc: vec![0.5, 0.6],
            mu: vec![0.02, 0.4],
            ..ProfileSolution::default()
        };
        let scales = BandScales {
            per_observable: [vec![0.01, 0.02], vec![0.1, 0.1], vec![0.05, 0.1]],
        };
        let b = ProfileBands::new(&s, &scales, [2.0, 1.0, 1.0], 0.9);
        assert_eq!(b.lower[0], vec![0.1 - 0.02, -0.1 - 0.04]);
        assert_eq!(b.upper[1], vec![0.6, 0.7]);
        // mu's band stops at 0.
        assert_eq!(b.lower[2], vec![0.0, 0.30000000000000004]);
        let widths = b.relative_widths(&s);
        assert!((widths[0] - 0.06 / 0.1).abs() < 1e-12, "{widths:?}");
    }
}
