//! File access that names the file in every error.

use std::path::Path;

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::error::{Result, SurrogateError};

/// The bytes of the file at `path`.
pub(crate) fn read(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| SurrogateError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes `bytes` to `path`, replacing any file there.
pub(crate) fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).map_err(|source| SurrogateError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Creates the directory `path` and its missing parents.
pub(crate) fn create_dir_all(path: &Path) -> Result<()> {
    std::fs::create_dir_all(path).map_err(|source| SurrogateError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// `bytes`, read from `path`, parsed as JSON.
pub(crate) fn parse_json<T: DeserializeOwned>(path: &Path, bytes: &[u8]) -> Result<T> {
    serde_json::from_slice(bytes).map_err(|source| SurrogateError::Json {
        path: path.to_path_buf(),
        source,
    })
}

/// The file at `path` parsed as JSON.
pub(crate) fn read_json<T: DeserializeOwned>(path: &Path) -> Result<T> {
    parse_json(path, &read(path)?)
}

/// Writes `value` to `path` as indented JSON.
pub(crate) fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<()> {
    let json = serde_json::to_vec_pretty(value).map_err(|source| SurrogateError::Json {
        path: path.to_path_buf(),
        source,
    })?;
    write(path, &json)
}
