//! Time stepping: the particle arrays, the periodic box, the automatic time step and the
//! steps (implicit and velocity Verlet) with their blow-up checks.

pub mod implicit_dissipation;
pub mod integrator;
pub mod particle_ranges;
pub mod particles;
pub mod pass_times;
pub mod periodic_box;
pub mod simulation;
pub mod stage_timers;
pub mod timestep;
