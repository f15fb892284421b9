//! Calibrating a mapping's intervals ([`crate::models::intervals`]) on rows its models did not
//! see, and measuring how well intervals made three ways cover rows of held-out families.
//!
//! The folds are those of tuning ([`tuning_folds`]): one per profile family when the data
//! hold at least three, else one per simulation. Each fold's model and quantile trees are
//! fitted on its training rows with the model's hyper-parameters and predict its held-out
//! rows; every training row thus gets one out-of-fold prediction and conformity score, and
//! those scores calibrate the shipped model's intervals.
//!
//! The coverage a user can expect on a new family is measured by cross-conformal prediction:
//! the held-out rows of fold `f` get the margin of the scores of every other fold, so that a
//! family's own rows never widen or narrow its intervals. Three methods, on the same fold
//! fits ([`IntervalMethod`]):
//! - conformalised quantile trees with the targets' noise apart (the shipped method,
//!   [`crate::models::intervals`]): each row's interval is that of a target with the row's
//!   own standard error (`<output>_se`);
//! - the same blind to the noise (CQR as published): `[lower - m, upper + m]`;
//! - constant conformal: `y_hat +- m` with `m` from the absolute residuals;
//! - the quantile trees as fitted, `[lower, upper]`, without a margin.
//!
//! Beside coverage and mean width, the interval score (Gneiting & Raftery, JASA 102, 359
//! (2007), eq 43) `(upper - lower) + (2 / alpha) (distance outside)`, `alpha = 1 - level`, a
//! proper score: the lower, the better, rewarding narrow intervals and punishing misses by
//! how far they miss.

use ndarray::{Array2, ArrayView2, Axis};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::error::{Result, SurrogateError};
use crate::models::booster::HyperParameters;
use crate::models::intervals::{
    check_level, mean_widths, quantile_ends, widen, CalibrationRows, IntervalCalibration,
    Intervals, DEFAULT_LEVEL, QUANTILE_LEVELS,
};
use crate::models::model::TrainedModel;
use crate::models::model_meta::ModelMeta;
use crate::validation::family_folds::{tuning_folds, LeftOut};

/// Per-fold coverage below this, or above [`FOLD_COVERAGE_HIGH`], is counted as a fold the
/// intervals fit badly (at the 90 % level; the band for the pooled coverage).
pub const FOLD_COVERAGE_LOW: f64 = 0.85;
pub const FOLD_COVERAGE_HIGH: f64 = 0.95;

/// A way of making intervals.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntervalMethod {
    /// Quantile trees widened by the conformal margin, the targets' noise apart (shipped).
    ConformalQuantiles,
    /// Quantile trees widened by the conformal margin, blind to the targets' noise.
    NoiseBlindConformalQuantiles,
    /// The prediction plus or minus the conformal margin of the absolute residuals.
    ConstantConformal,
    /// The quantile trees' own ends.
    QuantileTrees,
}

impl IntervalMethod {
    pub const ALL: [IntervalMethod; 4] = [
        IntervalMethod::ConformalQuantiles,
        IntervalMethod::NoiseBlindConformalQuantiles,
        IntervalMethod::ConstantConformal,
        IntervalMethod::QuantileTrees,
    ];

    /// How reports name the method.
    pub fn label(self) -> &'static str {
        match self {
            IntervalMethod::ConformalQuantiles => {
                "quantile trees + conformal margin, noise apart (shipped)"
            }
            IntervalMethod::NoiseBlindConformalQuantiles => {
                "quantile trees + conformal margin, noise-blind"
            }
            IntervalMethod::ConstantConformal => "prediction +- conformal margin",
            IntervalMethod::QuantileTrees => "quantile trees alone",
        }
    }
}

/// How one method's intervals did on one output, all held-out rows together.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutputCoverage {
    /// Fraction of held-out rows inside their interval.
    pub coverage: f64,
    /// Mean of `upper - lower` (output units).
    pub mean_width: f64,
    /// Mean interval score (output units; lower is better).
    pub interval_score: f64,
    /// Folds whose own coverage lies below [`FOLD_COVERAGE_LOW`] and above
    /// [`FOLD_COVERAGE_HIGH`].
    pub folds_below: usize,
    pub folds_above: usize,
}

/// One method's coverage per output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodCoverage {
    pub method: IntervalMethod,
    pub per_output: Vec<OutputCoverage>,
}

