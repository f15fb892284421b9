//! Time stepping: the particle arrays, the periodic box, the automatic time step and the
//! velocity-Verlet step with its blow-up checks.

pub mod particles;
pub mod periodic_box;
pub mod simulation;
pub mod stage_timers;
pub mod timestep;
