//! Steady profiles from the forcing alone (docs/physics.md): the momentum balance of the
//! binned suspension, closed by a local-rheology law, by a learned mapping
//! (J, Delta_v, phi) -> (phi_loc, mu), or nonlocally by the learned mapping
//! (J, Theta, phi) -> (phi_loc, mu) with Theta from its own balance, solved by damped Newton
//! iterations.
//!
//! A [`ProfileProblem`] is built from a scene ([`ProfileProblem::from_scene`]: the forcing at
//! the bin centres and the drag coefficient of the particle mix); [`ProfileProblem::solve`]
//! takes a [`Closure`] (a [`LearnedClosure`], a [`NonlocalClosure`] with its
//! [`ThetaBalance`] fitted by [`ThetaBalance::fit`], or a `LocalRheology`, fitted on a dataset
//! by [`fit_local_rheology`]) and returns a [`ProfileSolution`], which a [`SolvedProfile`]
//! writes as `profile.csv` beside its [`SolveSummary`].

pub mod band_calibration;
pub mod bands;
pub mod closure;
pub mod closure_kind;
pub mod closures;
pub mod error;
pub mod local_fit;
pub mod newton;
pub mod problem;
pub mod proposal;
pub mod smoothing;
pub mod solution;
pub mod solved_profile;
pub mod theta_balance;
pub mod training;

pub use band_calibration::{calibrate_bands, ShippedModel};
pub use bands::{BandCalibration, BandScales, ClosureBands, ProfileBands, BANDED};
pub use closure::{
    Closure, ClosureInterval, Descriptor, ExtremumClosure, LearnedClosure, NonlocalClosure,
};
pub use closure_kind::ClosureKind;
pub use closures::{Bands, Closures};
pub use error::{Result, SolverError, Stall};
pub use local_fit::fit_local_rheology;
pub use newton::TOLERANCE;
pub use problem::ProfileProblem;
pub use proposal::{Candidate, Outcome, Proposal};
pub use smoothing::{EXTREMUM_SMOOTHING_FLOOR, SMOOTHING};
pub use solution::ProfileSolution;
pub use solved_profile::{BandSummary, SolveSummary, SolvedProfile};
pub use theta_balance::{ThetaBalance, ThetaBalanceFit};
pub use training::{
    BandsOutcome, BandsSummary, ClosureSummary, IntervalSummary, ParamsSource, TrainedMapping,
    TrainingEvent, TrainingJob, TrainingResult, TuningSummary,
};
