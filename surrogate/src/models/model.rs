//! A trained mapping: an XGBoost booster on min-max scaled outputs, plus the sidecar that says
//! how to use it (`<mapping>.meta.json` next to `<mapping>.json`).

use std::path::{Path, PathBuf};

use ndarray::{Array2, ArrayView2};
use serde::{Deserialize, Serialize};

use crate::data::dataset::Dataset;
use crate::data::files;
use crate::data::mapping::Mapping;
use crate::data::physical_range::clip_to_physical_range;
use crate::data::samples::Samples;
use crate::data::scaling::MinMaxScaling;
use crate::data::training_domain::TrainingDomain;
use crate::error::{Result, SurrogateError};
use crate::models::booster::{xgboost_version, Booster, HyperParameters};
use crate::models::metrics::relative_l2_error;
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
    pub fnv1a_64: String,
    /// Number of rows used for training.
    pub rows: usize,
    /// Rows of the source left out because a cell of the mapping's columns was empty.
    #[serde(default)]
    pub skipped_rows: usize,
}

/// A booster with its sidecar and the training domain of its features.
#[derive(Debug)]
pub struct TrainedModel {
    meta: ModelMeta,
    booster: Booster,
    domain: TrainingDomain,
}

impl TrainedModel {
    /// Trains `mapping` on all rows of `dataset`.
    pub fn train(mapping: &Mapping, dataset: &Dataset, params: &HyperParameters) -> Result<Self> {
        Self::fit(mapping, &Samples::from_dataset(dataset, mapping)?, params)
    }

    /// Trains `mapping` on `samples`: outputs are min-max scaled on these samples, then learnt.
    pub fn fit(mapping: &Mapping, samples: &Samples, params: &HyperParameters) -> Result<Self> {
        check_columns(samples, mapping.features, mapping.outputs)?;
        let domain = TrainingDomain::fit(samples)?;
        let scaling = MinMaxScaling::fit(samples.outputs.view())?;
        let (backbone, targets) = if params.backbone {
            let (backbone, residuals) = Backbone::fit(samples)?;
            (Some(backbone), residuals)
        } else {
            (None, scaling.scale(samples.outputs.view())?)
        };
        let booster = Booster::train(
            samples.features.view(),
            targets.view(),
            mapping.features,
            params,
        )?;
        let meta = ModelMeta {
            mapping: mapping.name.to_owned(),
            features: samples.feature_names.clone(),
            outputs: samples.output_names.clone(),
            scaling,
            backbone,
            hyper_parameters: params.clone(),
            training_data: TrainingData {
                source: samples.source_name.clone(),
                fnv1a_64: format!("{:016x}", samples.source_fingerprint),
                rows: samples.n_rows(),
                skipped_rows: samples.skipped_rows,
            },
            xgboost_version: xgboost_version(),
        };
        crate::models::bundle::check_meta(&meta).map_err(SurrogateError::InvalidArgument)?;
        Ok(TrainedModel {
            meta,
            booster,
            domain,
        })
    }

    /// The sidecar.
    pub fn meta(&self) -> &ModelMeta {
        &self.meta
    }

    /// Where the model's training rows lie in feature space.
    pub fn domain(&self) -> &TrainingDomain {
        &self.domain
    }

    /// Predictions in original units (rows x outputs) for the feature columns of `dataset`.
    pub fn predict(&self, dataset: &Dataset) -> Result<Array2<f64>> {
        self.predict_features(self.meta.feature_matrix(dataset)?.view())
    }

    /// Predictions in original units for a rows x features matrix, columns in
    /// [`ModelMeta::features`] order.
    pub fn predict_features(&self, features: ArrayView2<f64>) -> Result<Array2<f64>> {
        self.meta
            .outputs(features, self.booster.predict(features)?.view())
    }

    /// Relative L2 error of each output on `samples` (thesis eq 6.6), on outputs
    /// scaled with the training set's ranges.
    pub fn evaluate(&self, samples: &Samples) -> Result<Vec<f64>> {
        check_columns(samples, &self.meta.features, &self.meta.outputs)?;
        let truth = self.meta.scaling.scale(samples.outputs.view())?;
        let predicted = self
            .meta
            .scaling
            .scale(self.predict_features(samples.features.view())?.view())?;
        relative_l2_error(truth.view(), predicted.view())
    }

    /// Gain importance of each feature (see [`Booster::feature_importance_gain`]).
    pub fn feature_importance(&self) -> Result<Vec<(String, f64)>> {
        let gains = self.booster.feature_importance_gain()?;
        Ok(self.meta.features.iter().cloned().zip(gains).collect())
    }

    /// Writes `<dir>/<mapping>.json` (the booster, XGBoost JSON), `<dir>/<mapping>.meta.json`
    /// and `<dir>/<mapping>.domain.json`, creating `dir` if needed.
    pub fn save(&self, dir: &Path) -> Result<()> {
        files::create_dir_all(dir)?;
        let paths = ModelPaths::new(dir, &self.meta.mapping);
        self.booster.save_json(&paths.trees)?;
        files::write_json(&paths.meta, &self.meta)?;
        files::write_json(&paths.domain, &self.domain)
    }

    /// Reads the model of mapping `name` saved in `dir`, checking that the sidecar, the
    /// booster and the mapping's current definition agree on features and outputs.
    pub fn load(dir: &Path, name: &str) -> Result<Self> {
        let (meta, booster, domain) = ModelMeta::load_with(dir, name, Booster::load_json, |b| {
            // XGBoost reads the trees itself; their count is checked where they are walked.
            (
                b.n_features(),
                b.n_outputs(),
                b.feature_names().to_vec(),
                None,
            )
        })?;
        Ok(TrainedModel {
            meta,
            booster,
            domain,
        })
    }
}

