//! Prediction from a saved model without the XGBoost library: the sidecar plus the trees
//! read by [`Forest`], for callers that load a model to predict one profile and must do
//! so in milliseconds (`suspflow predict`). It gives the same numbers as the
//! [`TrainedModel`](crate::models::model::TrainedModel) the files came from, to f32 rounding.

use std::path::Path;

use ndarray::{Array2, ArrayView2};

use crate::data::dataset::Dataset;
use crate::data::training_domain::{DomainCheck, TrainingDomain};
use crate::error::Result;
use crate::models::forest::Forest;
use crate::models::model::ModelMeta;

/// A saved model, ready to predict.
#[derive(Debug, Clone)]
pub struct Predictor {
    meta: ModelMeta,
    forest: Forest,
    domain: TrainingDomain,
}

impl Predictor {
    /// Reads the model of mapping `name` saved in `dir`, with the same checks as
    /// [`TrainedModel::load`](crate::models::model::TrainedModel::load).
    pub fn load(dir: &Path, name: &str) -> Result<Self> {
        let read_trees =
            |path: &Path, json: &[u8]| Forest::from_json(json, &path.display().to_string());
        let (meta, forest, domain) =
            ModelMeta::load_with(dir, name, read_trees, |f| Some(f.n_trees()))?;
        Ok(Predictor {
            meta,
            forest,
            domain,
        })
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
