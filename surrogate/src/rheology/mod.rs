//! Stage 2, rheology and its statistics: the local rheology fitted on the training rows
//! (the backbone whose residual the trees learn), the jamming law of homogeneous shear and
//! its flow-curve fits, the flow curves by state (means over seeds, per-state fits, the
//! Green-Kubo combination and the bootstrap of the jamming law within the points' errors), the local viscosity of inhomogeneous flows in bands of phi_loc, one Brent minimisation for both fits, the ensemble statistics
//! of replicated runs and the z-score agreement of two profiles.

pub mod agreement;
pub mod backbone;
pub mod brent;
pub mod ensemble;
pub mod flow_curve_fit;
pub mod flow_curves;
pub mod jamming_bootstrap;
pub mod jamming_law;
pub mod local_rheology;
pub mod local_viscosity;
pub mod relaxation_fit;
pub mod statistics;
