//! Gradient-boosted trees: the only module that talks to XGBoost.
//!
//! Training, multi-output prediction and JSON save/load go through the `xgb` crate; the
//! library version comes straight from the C API (`xgboost_lib-sys`). Feature importance is
//! read from the model's JSON by [`Forest`].
//! Several outputs are learnt by one booster: the labels are passed as a row-major
//! rows x outputs array, and [`MultiStrategy`] says how trees are shared among the outputs.

use std::fmt;
use std::path::Path;

use ndarray::{Array2, ArrayView2};
use serde::{Deserialize, Serialize};

use crate::data::files;
use crate::error::{Result, SurrogateError};
use crate::models::f32_input::{prediction_input, to_f32};
use crate::models::forest::Forest;
use crate::models::xgboost_json::{LoaderJson, ShapeJson};

/// How a booster with several outputs grows its trees (XGBoost's `multi_strategy`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MultiStrategy {
    /// One tree per output per boosting round (XGBoost's default).
    #[default]
    OneOutputPerTree,
    /// One tree per round with a vector of outputs in each leaf.
    MultiOutputTree,
}

impl MultiStrategy {
    fn as_xgboost(self) -> &'static str {
        match self {
            MultiStrategy::OneOutputPerTree => "one_output_per_tree",
            MultiStrategy::MultiOutputTree => "multi_output_tree",
        }
    }
}

/// Training settings. The objective is `reg:squarederror` (thesis eq 6.5) for the models
/// themselves and `reg:quantileerror` for their intervals' quantile trees ([`Objective`]), the
/// tree method `hist`. Defaults are XGBoost's own, as the thesis trained without tuning, except
/// `nthread`, which is 1 so that training is reproducible and leaves the other core free.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HyperParameters {
    /// Number of boosting rounds.
    pub n_estimators: u32,
    pub max_depth: u32,
    /// Shrinkage of each tree's contribution (XGBoost's `eta`).
    pub learning_rate: f64,
    /// Fraction of rows sampled for each tree.
    pub subsample: f64,
    /// Fraction of features sampled for each tree.
    pub colsample_bytree: f64,
    /// Minimum sum of instance weight (hessian) in a child.
    pub min_child_weight: f64,
    /// L2 regularisation of leaf weights.
    pub lambda: f64,
    /// L1 regularisation of leaf weights.
    pub alpha: f64,
    /// Minimum loss reduction to split a node.
    pub gamma: f64,
    /// Number of histogram bins per feature.
    pub max_bin: u32,
    pub multi_strategy: MultiStrategy,
    pub seed: u32,
    /// Number of threads; 0 means all cores.
    pub nthread: u32,
    /// Whether the trees learn the residual of the local-rheology backbone
    /// ([`crate::rheology::local_rheology`]) instead of the outputs themselves. Not an XGBoost
    /// setting: it changes what the trees are trained on.
    #[serde(default)]
    pub backbone: bool,
}

impl Default for HyperParameters {
    fn default() -> Self {
        HyperParameters {
            n_estimators: 100,
            max_depth: 6,
            learning_rate: 0.3,
            subsample: 1.0,
            colsample_bytree: 1.0,
            min_child_weight: 1.0,
            lambda: 1.0,
            alpha: 0.0,
            gamma: 0.0,
            max_bin: 256,
            multi_strategy: MultiStrategy::default(),
            seed: 0,
            nthread: 1,
            backbone: false,
        }
    }
}

/// What the trees minimise.
#[derive(Debug, Clone, PartialEq)]
pub enum Objective {
    /// The squared error (thesis eq 6.5): the trees predict the mean.
    SquaredError,
    /// The pinball loss at each of these levels (XGBoost's `reg:quantileerror` with
    /// `quantile_alpha`): one output per level, the conditional quantile, of a single label.
    Quantiles(Vec<f64>),
}

impl Objective {
    fn as_xgboost_params(&self) -> Vec<(&'static str, String)> {
        match self {
            Objective::SquaredError => vec![("objective", "reg:squarederror".to_owned())],
            Objective::Quantiles(levels) => vec![
                ("objective", "reg:quantileerror".to_owned()),
                (
                    "quantile_alpha",
                    format!(
                        "[{}]",
                        levels
                            .iter()
                            .map(f64::to_string)
                            .collect::<Vec<_>>()
                            .join(",")
                    ),
                ),
            ],
        }
    }
}

