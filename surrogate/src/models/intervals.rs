//! Prediction intervals of a trained mapping: conformalised quantile trees (CQR; Romano,
//! Patterson & Candès, NeurIPS 2019), calibrated on rows the model did not see, with the
//! model's error kept apart from the target's own noise.
//!
//! Beside the model's own trees, one booster per output learns the 5 % and 95 % quantiles
//! ([`QUANTILE_LEVELS`]) of what the model's trees learn (the scaled output, or the scaled
//! residual of the backbone) with XGBoost's pinball loss. Quantile trees fitted on the training
//! rows are too narrow on a new forcing (81-86 % of the held-out rows inside the 90 %
//! band on the profile-family folds, docs/physics.md section 8), so they are widened by a
//! margin `m`, learnt on the rows of the families each model did not see
//! ([`crate::validation::interval_calibration`]).
//!
//! A target `y` of a simulation is the flow's true mean plus noise of standard error `sigma`
//! (the table's `<output>_se`: a 3-seed ensemble mean has `1/sqrt(3)` of a single run's). The
//! model's miss of the true mean and that noise are independent, so their half-widths add in
//! quadrature. At level `L`, with `z = Phi^-1((1 + L) / 2)`, `below = y_hat - lower_q` and
//! `above = upper_q - y_hat` the quantile trees' spans, the interval of a target with standard
//! error `sigma` is
//!
//! `[y_hat - sqrt((below + m)_+^2 + (z sigma)^2), y_hat + sqrt((above + m)_+^2 + (z sigma)^2)]`
//!
//! (`(x)_+ = max(x, 0)`). A calibration row of residual `r = y - y_hat` lies inside iff its
//! score `s = sqrt(r^2 - (z sigma)^2) - (above if r > 0 else below)` is at most `m` (`s =
//! -infinity` when `|r| <= z sigma`: its own noise covers it), so `m` is the
//! `ceil((n + 1) L)`-th smallest of the `n` scores (split conformal prediction), and the
//! intervals cover a fraction `L` of rows as noisy as the calibration rows. A row whose
//! target is less noisy (more seeds) gets the narrower interval it deserves, and `sigma = 0`
//! gives the interval of the true mean (infinitely many seeds), what the model alone is
//! unsure of. With `sigma = 0` everywhere this is CQR as published. The intervals are
//! clipped into the output's physical range. The calibration rows are stored, so any level
//! can be asked for; the trees are those of 5 % and 95 %.

use std::path::{Path, PathBuf};

use ndarray::{Array2, ArrayView1, ArrayView2, Axis};
use serde::{Deserialize, Serialize};

use crate::data::files;
use crate::data::physical_range::clip_to_physical_range;
use crate::error::{Result, SurrogateError};
use crate::models::booster::Booster;
use crate::models::forest::Forest;
use crate::models::model_meta::ModelMeta;
use crate::rheology::statistics::standard_normal_quantile;

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
    /// Per output, every training row as the models of the fold that held it out saw it.
    pub rows: Vec<CalibrationRows>,
}

/// One output's calibration rows (output units): each training row's residual `y - y_hat`
/// and its quantile trees' spans `y_hat - lower` and `upper - y_hat` (negative when that
/// quantile lies beyond the prediction), from the models of the fold that held it out, and
/// the standard error of its target (0 when the table gave none).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CalibrationRows {
    pub residual: Vec<f64>,
    pub below: Vec<f64>,
    pub above: Vec<f64>,
    pub noise: Vec<f64>,
}

