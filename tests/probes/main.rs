//! Regression probes of issue 55 ("nothing lost, nothing silent, third pass"), one module
//! per class of the issue; the cases and their outcomes before and after are listed in
//! `tests/probes/CASES.md` (third part).
#[path = "../common/mod.rs"]
mod common;

mod lifecycle;
mod limits;
mod locks;
mod nothing;
mod unclear;
mod validity;
mod writers;

use std::path::{Path, PathBuf};

/// `scene` (TOML text) written as `name.toml` in `dir`.
pub fn scene_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Whether a command failed with an error saying `text` (not a panic, exit status 101, nor
/// a signal).
pub fn refused_with(out: &std::process::Output, text: &str) -> bool {
    let stderr = common::stderr(out);
    matches!(out.status.code(), Some(c) if c != 0 && c != 101)
        && stderr.contains(text)
        && !stderr.contains("panicked")
}
