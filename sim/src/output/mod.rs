//! Files a run writes: the binned table, the summary, frames, and checkpoints.

pub mod atomic_write;
pub mod checkpoint;
pub mod result_files;
