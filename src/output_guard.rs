//! Refuse-unless-`--force`: nothing a user made is overwritten without being asked for,
//! and an `--out` of the wrong kind (a file where a directory goes) is named plainly.
use anyhow::bail;
use sim::output::file_lock::FileLock;
use std::path::Path;

/// Fails if `path` exists and `force` is not set; `what` says what the file is and `hint`
/// what else the user can do (e.g. "choose another --out").
pub fn refuse_unless_force(path: &Path, force: bool, what: &str, hint: &str) -> anyhow::Result<()> {
    if !force && path.exists() {
        return Err(refusal(path, what, hint));
    }
    Ok(())
}

/// The error of an existing `path` that only `--force` replaces (a library's refusal,
/// e.g. `solver::SolverError::WouldReplace`, told in the command's words).
pub fn refusal(path: &Path, what: &str, hint: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{} already exists ({what}); --force replaces it, or {hint}",
        path.display()
    )
}

/// [`refuse_unless_force`] for every file a writer would replace (a table and the files
/// written beside it): the first existing one is named.
pub fn refuse_any_unless_force(
    paths: &[std::path::PathBuf],
    force: bool,
    what: &str,
    hint: &str,
) -> anyhow::Result<()> {
    paths
        .iter()
        .try_for_each(|p| refuse_unless_force(p, force, what, hint))
}

/// Fails if `dir`, given as `--out`, exists and is not a directory.
pub fn out_dir(dir: &Path) -> anyhow::Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!(
            "--out {} is an existing file; give a directory (it is created if missing)",
            dir.display()
        );
    }
    Ok(())
}

/// An output directory held by one writer ([`claim_dir`]) until dropped.
pub struct Claim {
    _lock: FileLock,
    /// The directory, if the claim created it: removed again when the writer leaves it
    /// holding nothing but the lock (a refused or failed command leaves no trace).
    created: Option<std::path::PathBuf>,
}

impl Drop for Claim {
    fn drop(&mut self) {
        let Some(dir) = &self.created else { return };
        let only_lock = std::fs::read_dir(dir).is_ok_and(|entries| {
            entries
                .filter_map(Result::ok)
                .all(|e| e.file_name() == sim::output::file_lock::FOLDER_LOCK)
        });
        if only_lock {
            std::fs::remove_file(dir.join(sim::output::file_lock::FOLDER_LOCK)).ok();
            std::fs::remove_dir(dir).ok();
        }
    }
}

/// Claims the directory `dir`, given as `--out`, for the command `holder` (e.g.
/// "`suspflow cross-validate`"): checks it is a directory ([`out_dir`]), creates it and
/// takes the lock every writer of an output folder takes, held until the claim is dropped.
/// A second writer of the same folder is refused instead of replacing the first one's files.
pub fn claim_dir(dir: &Path, holder: &str) -> anyhow::Result<Claim> {
    out_dir(dir)?;
    let created = (!dir.exists()).then(|| dir.to_path_buf());
    Ok(Claim {
        _lock: FileLock::folder(dir, holder)?,
        created,
    })
}

/// Fails if `file`, given as `--out`, is an existing directory.
pub fn out_file(file: &Path) -> anyhow::Result<()> {
    if file.is_dir() {
        bail!("--out {} is a directory; give a file name", file.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_existing_paths_unless_forced_and_wrong_kinds() {
        let dir = crate::test_dir("guard");
        let file = dir.join("f.csv");
        assert!(refuse_unless_force(&file, false, "a dataset", "choose another --out").is_ok());
        std::fs::write(&file, "x\n").unwrap();
        let message = refuse_unless_force(&file, false, "a dataset", "choose another --out")
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(
                "already exists (a dataset); --force replaces it, or choose another --out"
            ),
            "{message}"
        );
        assert!(refuse_unless_force(&file, true, "a dataset", "").is_ok());
        assert!(out_dir(&file)
            .unwrap_err()
            .to_string()
            .contains("is an existing file"));
        assert!(out_dir(&dir).is_ok() && out_file(&file).is_ok());
        assert!(out_file(&dir)
            .unwrap_err()
            .to_string()
            .contains("is a directory"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
