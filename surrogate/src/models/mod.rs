//! Stage 3, the models: XGBoost boosters trained on samples, saved with their sidecar, read
//! back as predictors that walk the trees themselves; the relative L2 error (eq 6.6).

pub mod booster;
pub mod bundle;
pub(crate) mod f32_input;
pub mod forest;
pub mod intervals;
pub mod metrics;
pub mod model;
pub mod model_meta;
pub mod prediction_table;
pub mod predictor;
pub(crate) mod xgboost_json;
