//! Particle simulator for dense non-Brownian suspensions under inhomogeneous flow.
//! Physics: `docs/physics.md` in the repository; equation numbers are the thesis' (chapters
//! 3 and 6).
//!
//! Data flow, one folder per stage, each importing only from the stages before it:
//! [`state`] (the floor: [`Vec3`], the particle arrays, the periodic box, the particle
//! ranges) -> [`input`] (scene file -> [`Scene`], grids of scenes, the flow profile
//! u_inf(y), the initial packing) -> [`neighbours`] (cell and Verlet lists) -> [`forces`]
//! (contact, drag, lubrication, summed over the list) -> [`integrate`] (the [`Simulation`]
//! and its time step) -> [`sampling`] (bins, snapshot sums, [`BinAverages`], steady state)
//! -> [`output`] (tables, summary, frames, checkpoints); [`run`] drives a scene from start
//! to its averaged steady state, and [`studies`] sit above it (error against run length,
//! the stability sweep).
//!
//! One exception, with its reason: the [`Scene`] (in [`input`]) carries the quantities
//! derived from the file once for every stage, and three of them are typed by the stage
//! whose law defines them: the [`TimeStep`] (from the time-step limits of [`integrate`]),
//! the pair repulsion's parameters ([`forces`]) and the observable conventions
//! ([`sampling`]). Moving those types down into `input` would put each law's parameters
//! away from the law.

pub mod error;
pub mod forces;
pub mod input;
pub mod integrate;
pub mod json_numbers;
pub mod neighbours;
pub mod output;
pub mod run;
pub mod sampling;
pub mod state;
pub mod studies;

pub use error::SimError;
pub use input::flow_profile::FlowProfile;
pub use input::grid::{Grid, GridRun};
pub use input::scene::{Scene, SceneFile};
pub use integrate::simulation::Simulation;
pub use integrate::timestep::{DtLimit, TimeStep};
pub use output::run_summary::{RunOutcome, RunSummary};
pub use run::run_folder::RunFolder;
pub use run::RunOptions;
pub use sampling::bin_averages::BinAverages;
pub use state::Vec3;
