//! The thread pools of the simulation commands, and the thread counts they accept.

/// Value parser of a thread count: 0 (all cores) up to
/// [`sim::run::threads::THREADS_PER_CORE_MAX`] per core.
pub fn count(text: &str) -> Result<usize, String> {
    let n: usize = text
        .parse()
        .map_err(|_| format!("`{text}` is not a thread count (0 = all cores, or 1, 2, ...)"))?;
    sim::run::threads::check(n)
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
        assert!(count("100000").unwrap_err().contains("100000 threads on"));
        assert!(count("-1")
            .unwrap_err()
            .contains("`-1` is not a thread count"));
    }
}
