//! The sidecar of a trained model (`<mapping>.meta.json`): what it maps, how its outputs are
//! scaled, its backbone, hyper-parameters and training data; and the files a saved model is
//! made of.

use std::path::{Path, PathBuf};

use ndarray::{Array2, ArrayView2};
use schema::Fingerprint;
use serde::{Deserialize, Serialize};

use crate::data::dataset::Dataset;
use crate::data::extremum_distance::with_derived_features;
use crate::data::files;
use crate::data::physical_range::clip_to_physical_range;
use crate::data::scaling::MinMaxScaling;
use crate::error::{Result, SurrogateError};
use crate::models::booster::HyperParameters;
use crate::rheology::backbone::Backbone;
/// Everything about a trained model except its trees.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelMeta {
    /// Name of the [`Mapping`].
    pub mapping: String,
    /// Feature columns, in the order the booster reads them.
    pub features: Vec<String>,
    /// Output columns, in the order the booster predicts them.
    pub outputs: Vec<String>,
    /// Ranges of the outputs in the training set (eq 6.4, also the metric's scaling); the
    /// booster predicts scaled outputs, or scaled residuals when there is a backbone.
    pub scaling: MinMaxScaling,
    /// The physics backbone whose residual the trees learn, for models trained with
    /// [`HyperParameters::backbone`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub backbone: Option<Backbone>,
    pub hyper_parameters: HyperParameters,
    pub training_data: TrainingData,
    /// Version of the XGBoost library that trained the booster.
    pub xgboost_version: String,
}

/// Which data a model was trained on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainingData {
    /// The file (or other source) the rows came from.
    pub source: String,
    /// FNV-1a 64 hash of that source's bytes, as 16 hex digits.
    pub fnv1a_64: Fingerprint,
    /// Number of rows used for training.
    pub rows: usize,
    /// Rows of the source left out because a cell of the mapping's columns was empty.
    #[serde(default)]
    pub skipped_rows: usize,
}

impl ModelMeta {
    /// The training data file the sidecar names (`training_data.source`), for a model saved
    /// in `model_dir`: an absolute path as it is; a relative one is taken relative to the
    /// folder holding `model_dir` (`suspflow train` records it so: the shipped
    /// `models/*.meta.json` name `datasets/...` beside `models/`), or, when no file is there,
    /// relative to `model_dir` itself. The current directory plays no part, so a model is
    /// found with its data from anywhere. The path is returned even when no file is there
    /// (readers then name it).
    pub fn training_file(&self, model_dir: &Path) -> PathBuf {
        let source = Path::new(&self.training_data.source);
        if source.is_absolute() {
            return source.to_path_buf();
        }
        let dir = std::fs::canonicalize(model_dir)
            .or_else(|_| std::path::absolute(model_dir))
            .unwrap_or_else(|_| model_dir.to_path_buf());
        let beside = dir.parent().unwrap_or(&dir).join(source);
        let inside = dir.join(source);
        if !beside.exists() && inside.exists() {
            inside
        } else {
            beside
        }
    }

    /// The hyper-parameters of the model of mapping `name` saved in `dir` (its sidecar's).
    pub fn load_params(dir: &Path, name: &str) -> Result<HyperParameters> {
        let meta: ModelMeta =
            files::read_json(&ModelPaths::new(dir, name).meta, "a model sidecar")?;
        Ok(meta.hyper_parameters)
    }

    /// How `train` records `data` for a model saved in `model_dir` ([`ModelMeta::training_file`]
    /// reads it back): relative to the folder holding `model_dir` when `data` lies below it,
    /// else as an absolute path.
    pub fn recorded_source(data: &Path, model_dir: &Path) -> String {
        let absolute = |p: &Path| {
            std::fs::canonicalize(p)
                .or_else(|_| std::path::absolute(p))
                .unwrap_or_else(|_| p.to_path_buf())
        };
        let data = absolute(data);
        let dir = absolute(model_dir);
        let base = dir.parent().unwrap_or(&dir);
        data.strip_prefix(base)
            .map_or_else(|_| data.clone(), Path::to_path_buf)
            .display()
            .to_string()
    }

    /// Outputs in original units from the trees' predictions `scaled` for rows `features`:
    /// unscaled outputs, or the backbone plus unscaled residuals, clipped into their
    /// [`physical_range`](crate::data::physical_range::physical_range).
    pub fn outputs(
        &self,
        features: ArrayView2<f64>,
        scaled: ArrayView2<f64>,
    ) -> Result<Array2<f64>> {
        Ok(self.outputs_counting_clips(features, scaled)?.0)
    }

    /// [`ModelMeta::outputs`], with the number of cells the physical range clipped.
    pub fn outputs_counting_clips(
        &self,
        features: ArrayView2<f64>,
        scaled: ArrayView2<f64>,
    ) -> Result<(Array2<f64>, usize)> {
        let mut values = match &self.backbone {
            None => self.scaling.unscale(scaled)?,
            Some(backbone) => backbone.outputs(&self.features, &self.outputs, features, scaled)?,
        };
        let clipped = clip_to_physical_range(&self.outputs, &mut values);
        Ok((values, clipped))
    }

    /// The feature columns of `dataset`, in the model's order, as a matrix of finite numbers;
    /// a missing column is a [`SurrogateError::FeatureMismatch`].
    pub fn feature_matrix(&self, dataset: &Dataset) -> Result<Array2<f64>> {
        let dataset = &*with_derived_features(dataset, &self.features)?;
        let available = dataset.column_names();
        let missing: Vec<&str> = self
            .features
            .iter()
            .filter(|f| !available.contains(f))
            .map(String::as_str)
            .collect();
        if !missing.is_empty() {
            return Err(SurrogateError::FeatureMismatch {
                detail: format!(
                    "{} lacks column(s) {} of the model's features [{}]; its columns are [{}]",
                    dataset.source_name(),
                    missing.join(", "),
                    self.features.join(", "),
                    available.join(", ")
                ),
            });
        }
        let names: Vec<&str> = self.features.iter().map(String::as_str).collect();
        dataset.matrix(&names)
    }
}

/// The files of a saved model.
pub(crate) struct ModelPaths {
    /// `<dir>/<name>.json`: the trees (XGBoost JSON).
    pub(crate) trees: PathBuf,
    /// `<dir>/<name>.meta.json`: the sidecar.
    pub(crate) meta: PathBuf,
    /// `<dir>/<name>.domain.json`: the training domain.
    pub(crate) domain: PathBuf,
}

impl ModelPaths {
    pub(crate) fn new(dir: &Path, name: &str) -> Self {
        ModelPaths {
            trees: dir.join(format!("{name}.json")),
            meta: dir.join(format!("{name}.meta.json")),
            domain: dir.join(format!("{name}.domain.json")),
        }
    }
}
