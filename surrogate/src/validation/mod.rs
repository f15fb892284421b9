//! Stage 4, validation: cross-validation by simulation and by profile family, the choice of
//! hyper-parameters, linear baselines, and the error on unseen flow profiles.

pub mod baselines;
pub mod comparison;
pub mod cross_validation;
pub mod family_cv;
pub mod family_folds;
pub mod tuning;
pub mod unseen_profiles;
