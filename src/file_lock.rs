//! An exclusive lock on an output, so that two `suspflow generate` (or `simulate`) runs on
//! one output refuse to share it instead of deleting each other's files. The lock is the operating
//! system's advisory lock on a small file (which holds the owner's process id for the
//! message): it is released when the process ends, however it ends, so a killed run leaves
//! no stale lock behind.
use anyhow::{bail, Context};
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::Path;

/// Held until dropped (or the process ends).
pub struct FileLock {
    _file: File,
}

impl FileLock {
    /// Takes the lock at `path` (created if missing); `what` names the guarded output and
    /// `command` the command that takes it in the refusal when another process holds it.
    pub fn acquire(path: &Path, what: &str, command: &str) -> anyhow::Result<FileLock> {
        let mut file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .read(true)
            .write(true)
            .open(path)
            .with_context(|| format!("opening the lock file {}", path.display()))?;
        match file.try_lock() {
            Ok(()) => {
                file.set_len(0)?;
                file.rewind()?;
                write!(file, "{}", std::process::id())?;
                Ok(FileLock { _file: file })
            }
            Err(TryLockError::WouldBlock) => {
                let mut owner = String::new();
                file.read_to_string(&mut owner).ok();
                bail!(
                    "{what} is in use by another `suspflow {command}` (process {}, lock {}); \
                     wait for it to finish, or stop it (its work is kept) and run again",
                    owner.trim(),
                    path.display()
                )
            }
            Err(TryLockError::Error(e)) => {
                Err(e).with_context(|| format!("locking {}", path.display()))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_holder_is_refused_until_the_first_lets_go() {
        let dir = crate::test_dir("lock");
        let path = dir.join("lock");
        let first = FileLock::acquire(&path, "out.csv", "generate").unwrap();
        let message = FileLock::acquire(&path, "out.csv", "generate")
            .err()
            .unwrap()
            .to_string();
        assert!(
            message.contains("out.csv is in use by another `suspflow generate`")
                && message.contains(&format!("process {}", std::process::id())),
            "{message}"
        );
        drop(first);
        assert!(FileLock::acquire(&path, "out.csv", "generate").is_ok());
        std::fs::remove_dir_all(&dir).ok();
    }
}
