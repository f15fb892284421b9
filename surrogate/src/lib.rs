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
//! The modules sit in four stage folders, each importing only from earlier ones (and from
//! [`error`]): [`data`], [`rheology`] (the backbone, the jamming law, ensemble statistics), [`models`], [`validation`].
//!
//! The XGBoost library is the pinned `xgboost-cpu` wheel's `libxgboost.so`, provided by the
//! workspace's `vendor/xgboost_lib-sys` crate; see its build script.

pub mod data;
pub mod error;
pub mod models;
pub mod rheology;
pub mod validation;

pub use data::dataset::{Dataset, GROUP_COLUMN, PROFILE_COLUMN};
pub use data::extremum_distance::{
    distance_to_nearest, extremum_distances, shear_zero_faces, shear_zeros, ShearZero,
};
pub use data::mapping::{Mapping, MAPPINGS};
pub use data::physical_range::{clip_to_physical_range, physical_range, PHI_LOC_MAX};
pub use data::samples::Samples;
pub use data::scaling::{MinMaxScaling, Range};
pub use data::table_kind::TableKind;
pub use data::training_domain::{DomainCheck, TrainingDomain};
pub use error::{Result, SurrogateError};
pub use models::booster::{xgboost_version, Booster, HyperParameters, MultiStrategy, Objective};
pub use models::forest::Forest;
pub use models::intervals::{
    check_level, conformal_quantile, noise_quantile, widen, CalibrationRows, IntervalCalibration,
    Intervals, ModelIntervals, DEFAULT_LEVEL, QUANTILE_LEVELS,
};
pub use models::metrics::relative_l2_error;
pub use models::model::TrainedModel;
pub use models::model_meta::{ModelMeta, TrainingData};
pub use models::prediction_table::PredictionTable;
pub use models::predictor::{Prediction, Predictor};
pub use rheology::agreement::{agreement, Agreement};
pub use rheology::ensemble::{build_ensemble, Ensemble, EnsembleSummary, ObservableSummary};
pub use rheology::flow_curve_fit::{bin_viscosity, FlowCurvePoint, SeededJammingFit};
pub use rheology::flow_curves::{
    green_kubo_at, green_kubo_matches, green_kubo_points, keep_green_kubo_at_lowest_peclet,
    over_seeds, part_viscosity, seed_mean, state_rows, states, volume_fractions, Curve, State,
    StateFits, StatePoint, StateRow, StepSetting, CONVENTIONS,
};
pub use rheology::jamming_bootstrap::{JammingBootstrap, PointWithError, Quantiles};
pub use rheology::jamming_law::{
    JammingLaw, MIN_VOLUME_FRACTIONS, PHI_J_MAX, SEEDS_LAW, SEEDS_LOW_PECLET_PHI_J,
};
pub use rheology::local_rheology::LocalRheology;
pub use rheology::statistics::{mean_and_standard_error, median, DescriptorStats};
pub use schema::excerpt;
pub use validation::baselines::{evaluate_baseline, Baseline, BaselineScore};
pub use validation::comparison::{compare_contenders, ComparisonRow, Contender};
pub use validation::cross_validation::{
    cross_validate, grid_search, grouped_k_fold, leave_one_group_out, CvScore, Fold, GridSearch,
    HyperParameterGrid,
};
pub use validation::family_cv::{
    FamilyCv, FoldErrors, MeanErrors, RowErrors, Variant, VariantErrors, VariantSummary,
};
pub use validation::family_cv_study::{CvProgress, CvSettings, FamilyCvStudy};
pub use validation::family_folds::{
    family_names, leave_one_family_out, tuning_folds, FamilyFold, LeftOut, MIN_TUNING_FAMILIES,
};
pub use validation::family_learning_curve::{CurveCost, LearningCurve, LearningPoint};
pub use validation::interval_calibration::{
    fraction, interval_score, FoldCoverage, IntervalCoverage, IntervalMethod, IntervalStudy,
    MethodCoverage, OutputCoverage,
};
pub use validation::profile_error::{model_errors, relative_l2};
pub use validation::profile_rows::{gain_shares, records, theta_vs_dv, Lower, Record, ThetaVsDv};
pub use validation::target_noise::{beyond_noise, output_standard_errors, target_noise};
pub use validation::timing::{time_mapping, timed_fit, Timing, FITS};
pub use validation::training_overlap::{overlap_warning, training_samples};
pub use validation::tuning::{standard_grid, Tuning};
pub use validation::unseen_profiles::{
    profile_names, seeds_validation_error, ProfileError, Validation, ALL_PROFILES, IN_DOMAIN,
    OUT_OF_DOMAIN,
};