impl ModelMeta {
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
                    "{} lacks column(s) {}",
                    dataset.source_name(),
                    missing.join(", ")
                ),
                expected: self.features.clone(),
                found: available.to_vec(),
            });
        }
        let names: Vec<&str> = self.features.iter().map(String::as_str).collect();
        dataset.matrix(&names)
    }

    /// Reads the sidecar `<dir>/<name>.meta.json`, the trees `<dir>/<name>.json` (with
    /// `load_trees`) and the training domain `<dir>/<name>.domain.json`, and checks that the
    /// sidecar, the trees' `(features, outputs, feature names, tree count)` as `shape` tells
    /// them, the domain's feature count and mapping `name`'s current definition agree, then
    /// the whole bundle ([`crate::models::bundle::check`]). Trees that store no feature names
    /// are checked by their counts alone.
    pub(crate) fn load_with<T>(
        dir: &Path,
        name: &str,
        load_trees: impl FnOnce(&Path) -> Result<T>,
        shape: impl FnOnce(&T) -> (usize, usize, Vec<String>, Option<usize>),
    ) -> Result<(Self, T, TrainingDomain)> {
        let mapping = Mapping::by_name(name)?;
        let paths = ModelPaths::new(dir, name);
        let (trees_path, meta_path) = (&paths.trees, &paths.meta);
        let meta: ModelMeta = files::read_json(meta_path)?;
        let trees = load_trees(trees_path)?;
        let domain: TrainingDomain = files::read_json(&paths.domain)?;
        let (n_features, n_outputs, tree_features, n_trees) = shape(&trees);
        let mismatch = |detail: String| SurrogateError::FeatureMismatch {
            detail,
            expected: mapping.features.iter().map(|&s| s.to_owned()).collect(),
            found: meta.features.clone(),
        };
        if meta.mapping != mapping.name
            || meta.features != mapping.features
            || meta.outputs != mapping.outputs
        {
            return Err(mismatch(format!(
                "{} describes mapping `{}` with outputs [{}], but mapping `{}` now has outputs [{}]",
                meta_path.display(),
                meta.mapping,
                meta.outputs.join(", "),
                mapping.name,
                mapping.outputs.join(", ")
            )));
        }
        if n_features != meta.features.len()
            || n_outputs != meta.outputs.len()
            || meta.scaling.ranges.len() != meta.outputs.len()
        {
            return Err(mismatch(format!(
                "{} has {} features and {} outputs, {} lists {} and {} (with {} scaling ranges)",
                trees_path.display(),
                n_features,
                n_outputs,
                meta_path.display(),
                meta.features.len(),
                meta.outputs.len(),
                meta.scaling.ranges.len()
            )));
        }
        if !tree_features.is_empty() && tree_features != meta.features {
            return Err(mismatch(format!(
                "the trees in {} were trained on features [{}], not on the [{}] of {} (trees of \
                 another mapping?)",
                trees_path.display(),
                tree_features.join(", "),
                meta.features.join(", "),
                meta_path.display()
            )));
        }
        if domain.axes.len() != meta.features.len()
            || !domain
                .points
                .len()
                .is_multiple_of(meta.features.len().max(1))
        {
            return Err(mismatch(format!(
                "{} has {} feature axes and {} coordinates, {} lists {} features",
                paths.domain.display(),
                domain.axes.len(),
                domain.points.len(),
                meta_path.display(),
                meta.features.len()
            )));
        }
        crate::models::bundle::check(&meta, n_trees, &domain).map_err(|detail| {
            SurrogateError::InconsistentModel {
                model: dir.join(name).display().to_string(),
                detail,
            }
        })?;
        Ok((meta, trees, domain))
    }
}

/// The files of a saved model.
struct ModelPaths {
    /// `<dir>/<name>.json`: the trees (XGBoost JSON).
    trees: PathBuf,
    /// `<dir>/<name>.meta.json`: the sidecar.
    meta: PathBuf,
    /// `<dir>/<name>.domain.json`: the training domain.
    domain: PathBuf,
}

impl ModelPaths {
    fn new(dir: &Path, name: &str) -> Self {
        ModelPaths {
            trees: dir.join(format!("{name}.json")),
            meta: dir.join(format!("{name}.meta.json")),
            domain: dir.join(format!("{name}.domain.json")),
        }
    }
}

/// Fails unless `samples` holds exactly the columns `features` -> `outputs`, in that order.
fn check_columns<S: AsRef<str>>(samples: &Samples, features: &[S], outputs: &[S]) -> Result<()> {
    let same = |names: &[String], expected: &[S]| {
        names
            .iter()
            .map(String::as_str)
            .eq(expected.iter().map(AsRef::as_ref))
    };
    if same(&samples.feature_names, features) && same(&samples.output_names, outputs) {
        return Ok(());
    }
    let owned = |names: &[S]| {
        names
            .iter()
            .map(|n| n.as_ref().to_owned())
            .collect::<Vec<_>>()
    };
    Err(SurrogateError::FeatureMismatch {
        detail: format!(
            "samples of {} map to outputs [{}], the model to outputs [{}]",
            samples.source_name,
            samples.output_names.join(", "),
            owned(outputs).join(", ")
        ),
        expected: owned(features),
        found: samples.feature_names.clone(),
    })
}
