//! An exclusive lock on an output, so that two writers of one output (two runs into one
//! folder, two batches into one work directory) refuse to share it instead of replacing
//! each other's files. The lock is the operating
//! system's advisory lock on a small file (which holds the owner's process id for the
//! message): it is released when the process ends, however it ends, so a killed run leaves
//! no stale lock behind.
use crate::error::SimError;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::Path;

/// The lock file of an output folder, the same for every writer of one (a run, a
/// Green-Kubo run, a cross-validation, flow curves, a solve), so that no two of them write
/// one folder at once.
pub const FOLDER_LOCK: &str = "run.lock";

/// Held until dropped (or the process ends).
pub struct FileLock {
    _file: File,
}

impl FileLock {
    /// Creates the folder `dir` and takes its lock ([`FOLDER_LOCK`]); `holder` as in
    /// [`FileLock::acquire`].
    pub fn folder(dir: &Path, holder: &str) -> Result<FileLock, SimError> {
        std::fs::create_dir_all(dir).map_err(|e| SimError::Output {
            path: dir.display().to_string(),
            message: e.to_string(),
        })?;
        FileLock::acquire(&dir.join(FOLDER_LOCK), &dir.display().to_string(), holder)
    }

    /// Takes the lock at `path` (created if missing); `what` names the guarded output and
    /// `holder` the kind of writer that takes it (e.g. "`suspflow generate`"), in the
    /// refusal when another process holds it.
    pub fn acquire(path: &Path, what: &str, holder: &str) -> Result<FileLock, SimError> {
        let io = |e: std::io::Error| SimError::Output {
            path: path.display().to_string(),
            message: format!("locking: {e}"),
        };
        let mut file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .read(true)
            .write(true)
            .open(path)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => {
                file.set_len(0).map_err(io)?;
                file.rewind().map_err(io)?;
                write!(file, "{}", std::process::id()).map_err(io)?;
                Ok(FileLock { _file: file })
            }
            Err(TryLockError::WouldBlock) => {
                let mut owner = String::new();
                file.read_to_string(&mut owner).ok();
                Err(SimError::Locked {
                    what: what.to_string(),
                    holder: holder.to_string(),
                    owner: owner.trim().to_string(),
                    lock: path.display().to_string(),
                })
            }
            Err(TryLockError::Error(e)) => Err(io(e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_holder_is_refused_until_the_first_lets_go() {
        let dir = std::env::temp_dir().join(format!("sim-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("lock");
        let first = FileLock::acquire(&path, "out.csv", "`suspflow generate`").unwrap();
        let message = FileLock::acquire(&path, "out.csv", "`suspflow generate`")
            .err()
            .unwrap()
            .to_string();
        assert!(
            message.contains("out.csv is in use by another `suspflow generate`")
                && message.contains(&format!("process {}", std::process::id())),
            "{message}"
        );
        drop(first);
        assert!(FileLock::acquire(&path, "out.csv", "`suspflow generate`").is_ok());
        std::fs::remove_dir_all(&dir).ok();
    }
}
