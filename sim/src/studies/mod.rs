//! Studies above the run: each drives scenes through [`crate::run`] and measures what the
//! runs did. [`run_length`] samples one run for the study of statistical error against run
//! length, [`convergence`] measures that error and the run length a target error needs, and
//! [`stability_sweep`] runs stiff and extreme cases to see which ones stay stable;
//! [`benchmark`] and [`brownian_benchmark`] time the step on the LAMMPS peers' scenes.

pub mod benchmark;
pub mod brownian_benchmark;
pub mod convergence;
pub mod equilibrium;
pub mod run_length;
pub mod stability_sweep;
