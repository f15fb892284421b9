//! Atomic JSON files: checkpoints and results are written to a temporary file in the
//! same directory and renamed, so a reader never sees a half-written file.
use crate::error::SimError;
use serde::{de::DeserializeOwned, Serialize};
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically (temporary file, fsync, rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SimError> {
    let err = |e: std::io::Error| SimError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    let mut f = std::fs::File::create(&tmp).map_err(err)?;
    f.write_all(bytes).map_err(err)?;
    f.sync_all().map_err(err)?;
    std::fs::rename(&tmp, path).map_err(err)
}

/// Saves `state` as JSON at `path` (floats round-trip exactly).
pub fn save<T: Serialize>(path: &Path, state: &T) -> Result<(), SimError> {
    let bytes = serde_json::to_vec(state).map_err(|e| SimError::Checkpoint {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    write_atomic(path, &bytes)
}

/// Loads a state saved by [`save`].
pub fn load<T: DeserializeOwned>(path: &Path) -> Result<T, SimError> {
    let err = |m: String| SimError::Checkpoint {
        path: path.display().to_string(),
        message: m,
    };
    let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
    serde_json::from_slice(&bytes).map_err(|e| err(format!("not a readable checkpoint: {e}")))
}
