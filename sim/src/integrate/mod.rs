//! Time stepping: the automatic time step, the system in time and its three steppers
//! (velocity Verlet, backward Euler, the Brownian midpoint step) with their blow-up checks.

mod backward_euler;
pub mod brownian_limits;
mod brownian_midpoint;
pub mod implicit_dissipation;
mod midpoint_arrays;
pub mod pass_times;
pub mod simulation;
pub mod stage_timers;
mod stepper;
mod thermal_kicks;
pub mod timestep;
mod verlet;
