//! Prediction intervals of a trained mapping: conformalised quantile trees (CQR; Romano,
//! Patterson & Candès, NeurIPS 2019), calibrated on rows the model did not see.
//!
//! Beside the model's own trees, one booster per output learns the 5 % and 95 % quantiles
//! ([`QUANTILE_LEVELS`]) of what the model's trees learn (the scaled output, or the scaled
//! residual of the backbone) with XGBoost's pinball loss. Quantile trees fitted on the training
//! rows are too narrow on a new forcing (84.6-85.8 % of the held-out rows inside the 90 %
//! band on the profile-family folds, docs/physics.md section 8), so they are widened by a
//! margin `m`: with the conformity score `s = max(lower - y, y - upper)` of every training
//! row, predicted by the fold that held its profile family out
//! ([`crate::validation::interval_calibration`]), the interval at level `L` is
//! `[min(y_hat, lower - m), max(y_hat, upper + m)]` with `m` the `ceil((n + 1) L)`-th
//! smallest of the `n` scores (split conformal prediction; an interval that never excludes
//! its own prediction), clipped into the output's physical range. The scores are stored, so
//! any level can be asked for; the trees are those of 5 % and 95 %.

use std::path::{Path, PathBuf};

use ndarray::{Array2, ArrayView2, Axis};
use serde::{Deserialize, Serialize};

use crate::data::files;
use crate::data::physical_range::clip_to_physical_range;
use crate::error::{Result, SurrogateError};
use crate::models::booster::Booster;
use crate::models::forest::Forest;
use crate::models::model::ModelMeta;

/// The level of the intervals the commands report unless asked for another.
pub const DEFAULT_LEVEL: f64 = 0.9;

/// The levels of the quantile trees: the lower and upper ends of a central 90 % interval.
pub const QUANTILE_LEVELS: [f64; 2] = [0.05, 0.95];

/// How the intervals of a model were calibrated: `<mapping>.intervals.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IntervalCalibration {
    /// Name of the mapping.
    pub mapping: String,
    /// Output columns, in the order of `scores`.
    pub outputs: Vec<String>,
    /// The levels of the quantile trees.
    pub quantile_levels: [f64; 2],
    /// What each calibration fold held out (`profile families` when the data hold at least
    /// three, else `simulations`), and how many folds there were.
    pub held_out: String,
    pub folds: usize,
    /// At [`DEFAULT_LEVEL`], per output: the fraction of the training rows inside the
    /// interval that the other folds' scores give them (cross-conformal), and its mean width.
    pub fold_coverage: Vec<f64>,
    pub fold_mean_width: Vec<f64>,
    /// FNV-1a 64 hash and row count of the data the model and the scores came from: the
    /// scores of another training are refused.
    pub training_fnv1a_64: schema::Fingerprint,
    pub training_rows: usize,
    /// Per output, every training row's conformity score `max(lower - y, y - upper)` (output
    /// units) from the models of the fold that held it out, ascending.
    pub scores: Vec<Vec<f64>>,
}

impl IntervalCalibration {
    /// The margin `m` of each output at `level` (in (0, 1)): the `ceil((n + 1) level)`-th
    /// smallest score of `n`, or +infinity when that exceeds `n` (too few scores to bound the
    /// interval at that level).
    pub fn margins(&self, level: f64) -> Result<Vec<f64>> {
        check_level(level)?;
        Ok(self
            .scores
            .iter()
            .map(|s| conformal_quantile(s, level))
            .collect())
    }

    /// `<dir>/<name>.intervals.json`.
    pub fn path(dir: &Path, name: &str) -> PathBuf {
        dir.join(format!("{name}.intervals.json"))
    }

    /// `<dir>/<name>.quantiles_<output>.json`: the quantile trees of one output (XGBoost JSON).
    pub fn trees_path(dir: &Path, name: &str, output: &str) -> PathBuf {
        dir.join(format!("{name}.quantiles_{output}.json"))
    }

    /// Refuses a calibration of another mapping, other outputs or other training data than
    /// the model's `meta`, or one whose scores are not ascending finite numbers.
    pub(crate) fn check(&self, meta: &ModelMeta, source: &Path) -> Result<()> {
        let data = &meta.training_data;
        let problem = if self.mapping != meta.mapping || self.outputs != meta.outputs {
            Some(format!(
                "it calibrates mapping `{}` ({}), the model is `{}` ({})",
                self.mapping,
                self.outputs.join(", "),
                meta.mapping,
                meta.outputs.join(", ")
            ))
        } else if self.training_fnv1a_64 != data.fnv1a_64 || self.training_rows != data.rows {
            Some(format!(
                "its scores come from {} rows of data {}, the model was trained on {} rows of \
                 data {}: the intervals of an earlier training",
                self.training_rows, self.training_fnv1a_64, data.rows, data.fnv1a_64
            ))
        } else if self.scores.len() != self.outputs.len()
            || self
                .scores
                .iter()
                .any(|s| s.is_empty() || s.iter().any(|x| !x.is_finite()))
            || self
                .scores
                .iter()
                .any(|s| s.windows(2).any(|w| w[0] > w[1]))
        {
            Some("its scores are not one ascending list of finite numbers per output".to_owned())
        } else {
            None
        };
        match problem {
            Some(detail) => Err(SurrogateError::InconsistentModel {
                model: source.display().to_string(),
                detail,
            }),
            None => Ok(()),
        }
    }
}

