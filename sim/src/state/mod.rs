//! The system's state, the floor every stage stands on: 3-vectors, the particle arrays,
//! the periodic box, and the contiguous particle ranges the parallel passes split the
//! arrays into. Nothing here imports from a stage.

pub mod particle_ranges;
pub mod particles;
pub mod periodic_box;

/// Small 3-vectors (units of a, a/time, ...).
pub type Vec3 = nalgebra::Vector3<f64>;