impl HyperParameters {
    /// The settings as XGBoost parameter names and values, the objective apart.
    fn as_xgboost_params(&self) -> Vec<(&'static str, String)> {
        vec![
            ("tree_method", "hist".to_owned()),
            // The middle of the min-max scaled range [0, 1].
            ("base_score", "0.5".to_owned()),
            ("max_depth", self.max_depth.to_string()),
            ("eta", self.learning_rate.to_string()),
            ("subsample", self.subsample.to_string()),
            ("colsample_bytree", self.colsample_bytree.to_string()),
            ("min_child_weight", self.min_child_weight.to_string()),
            ("lambda", self.lambda.to_string()),
            ("alpha", self.alpha.to_string()),
            ("gamma", self.gamma.to_string()),
            ("max_bin", self.max_bin.to_string()),
            (
                "multi_strategy",
                self.multi_strategy.as_xgboost().to_owned(),
            ),
            ("seed", self.seed.to_string()),
            ("nthread", self.nthread.to_string()),
        ]
    }
}

/// A trained XGBoost model mapping `n_features` inputs to `n_outputs` outputs.
pub struct Booster {
    inner: xgb::Booster,
    n_features: usize,
    n_outputs: usize,
    /// Feature names stored in the model (empty if none were).
    feature_names: Vec<String>,
}

impl fmt::Debug for Booster {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Booster")
            .field("n_features", &self.n_features)
            .field("n_outputs", &self.n_outputs)
            .finish_non_exhaustive()
    }
}

impl From<xgb::XGBError> for SurrogateError {
    fn from(e: xgb::XGBError) -> Self {
        let message = e.to_string();
        let message = message.strip_prefix("XGBoost error: ").unwrap_or(&message);
        // The library appends its C++ stack trace ("Stack trace:\n  [bt] (0) ..."), which says
        // nothing to a user; the first lines are its message.
        let message = message.split("Stack trace:").next().unwrap_or(message);
        SurrogateError::Xgboost(message.trim_end().to_owned())
    }
}

impl Booster {
    /// Trains on `features` (rows x features) to predict `labels` (rows x outputs), with
    /// `feature_names` stored in the model (Python's xgboost shows them), minimising the
    /// squared error.
    pub fn train(
        features: ArrayView2<f64>,
        labels: ArrayView2<f64>,
        feature_names: &[&str],
        params: &HyperParameters,
    ) -> Result<Self> {
        Self::train_for(
            features,
            labels,
            feature_names,
            params,
            &Objective::SquaredError,
        )
    }

    /// [`Booster::train`] with `objective`; [`Objective::Quantiles`] takes one label column
    /// and predicts one output per level.
    pub fn train_for(
        features: ArrayView2<f64>,
        labels: ArrayView2<f64>,
        feature_names: &[&str],
        params: &HyperParameters,
        objective: &Objective,
    ) -> Result<Self> {
        let n_outputs = match objective {
            Objective::SquaredError => labels.ncols(),
            Objective::Quantiles(levels) => {
                if labels.ncols() != 1
                    || levels.is_empty()
                    || levels.iter().any(|l| !(*l > 0.0 && *l < 1.0))
                {
                    return Err(SurrogateError::InvalidArgument(format!(
                        "quantile trees take one label column and levels in (0, 1); got {} \
                         column(s) and levels {levels:?}",
                        labels.ncols()
                    )));
                }
                levels.len()
            }
        };
        if features.nrows() == 0 {
            return Err(SurrogateError::EmptyDataset {
                what: "the training set".to_owned(),
            });
        }
        if labels.nrows() != features.nrows() || labels.ncols() == 0 {
            return Err(SurrogateError::ShapeMismatch {
                what: "training labels (one row per feature row)".to_owned(),
                expected: (features.nrows(), labels.ncols().max(1)),
                found: labels.dim(),
            });
        }
        if feature_names.len() != features.ncols()
            || feature_names.iter().any(|name| name.contains('\0'))
        {
            return Err(SurrogateError::InvalidArgument(format!(
                "need {} feature names without NUL characters, got {feature_names:?}",
                features.ncols()
            )));
        }
        let mut dtrain = xgb::DMatrix::from_dense(
            &to_f32(features, "training features", feature_names)?,
            features.nrows(),
        )?;
        // Row-major rows x outputs: XGBoost takes the number of targets from the label count.
        dtrain.set_labels(&to_f32::<&str>(labels, "training labels", &[])?)?;
        // `xgb` first applies its own parameter defaults; every setting that matters is
        // overridden right after.
        let mut inner = xgb::Booster::new_with_cached_dmats(&Default::default(), &[&dtrain])?;
        for (name, value) in objective
            .as_xgboost_params()
            .into_iter()
            .chain(params.as_xgboost_params())
        {
            inner.set_param(name, &value)?;
        }
        inner.set_feature_names(&feature_names.to_vec())?;
        for round in 0..params.n_estimators {
            // XGBoost counts rounds with a C int; more than i32::MAX rounds is not a real case.
            inner.update(&dtrain, i32::try_from(round).unwrap_or(i32::MAX))?;
        }
        Ok(Booster {
            inner,
            n_features: features.ncols(),
            n_outputs,
            feature_names: feature_names.iter().map(|&n| n.to_owned()).collect(),
        })
    }