impl CalibrationRows {
    /// The rows of `residual`, `below`, `above` and `noise` (one value per row each).
    pub fn of(
        residual: ArrayView1<f64>,
        below: ArrayView1<f64>,
        above: ArrayView1<f64>,
        noise: ArrayView1<f64>,
    ) -> Self {
        CalibrationRows {
            residual: residual.to_vec(),
            below: below.to_vec(),
            above: above.to_vec(),
            noise: noise.to_vec(),
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.residual.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.residual.is_empty()
    }

    /// The rows `rows` (indices), in that order.
    pub fn select(&self, rows: &[usize]) -> Self {
        let pick = |v: &Vec<f64>| rows.iter().map(|&i| v[i]).collect();
        CalibrationRows {
            residual: pick(&self.residual),
            below: pick(&self.below),
            above: pick(&self.above),
            noise: pick(&self.noise),
        }
    }

    /// Every row's conformity score at `level` (module doc), ascending.
    pub fn scores(&self, level: f64) -> Vec<f64> {
        let z = noise_quantile(level);
        let mut scores: Vec<f64> = (0..self.len())
            .map(|i| {
                let r = self.residual[i];
                let need = (r * r - (z * self.noise[i]).powi(2)).max(0.0).sqrt();
                if need > 0.0 {
                    need - if r > 0.0 {
                        self.above[i]
                    } else {
                        self.below[i]
                    }
                } else {
                    f64::NEG_INFINITY
                }
            })
            .collect();
        scores.sort_by(f64::total_cmp);
        scores
    }

    /// The margin `m` at `level`: the `ceil((n + 1) level)`-th smallest score of `n`, or
    /// +infinity when that exceeds `n` (too few rows to bound the interval at that level).
    pub fn margin(&self, level: f64) -> f64 {
        conformal_quantile(&self.scores(level), level)
    }
}

/// `z = Phi^-1((1 + level) / 2)`: the half-width, in standard errors, of a central interval
/// at `level` of Gaussian noise.
pub fn noise_quantile(level: f64) -> f64 {
    standard_normal_quantile(0.5 * (1.0 + level))
}

impl IntervalCalibration {
    /// The margin `m` of each output at `level` (in (0, 1)), [`CalibrationRows::margin`].
    pub fn margins(&self, level: f64) -> Result<Vec<f64>> {
        check_level(level)?;
        Ok(self.rows.iter().map(|r| r.margin(level)).collect())
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
        } else if self.rows.len() != self.outputs.len()
            || self.rows.iter().any(|r| {
                r.is_empty()
                    || [&r.below, &r.above, &r.noise]
                        .iter()
                        .any(|v| v.len() != r.len())
                    || [&r.residual, &r.below, &r.above]
                        .iter()
                        .any(|v| v.iter().any(|x| !x.is_finite()))
                    || r.noise.iter().any(|x| !x.is_finite() || *x < 0.0)
            })
        {
            Some(
                "its rows are not, per output, residuals, spans and standard errors of one \
                 length, finite, the standard errors not negative"
                    .to_owned(),
            )
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
    /// The margins at [`DEFAULT_LEVEL`], computed once (a solve asks for them per bin).
    default_margins: Vec<f64>,
}

impl<T: Trees> ModelIntervals<T> {
    /// The intervals of `trees` calibrated by `calibration` (one tree per output of it).
    pub fn new(calibration: IntervalCalibration, trees: Vec<T>) -> Self {
        let default_margins = calibration
            .rows
            .iter()
            .map(|r| r.margin(DEFAULT_LEVEL))
            .collect();
        ModelIntervals {
            calibration,
            trees,
            default_margins,
        }
    }

    /// The margin of each output at `level` ([`IntervalCalibration::margins`]).
    pub fn margins(&self, level: f64) -> Result<Vec<f64>> {
        if level == DEFAULT_LEVEL {
            Ok(self.default_margins.clone())
        } else {
            self.calibration.margins(level)
        }
    }

