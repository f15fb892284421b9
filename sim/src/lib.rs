//! Particle simulator for dense non-Brownian suspensions under inhomogeneous flow.
//! Physics: `../shared/SPEC.md`; equation numbers are the thesis' (chapters 3 and 6).
//!
//! Data flow: [`scene::Scene`] -> [`run::initial_particles`] -> [`simulation::Simulation`]
//! (neighbours, pair laws, one-body laws, velocity Verlet) -> [`snapshot`] sums ->
//! [`profile::Profile`] -> [`output`].

/// Small 3-vectors (units of a, a/time, ...).
pub type Vec3 = nalgebra::Vector3<f64>;

pub mod binning;
pub mod block_sums;
pub mod cell_list;
pub mod checkpoint;
pub mod contact;
pub mod drag;
pub mod error;
pub mod flow_profile;
pub mod force_accumulation;
pub mod force_field;
pub mod grid;
pub mod lubrication;
pub mod memory_estimate;
pub mod output;
pub mod packing;
pub mod pair_load;
pub mod particles;
pub mod periodic_box;
pub mod profile;
pub mod profile_syntax;
pub mod run;
pub mod scene;
pub mod scene_name;
pub mod simulation;
pub mod snapshot;
pub mod stage_timers;
pub mod steady_state;
pub mod timestep;
pub mod verlet_list;

pub use error::SimError;

/// Version of the code that produced a result: package version, commit, and `-dirty` when
/// the working tree had uncommitted changes at build time (see `build.rs`).
pub const CODE_VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("SUSPFLOW_COMMIT"));
