//! Files written whole, the one writer of every result: the bytes go to a temporary file of
//! a name no other writer uses (`.<name>.<process>.<count>.tmp`, created new, so a link or
//! file left under that name is never followed or reused) in the same folder, are synced,
//! and the file is renamed over the target (which replaces a link there rather than
//! writing through it). A reader, or a run killed half-way, never sees a half-written
//! file, and two writers of one file leave one of the two whole.
use crate::error::{Result, SchemaError};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Temporary files made by this process so far.
static TEMPORARIES: AtomicU64 = AtomicU64::new(0);

/// A temporary name beside `path` that no other writer (process or thread) uses.
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    let count = TEMPORARIES.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}.{count}.tmp", std::process::id()))
}

/// Writes `bytes` to `path` whole (see the module).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let err = |source: std::io::Error| SchemaError::Write {
        path: path.display().to_string(),
        source,
    };
    let tmp = temporary(path);
    let written = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        })
        .and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        std::fs::remove_file(&tmp).ok();
    }
    written.map_err(err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_link_in_the_way_is_replaced_not_followed_and_no_temporary_is_left() {
        let dir = std::env::temp_dir().join(format!("schema-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("victim.txt");
        std::fs::write(&target, "kept").unwrap();
        let path = dir.join("out.csv");
        std::os::unix::fs::symlink(&target, &path).unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "kept");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert!(!std::fs::symlink_metadata(&path).unwrap().is_symlink());
        // Writers in parallel each leave the file whole.
        std::thread::scope(|s| {
            for k in 0..8 {
                let path = &path;
                s.spawn(move || {
                    write_atomic(path, format!("{k}").repeat(10_000).as_bytes()).unwrap()
                });
            }
        });
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.len() == 10_000 && text.chars().all(|c| c == text.chars().next().unwrap()));
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(left.is_empty(), "{left:?}");
        // A folder that does not exist is an error naming the file.
        let missing = dir.join("no/such/file.csv");
        assert!(write_atomic(&missing, b"x")
            .unwrap_err()
            .to_string()
            .contains("no/such/file.csv"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
