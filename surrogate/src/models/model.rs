//! A trained mapping: an XGBoost booster on min-max scaled outputs, plus the sidecar that says
//! how to use it (`<mapping>.meta.json` next to `<mapping>.json`).

use std::path::{Path, PathBuf};

use ndarray::{Array2, ArrayView2};
use schema::Fingerprint;
use serde::{Deserialize, Serialize};

use crate::data::dataset::Dataset;
use crate::data::extremum_distance::with_derived_features;
use crate::data::files;
use crate::data::mapping::Mapping;
use crate::data::physical_range::clip_to_physical_range;
use crate::data::samples::Samples;
use crate::data::scaling::MinMaxScaling;
use crate::data::training_domain::TrainingDomain;
use crate::error::{name_differences, Result, SurrogateError};
use crate::models::booster::{xgboost_version, Booster, HyperParameters, Objective};
use crate::models::intervals::{
    load_intervals, tree_targets, IntervalCalibration, Intervals, ModelIntervals, QUANTILE_LEVELS,
};
use crate::models::metrics::relative_l2_error;
use crate::models::xgboost_json::ShapeJson;
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

/// A booster with its sidecar, the training domain of its features and, once calibrated, its
/// prediction intervals ([`crate::models::intervals`]).
#[derive(Debug)]
pub struct TrainedModel {
    meta: ModelMeta,
    booster: Booster,
    domain: TrainingDomain,
    intervals: Option<ModelIntervals<Booster>>,
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
                fnv1a_64: samples.source_fingerprint,
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
            intervals: None,
        })
    }

    /// The quantile trees of this model's intervals on `samples` (the rows it was trained on,
    /// or a fold's): per output, one booster with `params`' settings and the pinball loss at
    /// the [`QUANTILE_LEVELS`], learning what the model's trees learn.
    pub fn fit_quantile_trees(
        &self,
        samples: &Samples,
        params: &HyperParameters,
    ) -> Result<Vec<Booster>> {
        check_columns(samples, &self.meta.features, &self.meta.outputs)?;
        let targets = tree_targets(&self.meta, samples.features.view(), samples.outputs.view())?;
        let names: Vec<&str> = self.meta.features.iter().map(String::as_str).collect();
        let objective = Objective::Quantiles(QUANTILE_LEVELS.to_vec());
        targets
            .columns()
            .into_iter()
            .map(|column| {
                let labels = column.insert_axis(ndarray::Axis(1));
                Booster::train_for(samples.features.view(), labels, &names, params, &objective)
            })
            .collect()
    }

    /// This model with the intervals of `trees` ([`TrainedModel::fit_quantile_trees`] on its
    /// training rows) calibrated by `calibration`, which must be of its outputs and training.
    pub fn with_intervals(
        mut self,
        trees: Vec<Booster>,
        calibration: IntervalCalibration,
    ) -> Result<Self> {
        calibration.check(&self.meta, Path::new(&self.meta.mapping))?;
        if trees.len() != self.meta.outputs.len() {
            return Err(SurrogateError::InvalidArgument(format!(
                "{} quantile boosters for {} outputs",
                trees.len(),
                self.meta.outputs.len()
            )));
        }
        self.intervals = Some(ModelIntervals::new(calibration, trees));
        Ok(self)
    }

    /// The XGBoost booster of the model's own trees.
    pub(crate) fn booster(&self) -> &Booster {
        &self.booster
    }

    /// The calibrated intervals, if the model has them.
    pub fn intervals(&self) -> Option<&ModelIntervals<Booster>> {
        self.intervals.as_ref()
    }

    /// The intervals at `level` of the predictions for rows `features`, for targets of
    /// standard errors `noise` (rows x outputs; `None`: the true means); `None` for a model
    /// without calibrated intervals.
    pub fn predict_intervals(
        &self,
        features: ArrayView2<f64>,
        noise: Option<ArrayView2<f64>>,
        level: f64,
    ) -> Result<Option<Intervals>> {
        let Some(intervals) = &self.intervals else {
            return Ok(None);
        };
        let point = self.predict_features(features)?;
        intervals
            .intervals(&self.meta, features, point.view(), noise, level)
            .map(Some)
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
    /// and `<dir>/<mapping>.domain.json`, and the intervals' calibration
    /// `<dir>/<mapping>.intervals.json` and quantile trees `<dir>/<mapping>.quantiles_<output>.json`
    /// (XGBoost JSON) when the model has them (removing an earlier training's when it has
    /// not), creating `dir` if needed.
    pub fn save(&self, dir: &Path) -> Result<()> {
        files::create_dir_all(dir)?;
        let name = &self.meta.mapping;
        let paths = ModelPaths::new(dir, name);
        self.booster.save_json(&paths.trees)?;
        files::write_json(&paths.meta, &self.meta)?;
        files::write_json(&paths.domain, &self.domain)?;
        let calibration = IntervalCalibration::path(dir, name);
        match &self.intervals {
            Some(intervals) => {
                for (output, trees) in self.meta.outputs.iter().zip(&intervals.trees) {
                    trees.save_json(&IntervalCalibration::trees_path(dir, name, output))?;
                }
                files::write_json(&calibration, &intervals.calibration)
            }
            None => {
                let stale = self
                    .meta
                    .outputs
                    .iter()
                    .map(|o| IntervalCalibration::trees_path(dir, name, o))
                    .chain([calibration]);
                for path in stale {
                    files::remove_if_present(&path)?;
                }
                Ok(())
            }
        }
    }

    /// Reads the model of mapping `name` saved in `dir`, checking that the sidecar, the
    /// booster and the mapping's current definition agree on features and outputs.
    pub fn load(dir: &Path, name: &str) -> Result<Self> {
        // XGBoost reads the trees itself; their count is checked where they are walked.
        let read = |path: &Path, json: &[u8]| Booster::from_json(json, path);
        let (meta, booster, domain) = ModelMeta::load_with(dir, name, read, |_| None)?;
        let intervals = load_intervals(dir, &meta, read, |b| (b.n_features(), b.n_outputs()))?;
        Ok(TrainedModel {
            meta,
            booster,
            domain,
            intervals,
        })
    }
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

    /// Reads the sidecar `<dir>/<name>.meta.json`, the trees `<dir>/<name>.json` and the
    /// training domain `<dir>/<name>.domain.json`, and checks that the sidecar, the trees'
    /// counts and feature names (read first, from the file's `learner_model_param`, so that a
    /// model of another mapping is named as such before its trees are read), the domain's
    /// feature count and mapping `name`'s current definition agree; then reads the trees with
    /// `load_trees` (the path and its bytes), then checks the whole bundle
    /// ([`crate::models::bundle::check`]) with the tree count `n_trees` gives. Trees that
    /// store no feature names are checked by their counts alone.
    pub(crate) fn load_with<T>(
        dir: &Path,
        name: &str,
        load_trees: impl FnOnce(&Path, &[u8]) -> Result<T>,
        n_trees: impl FnOnce(&T) -> Option<usize>,
    ) -> Result<(Self, T, TrainingDomain)> {
        let mapping = Mapping::by_name(name)?;
        let paths = ModelPaths::new(dir, name);
        let (trees_path, meta_path) = (&paths.trees, &paths.meta);
        let meta: ModelMeta = files::read_json(meta_path, "a model sidecar")?;
        let trees_json = files::read(trees_path)?;
        let shape: ShapeJson = files::parse_json(trees_path, &trees_json, "an XGBoost JSON model")?;
        let (n_features, n_outputs) = shape
            .learner
            .learner_model_param
            .counts(&trees_path.display().to_string())?;
        let tree_features = shape.learner.feature_names;
        let domain: TrainingDomain = files::read_json(&paths.domain, "a training domain")?;
        let mismatch = |detail: String| SurrogateError::FeatureMismatch { detail };
        if meta.mapping != mapping.name {
            return Err(mismatch(format!(
                "{} describes mapping `{}`, not `{}` (the sidecar of another mapping?)",
                meta_path.display(),
                meta.mapping,
                mapping.name
            )));
        }
        for (what, listed, defined) in [
            ("features", &meta.features, mapping.features),
            ("outputs", &meta.outputs, mapping.outputs),
        ] {
            if listed
                .iter()
                .map(String::as_str)
                .ne(defined.iter().copied())
            {
                return Err(mismatch(format!(
                    "{} lists {what} [{}], mapping `{}` now has [{}]: {}",
                    meta_path.display(),
                    listed.join(", "),
                    mapping.name,
                    defined.join(", "),
                    name_differences(defined, listed)
                )));
            }
        }
        let counted = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
        if n_outputs != mapping.outputs.len() {
            return Err(mismatch(format!(
                "the model {} has {} (learner_model_param.num_target) where mapping `{}` has {} \
                 ({}): trees of another mapping, or an edited file?",
                trees_path.display(),
                counted(n_outputs, "output"),
                mapping.name,
                mapping.outputs.len(),
                mapping.outputs.join(", ")
            )));
        }
        if n_features != mapping.features.len() {
            return Err(mismatch(format!(
                "the model {} has {} (learner_model_param.num_feature) where mapping `{}` has {} \
                 ({}): trees of another mapping, or an edited file?",
                trees_path.display(),
                counted(n_features, "feature"),
                mapping.name,
                mapping.features.len(),
                mapping.features.join(", ")
            )));
        }
        if meta.scaling.ranges.len() != meta.outputs.len() {
            return Err(mismatch(format!(
                "{} holds {} for its {}",
                meta_path.display(),
                counted(meta.scaling.ranges.len(), "scaling range"),
                counted(meta.outputs.len(), "output")
            )));
        }
        if !tree_features.is_empty() && tree_features != meta.features {
            return Err(mismatch(format!(
                "the trees in {} were trained on features [{}], {} lists [{}]: {} (trees of \
                 another mapping?)",
                trees_path.display(),
                tree_features.join(", "),
                meta_path.display(),
                meta.features.join(", "),
                name_differences(&meta.features, &tree_features)
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
        let trees = load_trees(trees_path, &trees_json)?;
        crate::models::bundle::check(&meta, n_trees(&trees), &domain).map_err(|detail| {
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
    let differences = [
        ("features", &samples.feature_names, owned(features)),
        ("outputs", &samples.output_names, owned(outputs)),
    ]
    .into_iter()
    .filter(|(_, found, expected)| *found != expected)
    .map(|(what, found, expected)| {
        format!(
            "{what} [{}] where the model has [{}] ({})",
            found.join(", "),
            expected.join(", "),
            name_differences(&expected, found)
        )
    })
    .collect::<Vec<_>>();
    Err(SurrogateError::FeatureMismatch {
        detail: format!(
            "the samples of {} have {}",
            samples.source_name,
            differences.join(", and ")
        ),
    })
}
