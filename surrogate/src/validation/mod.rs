//! Stage 4, validation: cross-validation by simulation and by profile family, the choice of
//! hyper-parameters, linear baselines, the error on unseen flow profiles and the rows
//! printed from it, and the overlap of validation and training rows.

pub mod baselines;
pub mod comparison;
pub mod cross_validation;
pub mod family_cv;
pub mod family_folds;
pub mod profile_rows;
pub mod training_overlap;
pub mod tuning;
pub mod unseen_profiles;
