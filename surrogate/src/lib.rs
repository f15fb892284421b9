//! Surrogate models of local rheology (docs/physics.md section 8, thesis section 6.2).
//!
//! Data flow: a CSV [`Dataset`] (one row per bin per simulation) is seen through a
//! [`Mapping`] as [`Samples`] (features, outputs, simulation groups); outputs are min-max
//! scaled to [0, 1] ([`MinMaxScaling`], eq 6.4) and learnt by an XGBoost [`Booster`]
//! (`reg:squarederror`, eq 6.5). A [`TrainedModel`] is that booster plus a sidecar
//! ([`ModelMeta`]) and is saved as `<mapping>.json` (XGBoost JSON, loadable from Python) and
//! `<mapping>.meta.json`; a [`Predictor`] reads both back and predicts without the XGBoost
//! library, walking the trees itself ([`Forest`]). Accuracy is the relative L2 error on
//! scaled outputs ([`relative_l2_error`], eq 6.6), cross-validated by whole simulations
//! ([`grouped_k_fold`]) or by whole profile families ([`leave_one_family_out`]), which also
//! chooses the hyper-parameters ([`Tuning`]), and compared with linear [`baselines`];
//! [`FamilyCv`] compares trees alone, the physics backbone alone and the two together on
//! families left out; [`Validation`] measures a model on unseen flow profiles. Predictions
//! are clipped into each output's [`physical_range`].
//!
//! The XGBoost library is the pinned `xgboost-cpu` wheel's `libxgboost.so`, provided by the
//! workspace's `vendor/xgboost_lib-sys` crate; see its build script.

pub mod backbone;
pub mod baselines;
pub mod booster;
pub mod cross_validation;
pub mod dataset;
pub mod error;
pub mod excerpt;
pub mod family_cv;
pub mod family_folds;
mod files;
mod fingerprint;
pub mod forest;
pub mod local_rheology;
pub mod mapping;
pub mod metrics;
pub mod model;
pub mod physical_range;
pub mod predictor;
pub mod samples;
pub mod scaling;
pub mod table_kind;
pub mod training_domain;
pub mod tuning;
pub mod validation;
mod xgboost_json;

pub use baselines::{evaluate_baseline, Baseline, BaselineScore};
pub use booster::{xgboost_version, Booster, HyperParameters, MultiStrategy};
pub use cross_validation::{
    cross_validate, grid_search, grouped_k_fold, leave_one_group_out, CvScore, Fold, GridSearch,
    HyperParameterGrid,
};
pub use dataset::{Dataset, GROUP_COLUMN, PROFILE_COLUMN};
pub use error::{Result, SurrogateError};
pub use excerpt::excerpt;
pub use family_cv::{
    FamilyCv, FoldErrors, MeanErrors, RowErrors, Variant, VariantErrors, VariantSummary,
};
pub use family_folds::{
    family_names, leave_one_family_out, tuning_folds, FamilyFold, LeftOut, MIN_TUNING_FAMILIES,
};
pub use forest::Forest;
pub use local_rheology::LocalRheology;
pub use mapping::{Mapping, MAPPINGS};
pub use metrics::relative_l2_error;
pub use model::{ModelMeta, TrainedModel, TrainingData};
pub use physical_range::{clip_to_physical_range, physical_range, PHI_LOC_MAX};
pub use predictor::Predictor;
pub use samples::Samples;
pub use scaling::{MinMaxScaling, Range};
pub use table_kind::TableKind;
pub use training_domain::{DomainCheck, TrainingDomain};
pub use tuning::{standard_grid, Tuning};
pub use validation::{
    profile_names, seeds_validation_error, ProfileError, Validation, ALL_PROFILES, IN_DOMAIN,
    OUT_OF_DOMAIN,
};
