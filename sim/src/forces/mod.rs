//! The force laws (docs/physics.md, section Forces): contact springs, Stokes drag,
//! Kim-Karrila lubrication, the short-range repulsion of Brownian scenes, and their
//! accumulation over the neighbour list.

pub mod brownian_shell;
pub mod contact;
pub mod drag;
pub mod force_accumulation;
pub mod force_field;
pub mod lubrication;
pub mod network_loads;
pub mod pair_load;
pub mod range_buffers;
pub mod repulsion;
pub mod resistance_network;
pub mod thermal_noise;