/// Refuses a level outside (0, 1).
pub fn check_level(level: f64) -> Result<()> {
    if level > 0.0 && level < 1.0 {
        Ok(())
    } else {
        Err(SurrogateError::InvalidArgument(format!(
            "an interval's level is a probability strictly between 0 and 1, not {level}"
        )))
    }
}

/// The split-conformal quantile of ascending `sorted` scores at `level`: the
/// `ceil((n + 1) level)`-th smallest, +infinity beyond the `n`-th.
pub fn conformal_quantile(sorted: &[f64], level: f64) -> f64 {
    let n = sorted.len();
    let rank = ((n + 1) as f64 * level).ceil() as usize;
    match rank {
        0 => f64::NEG_INFINITY,
        r if r <= n => sorted[r - 1],
        _ => f64::INFINITY,
    }
}

/// Lower and upper bounds (rows x outputs, original units) at a level.
#[derive(Debug, Clone, PartialEq)]
pub struct Intervals {
    pub level: f64,
    pub lower: Array2<f64>,
    pub upper: Array2<f64>,
}

impl Intervals {
    /// Whether `truth` (rows x outputs) lies inside, per cell.
    pub fn covers(&self, truth: ArrayView2<f64>) -> Array2<bool> {
        Array2::from_shape_fn(truth.dim(), |(i, j)| {
            (self.lower[[i, j]]..=self.upper[[i, j]]).contains(&truth[[i, j]])
        })
    }
}

/// Trees that predict from a rows x features matrix: XGBoost's booster or the crate's own walk.
pub trait Trees {
    fn predict_rows(&self, features: ArrayView2<f64>) -> Result<Array2<f64>>;
}

impl Trees for Booster {
    fn predict_rows(&self, features: ArrayView2<f64>) -> Result<Array2<f64>> {
        self.predict(features)
    }
}

impl Trees for Forest {
    fn predict_rows(&self, features: ArrayView2<f64>) -> Result<Array2<f64>> {
        self.predict(features)
    }
}

/// A model's quantile trees (one per output, predicting the two [`QUANTILE_LEVELS`]) and
/// their calibration.
#[derive(Debug, Clone)]
pub struct ModelIntervals<T> {
    pub calibration: IntervalCalibration,
    pub trees: Vec<T>,
}

impl<T: Trees> ModelIntervals<T> {
    /// The intervals at `level` around the model's predictions `point` of rows `features`.
    pub fn intervals(
        &self,
        meta: &ModelMeta,
        features: ArrayView2<f64>,
        point: ArrayView2<f64>,
        level: f64,
    ) -> Result<Intervals> {
        let margins = self.calibration.margins(level)?;
        let (low, high) = quantile_ends(&self.trees, meta, features)?;
        Ok(widen(
            &meta.outputs,
            point,
            low.view(),
            high.view(),
            &margins,
            level,
        ))
    }
}

/// The lower and upper ends (rows x outputs, original units) that the quantile trees `trees`
/// (one per output of model `meta`) give for rows `features`, before any margin.
pub fn quantile_ends<T: Trees>(
    trees: &[T],
    meta: &ModelMeta,
    features: ArrayView2<f64>,
) -> Result<(Array2<f64>, Array2<f64>)> {
    let n = features.nrows();
    let (mut low, mut high) = (
        Array2::zeros((n, trees.len())),
        Array2::zeros((n, trees.len())),
    );
    for (j, trees) in trees.iter().enumerate() {
        let q = trees.predict_rows(features)?;
        low.column_mut(j).assign(&q.column(0));
        high.column_mut(j).assign(&q.column(1));
    }
    Ok((
        meta.outputs(features, low.view())?,
        meta.outputs(features, high.view())?,
    ))
}

/// `[min(point, low - m), max(point, high + m)]` per cell, `m` the output's margin, clipped
/// into each output's physical range.
pub fn widen(
    outputs: &[String],
    point: ArrayView2<f64>,
    low: ArrayView2<f64>,
    high: ArrayView2<f64>,
    margins: &[f64],
    level: f64,
) -> Intervals {
    let mut lower = Array2::from_shape_fn(point.dim(), |(i, j)| {
        point[[i, j]].min(low[[i, j]] - margins[j])
    });
    let mut upper = Array2::from_shape_fn(point.dim(), |(i, j)| {
        point[[i, j]].max(high[[i, j]] + margins[j])
    });
    clip_to_physical_range(outputs, &mut lower);
    clip_to_physical_range(outputs, &mut upper);
    Intervals {
        level,
        lower,
        upper,
    }
}