    /// Number of input features.
    pub fn n_features(&self) -> usize {
        self.n_features
    }

    /// Number of outputs.
    pub fn n_outputs(&self) -> usize {
        self.n_outputs
    }

    /// Predictions (rows x outputs) for `features` (rows x features).
    pub fn predict(&self, features: ArrayView2<f64>) -> Result<Array2<f64>> {
        let values = prediction_input(features, self.n_features, &self.feature_names)?;
        let n_rows = features.nrows();
        if n_rows == 0 {
            return Ok(Array2::zeros((0, self.n_outputs)));
        }
        let dmatrix = xgb::DMatrix::from_dense(&values, n_rows)?;
        let config = xgb::PredictConfig {
            strict_shape: true,
            ..Default::default()
        };
        let (values, shape) = self.inner.predict_matrix(&dmatrix, &config.as_json())?;
        if shape != [n_rows as u64, self.n_outputs as u64] {
            return Err(SurrogateError::Xgboost(format!(
                "prediction has shape {shape:?}, expected [{n_rows}, {}]",
                self.n_outputs
            )));
        }
        Array2::from_shape_vec(
            (n_rows, self.n_outputs),
            values.into_iter().map(f64::from).collect(),
        )
        .map_err(|e| {
            SurrogateError::Xgboost(format!("prediction buffer does not match its shape: {e}"))
        })
    }

    /// Writes the model in XGBoost's JSON format, loadable by Python's `xgboost.Booster`.
    pub fn save_json(&self, path: &Path) -> Result<()> {
        files::write(path, &self.to_json()?)
    }

    /// Reads a model written by [`Booster::save_json`] (or by XGBoost itself, in JSON). The
    /// loaded booster predicts on one thread: inputs here are profiles of tens of rows, for
    /// which starting a team of threads costs more than it saves.
    pub fn load_json(path: &Path) -> Result<Self> {
        Self::from_json(&files::read(path)?, path)
    }

    /// [`Booster::load_json`] of the bytes read from `path`. The file is checked before
    /// XGBoost sees it ([`LoaderJson`]: JSON, the fields and node arrays its loader reads),
    /// so that a truncated or edited file is named with what is wrong rather than met by the
    /// library's exception.
    pub fn from_json(json: &[u8], path: &Path) -> Result<Self> {
        let unreadable = |detail: String| SurrogateError::UnreadableFile {
            path: path.to_path_buf(),
            detail,
        };
        let shape: ShapeJson = files::parse_json(path, json, "an XGBoost JSON model")?;
        let loader: LoaderJson = files::parse_json(path, json, "an XGBoost JSON model")?;
        if let Some(problem) = loader.problem() {
            return Err(unreadable(format!(
                "is not a whole XGBoost tree model: {problem}"
            )));
        }
        let (n_features, n_outputs) = shape
            .learner
            .learner_model_param
            .counts(&path.display().to_string())?;
        let feature_names = shape.learner.feature_names;
        let mut inner = xgb::Booster::load_buffer(json)?;
        inner.set_param("nthread", "1")?;
        Ok(Booster {
            inner,
            n_features,
            n_outputs,
            feature_names,
        })
    }

    /// Feature names stored in the model, in input order (empty if none were).
    pub fn feature_names(&self) -> &[String] {
        &self.feature_names
    }

    /// XGBoost's "gain" importance of each feature (see [`Forest::feature_importance_gain`]).
    pub fn feature_importance_gain(&self) -> Result<Vec<f64>> {
        Ok(Forest::from_json(&self.to_json()?, "the model's own JSON")?.feature_importance_gain())
    }

    /// The model as XGBoost JSON bytes.
    pub(crate) fn to_json(&self) -> Result<Vec<u8>> {
        let mut json = self.inner.save_buffer(false)?;
        // The C API may count a terminating NUL in the length.
        if json.last() == Some(&0) {
            json.pop();
        }
        Ok(json)
    }
}

/// Version of the linked XGBoost library, e.g. "3.2.0".
pub fn xgboost_version() -> String {
    let (mut major, mut minor, mut patch) = (0, 0, 0);
    // SAFETY: XGBoostVersion only writes one int through each of the three valid pointers.
    unsafe { xgboost_lib_sys::XGBoostVersion(&mut major, &mut minor, &mut patch) };
    format!("{major}.{minor}.{patch}")
}
