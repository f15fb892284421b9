//! Stage 4, validation: cross-validation by simulation and by profile family, the error
//! against the number of families trained on, the choice of
//! hyper-parameters, linear baselines, the error on unseen flow profiles and the rows
//! printed from it, the overlap of validation and training rows, the relative L2 error of
//! a profile against a reference, and the timings of prediction and training.

pub mod baselines;
pub mod comparison;
pub mod cross_validation;
pub mod family_cv;
pub mod family_cv_study;
pub mod family_folds;
pub mod family_learning_curve;
pub mod interval_calibration;
pub mod profile_error;
pub mod profile_rows;
pub mod target_noise;
pub mod timing;
pub mod training_overlap;
pub mod tuning;
pub mod unseen_profiles;
