//! From particles to local observables: bins along y, per-snapshot sums, time averages with
//! standard errors, the box totals of homogeneous shear, and the steady-state test.

pub mod bin_averages;
pub mod binning;
pub mod block_sums;
pub mod convention_effects;
pub mod conventions;
pub mod green_kubo;
pub mod local_velocity;
pub mod periodic_derivative;
pub mod scene_binning;
pub mod shear_rheology;
pub mod snapshot;
pub mod species_temperatures;
pub mod steady_state;
pub mod stress_checks;
pub mod stress_parts;
