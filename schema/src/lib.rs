//! The schema of suspflow's tables, with no dependencies: the simulator that writes them,
//! the surrogate that learns from them and the commands that read them take the column
//! names and their order from here ([`columns`]), and index the observables by
//! [`Observable`].

pub mod columns;
pub mod observable;

pub use observable::Observable;
