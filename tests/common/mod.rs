//! Helpers shared by the end-to-end tests of the `suspflow` command (`mod common;` in each
//! test file).
// Each test file is a crate of its own that uses only some of these.
#![allow(dead_code)]
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The workspace root, where `suspflow` runs (the paths of shipped scenes and grids are
/// relative to it).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs `suspflow args` in the workspace root.
pub fn suspflow(args: &[&str]) -> Output {
    suspflow_with_env(args, &[])
}

/// Runs `suspflow args` in the workspace root with the environment variables `env` set.
pub fn suspflow_with_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_suspflow"))
        .args(args)
        .envs(env.iter().copied())
        .current_dir(root())
        .output()
        .expect("runs suspflow")
}

/// The command's standard error as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Fails the test with the command's standard error unless it succeeded.
pub fn assert_ok(out: &Output) {
    assert!(out.status.success(), "{}", stderr(out));
}

/// A fresh empty directory for one test, named after the test file, `name` and this
/// process.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "suspflow-{}-{name}-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A path as an argument.
pub fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The header and the rows of cells of CSV `text`.
pub fn csv_table(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header = reader.headers().unwrap().iter().map(String::from).collect();
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// The header and the rows of cells of the CSV file at `path`.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    csv_table(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}

/// The cells of column `name` in CSV `text`.
pub fn csv_column(text: &str, name: &str) -> Vec<String> {
    let (header, rows) = csv_table(text);
    let k = header
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    rows.into_iter().map(|mut row| row.swap_remove(k)).collect()
}

/// The cells of column `name` in CSV `text`, as numbers.
pub fn numbers(text: &str, name: &str) -> Vec<f64> {
    csv_column(text, name)
        .iter()
        .map(|c| c.parse().unwrap())
        .collect()
}
