//! Prediction from a saved model without the XGBoost library: the sidecar plus the trees
//! read by [`Forest`], for callers that load a model to predict one profile and must do
//! so in milliseconds (`suspflow predict`). It gives the same numbers as the
//! [`TrainedModel`](crate::models::model::TrainedModel) the files came from, to f32 rounding.

use std::path::Path;

use ndarray::{Array2, ArrayView2};

use crate::data::dataset::Dataset;
use crate::data::training_domain::{DomainCheck, TrainingDomain};
use crate::error::Result;
use crate::models::bundle::load_bundle;
use crate::models::forest::Forest;
use crate::models::intervals::{check_level, load_intervals, widen, Intervals, ModelIntervals};
use crate::models::model::TrainedModel;
use crate::models::model_meta::ModelMeta;

/// A saved model, ready to predict, with its intervals when it was saved with them.
#[derive(Debug, Clone)]
pub struct Predictor {
    meta: ModelMeta,
    forest: Forest,
    domain: TrainingDomain,
    intervals: Option<ModelIntervals<Forest>>,
}

/// Predictions for the rows of a table, with their intervals.
#[derive(Debug, Clone)]
pub struct Prediction {
    /// Rows x outputs, original units, clipped into the physical range.
    pub values: Array2<f64>,
    /// Predicted values that left their physical range and were clipped.
    pub clipped: usize,
    /// The intervals at the level asked for; `None` for a model saved without them.
    pub intervals: Option<Intervals>,
    /// Whether the intervals are those of targets with the table's standard errors
    /// (`<output>_se` columns), rather than of the true means.
    pub with_target_noise: bool,
}

impl Predictor {
    /// Reads the model of mapping `name` saved in `dir`, with the same checks as
    /// [`TrainedModel::load`](crate::models::model::TrainedModel::load).
    pub fn load(dir: &Path, name: &str) -> Result<Self> {
        let read_trees =
            |path: &Path, json: &[u8]| Forest::from_json(json, &path.display().to_string());
        let (meta, forest, domain) = load_bundle(dir, name, read_trees, |f| Some(f.n_trees()))?;
        let intervals =
            load_intervals(dir, &meta, read_trees, |f| (f.n_features(), f.n_outputs()))?;
        Ok(Predictor {
            meta,
            forest,
            domain,
            intervals,
        })
    }

    /// The predictor of a model trained in this process, as [`Predictor::load`] would read it
    /// back after [`TrainedModel::save`] (its trees through their XGBoost JSON).
    pub fn of(model: &TrainedModel) -> Result<Self> {
        let forest = |booster: &crate::models::booster::Booster| {
            Forest::from_json(&booster.to_json()?, "a model trained in this process")
        };
        let intervals = model
            .intervals()
            .map(|i| -> Result<_> {
                Ok(ModelIntervals::new(
                    i.calibration.clone(),
                    i.trees.iter().map(forest).collect::<Result<Vec<_>>>()?,
                ))
            })
            .transpose()?;
        Ok(Predictor {
            meta: model.meta().clone(),
            forest: forest(model.booster())?,
            domain: model.domain().clone(),
            intervals,
        })
    }

    /// The intervals' quantile trees and calibration, if the model was saved with them.
    pub fn intervals(&self) -> Option<&ModelIntervals<Forest>> {
        self.intervals.as_ref()
    }

    /// Predictions for the feature columns of `dataset`, with their intervals at `level`:
    /// of the value the row's simulation would measure with the standard errors of the
    /// table's `<output>_se` columns when it has them (0 in an empty cell), else of the true
    /// mean ([`crate::models::intervals`]).
    pub fn predict_with_intervals(&self, dataset: &Dataset, level: f64) -> Result<Prediction> {
        check_level(level)?;
        let features = self.meta.feature_matrix(dataset)?;
        let scaled = self.forest.predict(features.view())?;
        let (values, clipped) = self
            .meta
            .outputs_counting_clips(features.view(), scaled.view())?;
        let noise = self.target_standard_errors(dataset)?;
        let intervals = self
            .intervals
            .as_ref()
            .map(|i| {
                i.intervals(
                    &self.meta,
                    features.view(),
                    values.view(),
                    noise.as_ref().map(Array2::view),
                    level,
                )
            })
            .transpose()?;
        Ok(Prediction {
            values,
            clipped,
            intervals,
            with_target_noise: noise.is_some(),
        })
    }

    /// The standard errors of the outputs' targets in `dataset` (rows x outputs): its
    /// `<output>_se` columns, 0 in an empty or non-finite cell and for an output without
    /// one; `None` when no output has one.
    fn target_standard_errors(&self, dataset: &Dataset) -> Result<Option<Array2<f64>>> {
        let names = dataset.column_names();
        let columns: Vec<Option<String>> = self
            .meta
            .outputs
            .iter()
            .map(|o| Some(schema::columns::standard_error(o)).filter(|c| names.contains(c)))
            .collect();
        if columns.iter().all(Option::is_none) {
            return Ok(None);
        }
        let mut se = Array2::zeros((dataset.n_rows(), columns.len()));
        for (j, column) in columns.iter().enumerate() {
            let Some(column) = column else { continue };
            for (i, &e) in dataset.column(column)?.iter().enumerate() {
                se[[i, j]] = if e.is_finite() && e > 0.0 { e } else { 0.0 };
            }
        }
        Ok(Some(se))
    }

