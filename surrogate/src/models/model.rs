//! A trained mapping: an XGBoost booster on min-max scaled outputs, plus the sidecar that says
//! how to use it (`<mapping>.meta.json` next to `<mapping>.json`).

use std::path::Path;

use ndarray::{Array2, ArrayView2};

use crate::data::dataset::Dataset;
use crate::data::files;
use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::data::scaling::MinMaxScaling;
use crate::data::training_domain::TrainingDomain;
use crate::error::{name_differences, Result, SurrogateError};
use crate::models::booster::{xgboost_version, Booster, HyperParameters, Objective};
use crate::models::intervals::{
    load_intervals, tree_targets, IntervalCalibration, Intervals, ModelIntervals, QUANTILE_LEVELS,
};
use crate::models::metrics::relative_l2_error;
use crate::models::model_meta::{ModelMeta, ModelPaths, TrainingData};
use crate::rheology::backbone::Backbone;

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
        let (meta, booster, domain) =
            crate::models::bundle::load_bundle(dir, name, read, |_| None)?;
        let intervals = load_intervals(dir, &meta, read, |b| (b.n_features(), b.n_outputs()))?;
        Ok(TrainedModel {
            meta,
            booster,
            domain,
            intervals,
        })
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
