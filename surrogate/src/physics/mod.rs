//! Stage 2, the physics backbone: the local rheology fitted on the training rows, whose
//! residual the trees learn.

pub mod backbone;
pub mod local_rheology;