/// The shipped method on one fold.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FoldCoverage {
    /// The family (or simulation) held out.
    pub held_out: String,
    pub rows: usize,
    /// Per output: fraction of the rows covered, mean width.
    pub coverage: Vec<f64>,
    pub mean_width: Vec<f64>,
}

/// The coverage of every method on the calibration folds, at one level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IntervalCoverage {
    pub mapping: String,
    pub outputs: Vec<String>,
    pub level: f64,
    pub left_out: LeftOut,
    /// In [`IntervalMethod::ALL`] order.
    pub methods: Vec<MethodCoverage>,
    /// The shipped method's coverage per fold.
    pub folds: Vec<FoldCoverage>,
}

/// Out-of-fold predictions of every row: the held-out fold, the model's prediction and the
/// quantile trees' ends (rows x outputs, original units), and the targets' standard errors.
struct OutOfFold {
    fold: Vec<usize>,
    names: Vec<String>,
    point: Array2<f64>,
    low: Array2<f64>,
    high: Array2<f64>,
    noise: Array2<f64>,
}

/// The calibration of a mapping's intervals and the coverage measured on its folds.
#[derive(Debug, Clone)]
pub struct IntervalStudy {
    pub calibration: IntervalCalibration,
    pub coverage: IntervalCoverage,
    /// The name of the fold (family or simulation) that held each row out.
    held_out_by: Vec<String>,
}

impl IntervalStudy {
    /// Fits `mapping`'s model and quantile trees with `params` on each fold of `samples`,
    /// predicts the held-out rows, and measures every method's cross-conformal coverage at
    /// `level`. `noise` holds the standard errors of the outputs' targets (rows x outputs;
    /// `None`: noiseless targets, and the shipped method is CQR as published). The folds run
    /// in parallel on rayon's pool.
    pub fn run(
        mapping: &Mapping,
        samples: &Samples,
        noise: Option<ArrayView2<f64>>,
        params: &HyperParameters,
        level: f64,
    ) -> Result<Self> {
        check_level(level)?;
        let (left_out, folds) = tuning_folds(samples)?;
        let mut oof = out_of_fold(mapping, samples, params, left_out, &folds)?;
        if let Some(noise) = noise {
            if noise.dim() != oof.noise.dim() || noise.iter().any(|e| e.is_nan() || *e < 0.0) {
                return Err(SurrogateError::InvalidArgument(format!(
                    "the targets' standard errors must be {} x {} numbers >= 0",
                    samples.n_rows(),
                    samples.output_names.len()
                )));
            }
            oof.noise.assign(&noise);
        }
        let truth = samples.outputs.view();
        let rows = calibration_rows(IntervalMethod::ConformalQuantiles, &oof, truth);
        let at_default = cross_conformal(
            IntervalMethod::ConformalQuantiles,
            &oof,
            truth,
            &samples.output_names,
            DEFAULT_LEVEL,
        );
        let calibration = IntervalCalibration {
            mapping: mapping.name.to_owned(),
            outputs: samples.output_names.clone(),
            quantile_levels: QUANTILE_LEVELS,
            held_out: left_out.plural().to_owned(),
            folds: folds.len(),
            fold_coverage: at_default
                .covers(truth)
                .columns()
                .into_iter()
                .map(|c| fraction(c.iter().copied()))
                .collect(),
            fold_mean_width: mean_widths(&at_default),
            training_fnv1a_64: samples.source_fingerprint,
            training_rows: samples.n_rows(),
            rows,
        };
        let methods = IntervalMethod::ALL
            .iter()
            .map(|&method| {
                let intervals = cross_conformal(method, &oof, truth, &samples.output_names, level);
                MethodCoverage {
                    method,
                    per_output: output_coverage(&intervals, truth, &oof.fold, folds.len(), level),
                }
            })
            .collect();
        let shipped = cross_conformal(
            IntervalMethod::ConformalQuantiles,
            &oof,
            truth,
            &samples.output_names,
            level,
        );
        let fold_coverage = (0..folds.len())
            .map(|f| {
                let rows: Vec<usize> = (0..oof.fold.len()).filter(|&i| oof.fold[i] == f).collect();
                let covered = shipped.covers(truth).select(Axis(0), &rows);
                let widths = (&shipped.upper - &shipped.lower).select(Axis(0), &rows);
                FoldCoverage {
                    held_out: oof.names[f].clone(),
                    rows: rows.len(),
                    coverage: covered
                        .columns()
                        .into_iter()
                        .map(|c| fraction(c.iter().copied()))
                        .collect(),
                    mean_width: widths
                        .mean_axis(Axis(0))
                        .map_or_else(Vec::new, |m| m.to_vec()),
                }
            })
            .collect();
        let held_out_by = oof.fold.iter().map(|&f| oof.names[f].clone()).collect();
        Ok(IntervalStudy {
            calibration,
            held_out_by,
            coverage: IntervalCoverage {
                mapping: mapping.name.to_owned(),
                outputs: samples.output_names.clone(),
                level,
                left_out,
                methods,
                folds: fold_coverage,
            },
        })
    }
}

