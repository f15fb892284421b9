//! Time stepping: the automatic time step and the steps (implicit and velocity Verlet) with
//! their blow-up checks.

pub mod brownian_limits;
pub mod implicit_dissipation;
pub mod pass_times;
pub mod simulation;
pub mod stage_timers;
pub mod timestep;
