//! `suspflow`: the command-line package of the workspace. The physics lives in the `sim`
//! crate (particle simulator) and the surrogate models in `surrogate`; this crate holds one
//! module per command (`commands`), the report sections (`report`), the figures (`plots`) and
//! the helpers the commands share. Physics notes: `docs/physics.md`.

pub mod commands;
mod cv_sections;
mod ensemble_table;
pub mod exit_status;
mod interrupt;
mod output_guard;
mod plots;
mod progress;
mod report;
mod surrogate_text;
mod threads;

/// Version of the code that produced a result: package version, commit, and `-dirty` when
/// the working tree had uncommitted changes at build time (see `build/stamp.rs`).
pub const CODE_VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("SUSPFLOW_COMMIT"));

/// A fresh directory for one unit test: `suspflow-<name>-<pid>` in the system's temporary
/// folder (created; emptied if an earlier run left it).
#[cfg(test)]
fn test_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("suspflow-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