    /// The interval at `level` of [`Predictor::expected_outputs`] (of the true mean) for one
    /// row `x`, each
    /// feature spread over `x_i +- half_width_i`: the quantile trees' expected ends widened
    /// by the margins ([`crate::models::intervals::widen`]), as `(lower, upper)` per output;
    /// `None` for a model without intervals.
    pub fn expected_interval(
        &self,
        x: &[f64],
        half_width: &[f64],
        level: f64,
    ) -> Result<Option<Intervals>> {
        let Some(intervals) = &self.intervals else {
            return Ok(None);
        };
        let n = self.meta.outputs.len();
        let (mut low, mut high) = (Array2::zeros((1, n)), Array2::zeros((1, n)));
        for (j, trees) in intervals.trees.iter().enumerate() {
            let q = trees.expected(x, half_width);
            low[[0, j]] = q[0];
            high[[0, j]] = q[1];
        }
        let features = ArrayView2::from_shape((1, x.len()), x)
            .map_err(|e| crate::error::SurrogateError::InvalidArgument(e.to_string()))?;
        let point = Array2::from_shape_vec((1, n), self.expected_outputs(x, half_width)?)
            .map_err(|e| crate::error::SurrogateError::InvalidArgument(e.to_string()))?;
        Ok(Some(widen(
            &self.meta.outputs,
            point.view(),
            self.meta.outputs(features, low.view())?.view(),
            self.meta.outputs(features, high.view())?.view(),
            &intervals.margins(level)?,
            None,
            level,
        )))
    }

    /// The sidecar.
    pub fn meta(&self) -> &ModelMeta {
        &self.meta
    }

    /// Where the training rows lie in feature space.
    pub fn domain(&self) -> &TrainingDomain {
        &self.domain
    }

    /// The training-domain check of every row of `dataset`.
    pub fn check_domain(&self, dataset: &Dataset) -> Result<Vec<DomainCheck>> {
        self.domain.check(self.meta.feature_matrix(dataset)?.view())
    }

    /// The expected prediction in original units for one row `x` (features in
    /// [`ModelMeta::features`] order) when each feature is spread uniformly over `x_i +-
    /// half_width_i` (see [`Forest::expected`]): continuous in `x`, for solvers.
    pub fn expected_outputs(&self, x: &[f64], half_width: &[f64]) -> Result<Vec<f64>> {
        let scaled = ndarray::Array2::from_shape_vec(
            (1, self.meta.outputs.len()),
            self.forest.expected(x, half_width),
        )
        .map_err(|e| crate::error::SurrogateError::InvalidArgument(e.to_string()))?;
        let features = ndarray::ArrayView2::from_shape((1, x.len()), x)
            .map_err(|e| crate::error::SurrogateError::InvalidArgument(e.to_string()))?;
        Ok(self.meta.outputs(features, scaled.view())?.row(0).to_vec())
    }

    /// Output `output` (an index into [`ModelMeta::outputs`]) of
    /// [`Predictor::expected_outputs`] alone, walking only that output's trees; the same
    /// number.
    pub fn expected_output(&self, x: &[f64], half_width: &[f64], output: usize) -> Result<f64> {
        let n = self.meta.outputs.len();
        if output >= n {
            return Err(crate::error::SurrogateError::InvalidArgument(format!(
                "output {output} of a model of {n} outputs"
            )));
        }
        // The other outputs' cells are left at 0: each output is unscaled on its own.
        let mut scaled = ndarray::Array2::zeros((1, n));
        scaled[[0, output]] = self.forest.expected_output(x, half_width, output);
        let features = ndarray::ArrayView2::from_shape((1, x.len()), x)
            .map_err(|e| crate::error::SurrogateError::InvalidArgument(e.to_string()))?;
        Ok(self.meta.outputs(features, scaled.view())?[[0, output]])
    }

    /// Predictions in original units (rows x outputs) for the feature columns of `dataset`.
    pub fn predict(&self, dataset: &Dataset) -> Result<Array2<f64>> {
        self.predict_features(self.meta.feature_matrix(dataset)?.view())
    }

    /// [`Predictor::predict`], with the number of cells clipped into their physical range
    /// ([`crate::data::physical_range`]).
    pub fn predict_counting_clips(&self, dataset: &Dataset) -> Result<(Array2<f64>, usize)> {
        let features = self.meta.feature_matrix(dataset)?;
        let scaled = self.forest.predict(features.view())?;
        self.meta
            .outputs_counting_clips(features.view(), scaled.view())
    }

    /// Predictions in original units for a rows x features matrix, columns in
    /// [`ModelMeta::features`] order.
    pub fn predict_features(&self, features: ArrayView2<f64>) -> Result<Array2<f64>> {
        let scaled = self.forest.predict(features)?;
        self.meta.outputs(features, scaled.view())
    }
}