/// Reads the calibration and quantile trees of model `meta` saved in `dir` with `read_trees`
/// (the path and its bytes), or `None` when the model has no calibration file.
pub(crate) fn load_intervals<T>(
    dir: &Path,
    meta: &ModelMeta,
    read_trees: impl Fn(&Path, &[u8]) -> Result<T>,
    n_features_outputs: impl Fn(&T) -> (usize, usize),
) -> Result<Option<ModelIntervals<T>>> {
    let path = IntervalCalibration::path(dir, &meta.mapping);
    if !path.exists() {
        return Ok(None);
    }
    let calibration: IntervalCalibration = files::read_json(&path, "an interval calibration")?;
    calibration.check(meta, &path)?;
    let trees = meta
        .outputs
        .iter()
        .map(|output| {
            let trees_path = IntervalCalibration::trees_path(dir, &meta.mapping, output);
            let trees = read_trees(&trees_path, &files::read(&trees_path)?)?;
            let shape = n_features_outputs(&trees);
            if shape != (meta.features.len(), QUANTILE_LEVELS.len()) {
                return Err(SurrogateError::InconsistentModel {
                    model: trees_path.display().to_string(),
                    detail: format!(
                        "quantile trees of {} features and {} outputs, the model has {} \
                         features and needs the {} quantiles {QUANTILE_LEVELS:?}",
                        shape.0,
                        shape.1,
                        meta.features.len(),
                        QUANTILE_LEVELS.len()
                    ),
                });
            }
            Ok(trees)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Some(ModelIntervals { calibration, trees }))
}

/// The targets the trees of model `meta` learn for rows `features` with outputs `outputs`
/// (original units): the min-max scaled outputs, or the scaled residual of the backbone.
pub fn tree_targets(
    meta: &ModelMeta,
    features: ArrayView2<f64>,
    outputs: ArrayView2<f64>,
) -> Result<Array2<f64>> {
    match &meta.backbone {
        None => meta.scaling.scale(outputs),
        Some(backbone) => {
            let law = backbone.law_outputs(&meta.features, &meta.outputs, features)?;
            backbone.residual_scaling.scale((&outputs - &law).view())
        }
    }
}

/// The mean width of the intervals of each output.
pub fn mean_widths(intervals: &Intervals) -> Vec<f64> {
    (&intervals.upper - &intervals.lower)
        .mean_axis(Axis(0))
        .map_or_else(Vec::new, |m| m.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn the_conformal_quantile_is_the_ceil_n_plus_one_level_th_score() {
        let scores: Vec<f64> = (1..=9).map(f64::from).collect();
        // (9 + 1) 0.9 = 9: the largest; (9 + 1) 0.5 = 5: the fifth.
        assert_eq!(conformal_quantile(&scores, 0.9), 9.0);
        assert_eq!(conformal_quantile(&scores, 0.5), 5.0);
        // (9 + 1) 0.95 = 9.5 -> 10 > 9: no finite margin.
        assert_eq!(conformal_quantile(&scores, 0.95), f64::INFINITY);
    }

    #[test]
    fn widening_keeps_the_prediction_inside_and_clips_to_the_physical_range() {
        let outputs = vec!["mu".to_owned()];
        let point = array![[0.5], [0.1], [0.9]];
        let low = array![[0.4], [0.2], [0.3]];
        let high = array![[0.6], [0.3], [0.8]];
        let i = widen(
            &outputs,
            point.view(),
            low.view(),
            high.view(),
            &[0.15],
            0.9,
        );
        // Row 1: the quantiles lie above the prediction; row 2: below.
        assert!((i.lower[[0, 0]] - 0.25).abs() < 1e-12 && (i.upper[[0, 0]] - 0.75).abs() < 1e-12);
        assert!((i.lower[[1, 0]] - 0.05).abs() < 1e-12 && (i.upper[[1, 0]] - 0.45).abs() < 1e-12);
        assert!((i.upper[[2, 0]] - 0.95).abs() < 1e-12);
        // A negative margin (a level below the quantile trees' own) narrows, but never
        // past the prediction.
        let (p, l, h) = (array![[0.5]], array![[0.4]], array![[0.6]]);
        let i = widen(&outputs, p.view(), l.view(), h.view(), &[-0.5], 0.5);
        assert_eq!((i.lower[[0, 0]], i.upper[[0, 0]]), (0.5, 0.5));
        // mu is never below 0.
        let (p, l, h) = (array![[0.02]], array![[-0.1]], array![[0.1]]);
        let i = widen(&outputs, p.view(), l.view(), h.view(), &[0.15], 0.9);
        assert_eq!(i.lower[[0, 0]], 0.0);
        let truth = array![[0.0]];
        assert!(i.covers(truth.view())[[0, 0]]);
    }

    #[test]
    fn a_level_outside_zero_one_is_refused() {
        for level in [0.0, 1.0, -0.1, f64::NAN] {
            assert!(check_level(level).is_err(), "{level}");
        }
        assert!(check_level(0.9).is_ok());
    }
}
