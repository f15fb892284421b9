//! Files a run writes: the binned table, the summary, frames, and checkpoints.

pub mod checkpoint;
pub mod element_symbol;
pub mod extended_xyz;
pub mod file_lock;
pub mod frame_writer;
pub mod gsd;
pub mod lammps_dump;
pub mod result_files;
pub mod run_summary;
pub mod snapshot_cell;
pub mod snapshot_columns;
pub mod snapshot_format;
