//! The thread pools of the simulation commands, and the thread counts they accept.

/// Most threads per core a `--threads` (or `--jobs`) count may ask for: beyond it the
/// threads only take turns on the cores, and a count of 100000 would spend minutes
/// creating threads before the first step.
pub const THREADS_PER_CORE_MAX: usize = 8;

/// Cores of this machine (1 if unknown).
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Value parser of a thread count: 0 (all cores) up to [`THREADS_PER_CORE_MAX`] per core.
pub fn count(text: &str) -> Result<usize, String> {
    let n: usize = text
        .parse()
        .map_err(|_| format!("`{text}` is not a thread count (0 = all cores, or 1, 2, ...)"))?;
    let max = THREADS_PER_CORE_MAX * cores();
    if n > max {
        return Err(format!(
            "{n} threads on {} cores: at most {max} ({THREADS_PER_CORE_MAX} per core; 0 = all cores)",
            cores()
        ));
    }
    Ok(n)
}

/// Runs `f` on a pool of `threads` threads (0 = all cores).
pub fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> anyhow::Result<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    Ok(pool.install(f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_beyond_the_cap_and_non_numbers_are_refused() {
        assert_eq!(count("0"), Ok(0));
        assert_eq!(count("2"), Ok(2));
        let cap = THREADS_PER_CORE_MAX * cores();
        assert_eq!(count(&cap.to_string()), Ok(cap));
        let message = count(&(cap + 1).to_string()).unwrap_err();
        assert!(message.contains(&format!("at most {cap}")), "{message}");
        assert!(count("100000").unwrap_err().contains("100000 threads on"));
        assert!(count("-1")
            .unwrap_err()
            .contains("`-1` is not a thread count"));
    }
}
