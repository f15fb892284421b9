//! The schema of suspflow's tables: the simulator that writes them, the surrogate that
//! learns from them and the commands that read them take the column names and their order
//! from here ([`columns`]) and index the observables by [`Observable`]; a per-run table is
//! read and checked by one reader ([`RunTable`]), on which merging and ensembles build;
//! tables are identified by their [`Fingerprint`]; every result file is written whole by
//! one writer ([`write_atomic`]); work is estimated and limited by one rule
//! ([`work_cost`]).

pub mod atomic_write;
pub mod columns;
mod error;
pub mod excerpt;
pub mod fingerprint;
pub mod observable;
pub mod run_rows;
pub mod run_table;
pub mod scene_name;
pub mod work_cost;

pub use atomic_write::write_atomic;
pub use error::{Result, SchemaError};
pub use excerpt::excerpt;
pub use fingerprint::Fingerprint;
pub use observable::Observable;
pub use run_table::{RunKey, RunTable};
