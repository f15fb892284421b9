//! Checkpoints: the state of a run as JSON (floats round-trip exactly), written atomically.
use crate::error::SimError;
use schema::write_atomic;
use serde::{de::DeserializeOwned, Serialize};
use std::path::Path;

/// Saves `state` as JSON at `path` (floats round-trip exactly).
pub fn save<T: Serialize>(path: &Path, state: &T) -> Result<(), SimError> {
    let bytes = serde_json::to_vec(state).map_err(|e| SimError::Checkpoint {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(write_atomic(path, &bytes)?)
}

/// Loads a state saved by [`save`].
pub fn load<T: DeserializeOwned>(path: &Path) -> Result<T, SimError> {
    let err = |m: String| SimError::CheckpointUnusable {
        path: path.display().to_string(),
        message: m,
    };
    let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
    serde_json::from_slice(&bytes).map_err(|e| err(format!("not a readable checkpoint: {e}")))
}