impl IntervalStudy {
    /// The calibration of a model trained without the rows of fold `held_out` (a family or
    /// simulation of this study), `meta` its sidecar: the scores of every other fold's rows,
    /// which came from models that did not see them either (cross-conformal). Its
    /// `fold_coverage` and `fold_mean_width` are the whole study's.
    pub fn calibration_without(
        &self,
        held_out: &str,
        meta: &ModelMeta,
    ) -> Result<IntervalCalibration> {
        let rows: Vec<usize> = (0..self.held_out_by.len())
            .filter(|&i| self.held_out_by[i] != held_out)
            .collect();
        if rows.len() == self.held_out_by.len() {
            return Err(SurrogateError::InvalidArgument(format!(
                "no fold of the intervals' study of `{}` held out `{held_out}`",
                self.calibration.mapping
            )));
        }
        Ok(IntervalCalibration {
            training_fnv1a_64: meta.training_data.fnv1a_64,
            training_rows: meta.training_data.rows,
            rows: self
                .calibration
                .rows
                .iter()
                .map(|r| r.select(&rows))
                .collect(),
            ..self.calibration.clone()
        })
    }
}

/// The out-of-fold predictions of every row of `samples` over `folds`.
fn out_of_fold(
    mapping: &Mapping,
    samples: &Samples,
    params: &HyperParameters,
    left_out: LeftOut,
    folds: &[crate::validation::cross_validation::Fold],
) -> Result<OutOfFold> {
    let fitted = folds
        .par_iter()
        .map(|fold| {
            let train = samples.subset(&fold.train)?;
            let test = samples.subset(&fold.test)?;
            let model = TrainedModel::fit(mapping, &train, params)?;
            let trees = model.fit_quantile_trees(&train, params)?;
            let point = model.predict_features(test.features.view())?;
            let (low, high) = quantile_ends(&trees, model.meta(), test.features.view())?;
            Ok((point, low, high))
        })
        .collect::<Result<Vec<_>>>()?;
    let (n, k) = (samples.n_rows(), samples.output_names.len());
    let mut oof = OutOfFold {
        fold: vec![0; n],
        names: Vec::with_capacity(folds.len()),
        point: Array2::zeros((n, k)),
        low: Array2::zeros((n, k)),
        high: Array2::zeros((n, k)),
        noise: Array2::zeros((n, k)),
    };
    for (f, (fold, (point, low, high))) in folds.iter().zip(fitted).enumerate() {
        let first = fold.test[0];
        oof.names.push(match (left_out, &samples.families) {
            (LeftOut::Family, Some(families)) => families[first].clone(),
            _ => samples.groups[first].clone(),
        });
        for (i, &row) in fold.test.iter().enumerate() {
            oof.fold[row] = f;
            oof.point.row_mut(row).assign(&point.row(i));
            oof.low.row_mut(row).assign(&low.row(i));
            oof.high.row_mut(row).assign(&high.row(i));
        }
    }
    Ok(oof)
}

/// Every row's residual, spans and noise under `method`, per output: the quantile trees'
/// spans (zero for the constant interval, whose ends are the prediction), and the targets'
/// standard errors for the shipped method only.
fn calibration_rows(
    method: IntervalMethod,
    oof: &OutOfFold,
    truth: ArrayView2<f64>,
) -> Vec<CalibrationRows> {
    let residual = &truth - &oof.point;
    let (below, above) = match method {
        IntervalMethod::ConstantConformal => (
            Array2::zeros(residual.raw_dim()),
            Array2::zeros(residual.raw_dim()),
        ),
        _ => (&oof.point - &oof.low, &oof.high - &oof.point),
    };
    let noise = match method {
        IntervalMethod::ConformalQuantiles => oof.noise.clone(),
        _ => Array2::zeros(residual.raw_dim()),
    };
    (0..truth.ncols())
        .map(|j| {
            CalibrationRows::of(
                residual.column(j),
                below.column(j),
                above.column(j),
                noise.column(j),
            )
        })
        .collect()
}

