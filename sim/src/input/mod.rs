//! What a run starts from: scene files and their validation, grids of scenes and their
//! replicas, the streaming flow profile u_inf(y), and the initial random packing.

pub mod composition;
pub mod flow_profile;
pub mod grid;
pub mod initial_state;
pub mod integrator;
pub mod memory_estimate;
pub mod packing;
pub mod profile_syntax;
pub mod replica_seeds;
pub mod run_cost;
pub mod scene;
pub mod scene_checks;
pub mod scene_file;
pub mod scene_limits;
pub mod thermal_scales;