    /// The intervals at `level` around the model's predictions `point` of rows `features`,
    /// for targets of standard errors `noise` (rows x outputs; `None`: the true means).
    pub fn intervals(
        &self,
        meta: &ModelMeta,
        features: ArrayView2<f64>,
        point: ArrayView2<f64>,
        noise: Option<ArrayView2<f64>>,
        level: f64,
    ) -> Result<Intervals> {
        let margins = self.margins(level)?;
        let (low, high) = quantile_ends(&self.trees, meta, features)?;
        Ok(widen(
            &meta.outputs,
            point,
            low.view(),
            high.view(),
            &margins,
            noise,
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

/// The intervals at `level` of targets of standard errors `noise` (rows x outputs; `None`:
/// zero) around `point`, from the quantile ends `low`, `high` and the margin `m` of each
/// output (module doc): `point -+ sqrt((span + m)_+^2 + (z noise)^2)`, clipped into each
/// output's physical range.
pub fn widen(
    outputs: &[String],
    point: ArrayView2<f64>,
    low: ArrayView2<f64>,
    high: ArrayView2<f64>,
    margins: &[f64],
    noise: Option<ArrayView2<f64>>,
    level: f64,
) -> Intervals {
    let z = noise_quantile(level);
    let half = |span: f64, m: f64, (i, j): (usize, usize)| {
        let sigma = noise.map_or(0.0, |n| n[[i, j]]);
        let model = (span + m).max(0.0);
        if sigma > 0.0 {
            model.hypot(z * sigma)
        } else {
            model
        }
    };
    let mut lower = Array2::from_shape_fn(point.dim(), |(i, j)| {
        point[[i, j]] - half(point[[i, j]] - low[[i, j]], margins[j], (i, j))
    });
    let mut upper = Array2::from_shape_fn(point.dim(), |(i, j)| {
        point[[i, j]] + half(high[[i, j]] - point[[i, j]], margins[j], (i, j))
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
pub(crate) fn load_intervals<T: Trees>(
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
    Ok(Some(ModelIntervals::new(calibration, trees)))
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
            None,
            0.9,
        );
        // Row 1: the quantiles lie above the prediction; row 2: below.
        assert!((i.lower[[0, 0]] - 0.25).abs() < 1e-12 && (i.upper[[0, 0]] - 0.75).abs() < 1e-12);
        assert!((i.lower[[1, 0]] - 0.05).abs() < 1e-12 && (i.upper[[1, 0]] - 0.45).abs() < 1e-12);
        assert!((i.upper[[2, 0]] - 0.95).abs() < 1e-12);
        // A negative margin (a level below the quantile trees' own) narrows, but never
        // past the prediction.
        let (p, l, h) = (array![[0.5]], array![[0.4]], array![[0.6]]);
        let i = widen(&outputs, p.view(), l.view(), h.view(), &[-0.5], None, 0.5);
        assert_eq!((i.lower[[0, 0]], i.upper[[0, 0]]), (0.5, 0.5));
        // mu is never below 0.
        let (p, l, h) = (array![[0.02]], array![[-0.1]], array![[0.1]]);
        let i = widen(&outputs, p.view(), l.view(), h.view(), &[0.15], None, 0.9);
        assert_eq!(i.lower[[0, 0]], 0.0);
        let truth = array![[0.0]];
        assert!(i.covers(truth.view())[[0, 0]]);
    }

    #[test]
    fn a_row_lies_inside_its_interval_exactly_when_its_score_is_at_most_the_margin() {
        // Rows of residual r, spans below / above and noise sigma, each checked against its
        // own interval (predicted at 0 with quantile ends -below, +above) for margins
        // between the scores: the score is the smallest margin that covers the row.
        let rows = CalibrationRows {
            residual: vec![0.3, -0.2, 0.05, -0.4, 0.0, 0.25],
            below: vec![0.1, 0.1, 0.2, 0.5, 0.1, -0.05],
            above: vec![0.1, 0.3, 0.2, 0.1, 0.1, 0.15],
            noise: vec![0.0, 0.05, 0.1, 0.02, 0.0, 0.2],
        };
        let level = 0.9;
        let outputs = vec!["u".to_owned()];
        let n = rows.len();
        let column = |v: &[f64]| Array2::from_shape_vec((n, 1), v.to_vec()).unwrap();
        let point = Array2::zeros((n, 1));
        let low = -column(&rows.below);
        let high = column(&rows.above);
        let truth = column(&rows.residual);
        let noise = column(&rows.noise);
        for m in [-0.3, -0.1, -0.01, 0.0, 0.05, 0.1, 0.2] {
            let i = widen(
                &outputs,
                point.view(),
                low.view(),
                high.view(),
                &[m],
                Some(noise.view()),
                level,
            );
            let covered = i.covers(truth.view());
            for k in 0..n {
                let own = rows.select(&[k]).scores(level)[0];
                assert_eq!(covered[[k, 0]], own <= m, "row {k}, m {m}");
            }
        }
        // Rows 3 (|r| = 0.05 < z 0.1) and 6 (0.25 < z 0.2) and row 5 (r = 0) are covered by
        // their noise alone; without noise the scores are CQR's max(lower - y, y - upper).
        let scores = rows.scores(level);
        assert_eq!(scores.iter().filter(|s| s.is_infinite()).count(), 3);
        let blind = CalibrationRows {
            noise: vec![0.0; n],
            ..rows.clone()
        };
        let scores = blind.scores(level);
        let mut cqr: Vec<f64> = (0..n)
            .filter(|&k| rows.residual[k] != 0.0)
            .map(|k| (-rows.below[k] - rows.residual[k]).max(rows.residual[k] - rows.above[k]))
            .collect();
        cqr.sort_by(f64::total_cmp);
        assert_eq!(&scores[1..], &cqr[..]);
    }

    #[test]
    fn less_noise_narrows_the_interval_in_quadrature() {
        let outputs = vec!["mu".to_owned()];
        let (p, l, h) = (array![[0.5]], array![[0.4]], array![[0.6]]);
        let z = noise_quantile(0.9);
        let at = |sigma: f64| {
            let noise = array![[sigma]];
            widen(
                &outputs,
                p.view(),
                l.view(),
                h.view(),
                &[0.05],
                Some(noise.view()),
                0.9,
            )
        };
        // Model part 0.1 + 0.05 = 0.15 on each side, noise z sigma beside it.
        for sigma in [0.0, 0.03, 0.1] {
            let i = at(sigma);
            let half = 0.15f64.hypot(z * sigma);
            assert!((i.upper[[0, 0]] - 0.5 - half).abs() < 1e-12, "{sigma}");
            assert!((0.5 - i.lower[[0, 0]] - half).abs() < 1e-12, "{sigma}");
        }
        assert!((z - 1.644_853_627).abs() < 1e-8);
    }

    #[test]
    fn a_level_outside_zero_one_is_refused() {
        for level in [0.0, 1.0, -0.1, f64::NAN] {
            assert!(check_level(level).is_err(), "{level}");
        }
        assert!(check_level(0.9).is_ok());
    }
}