/// The intervals of every row under `method`, each fold's rows with the margin of the
/// other folds' rows at `level` (and, for the shipped method, their own noise).
fn cross_conformal(
    method: IntervalMethod,
    oof: &OutOfFold,
    truth: ArrayView2<f64>,
    outputs: &[String],
    level: f64,
) -> Intervals {
    let rows = calibration_rows(method, oof, truth);
    let (n, k) = truth.dim();
    let mut lower = Array2::zeros((n, k));
    let mut upper = Array2::zeros((n, k));
    for f in 0..oof.names.len() {
        let (inside, outside): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| oof.fold[i] == f);
        let margins: Vec<f64> = rows
            .iter()
            .map(|r| match method {
                IntervalMethod::QuantileTrees => 0.0,
                _ => r.select(&outside).margin(level),
            })
            .collect();
        let pick = |a: &Array2<f64>| a.select(Axis(0), &inside);
        let (low, high) = match method {
            IntervalMethod::ConstantConformal => (pick(&oof.point), pick(&oof.point)),
            _ => (pick(&oof.low), pick(&oof.high)),
        };
        let noise = pick(&oof.noise);
        let part = widen(
            outputs,
            pick(&oof.point).view(),
            low.view(),
            high.view(),
            &margins,
            (method == IntervalMethod::ConformalQuantiles).then(|| noise.view()),
            level,
        );
        for (r, &i) in inside.iter().enumerate() {
            lower.row_mut(i).assign(&part.lower.row(r));
            upper.row_mut(i).assign(&part.upper.row(r));
        }
    }
    Intervals {
        level,
        lower,
        upper,
    }
}

/// Coverage, width, interval score and the folds covered badly, per output.
fn output_coverage(
    intervals: &Intervals,
    truth: ArrayView2<f64>,
    fold: &[usize],
    n_folds: usize,
    level: f64,
) -> Vec<OutputCoverage> {
    let covered = intervals.covers(truth);
    (0..truth.ncols())
        .map(|j| {
            let per_fold: Vec<f64> = (0..n_folds)
                .map(|f| {
                    fraction(
                        (0..fold.len())
                            .filter(|&i| fold[i] == f)
                            .map(|i| covered[[i, j]]),
                    )
                })
                .collect();
            let (lo, hi) = (intervals.lower.column(j), intervals.upper.column(j));
            OutputCoverage {
                coverage: fraction(covered.column(j).iter().copied()),
                mean_width: (&hi - &lo).mean().unwrap_or(f64::NAN),
                interval_score: interval_score(lo, hi, truth.column(j), level),
                folds_below: per_fold.iter().filter(|&&c| c < FOLD_COVERAGE_LOW).count(),
                folds_above: per_fold.iter().filter(|&&c| c > FOLD_COVERAGE_HIGH).count(),
            }
        })
        .collect()
}

/// The mean interval score `(u - l) + (2 / alpha) ((l - y)^+ + (y - u)^+)`, `alpha = 1 - level`.
pub fn interval_score(
    lower: ndarray::ArrayView1<f64>,
    upper: ndarray::ArrayView1<f64>,
    truth: ndarray::ArrayView1<f64>,
    level: f64,
) -> f64 {
    let alpha = 1.0 - level;
    let n = truth.len().max(1) as f64;
    lower
        .iter()
        .zip(upper)
        .zip(truth)
        .map(|((&l, &u), &y)| (u - l) + 2.0 / alpha * ((l - y).max(0.0) + (y - u).max(0.0)))
        .sum::<f64>()
        / n
}

/// The fraction of `true` among `flags` (NaN without any).
pub fn fraction(flags: impl Iterator<Item = bool>) -> f64 {
    let (n, k) = flags.fold((0usize, 0usize), |(n, k), f| (n + 1, k + usize::from(f)));
    if n == 0 {
        f64::NAN
    } else {
        k as f64 / n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn the_interval_score_adds_the_width_and_twenty_times_a_miss_at_90_percent() {
        let (l, u) = (array![0.0, 0.0], array![1.0, 1.0]);
        let y = array![0.5, 1.5];
        // Width 1 each; the second misses by 0.5: 2 / 0.1 * 0.5 = 10.
        let s = interval_score(l.view(), u.view(), y.view(), 0.9);
        assert!((s - (1.0 + 11.0) / 2.0).abs() < 1e-12, "{s}");
        assert_eq!(fraction([true, false, true, true].into_iter()), 0.75);
        assert!(fraction(std::iter::empty()).is_nan());
    }
}
