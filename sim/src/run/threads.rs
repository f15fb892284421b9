//! How many threads a run may ask for, the one cap of every front end (the commands'
//! `--threads` and `--jobs`, Python's `threads`).

/// Most threads per core a run (or a batch's parallel runs) may ask for: beyond it the
/// threads only take turns on the cores, and a count of 100000 would spend minutes
/// creating threads before the first step.
pub const THREADS_PER_CORE_MAX: usize = 8;

/// Cores of this machine (1 if unknown).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// `n` threads (0 = all cores) if at most [`THREADS_PER_CORE_MAX`] per core, else the
/// refusal.
pub fn check(n: usize) -> Result<usize, String> {
    let max = THREADS_PER_CORE_MAX * cores();
    if n > max {
        return Err(format!(
            "{n} threads on {} cores: at most {max} ({THREADS_PER_CORE_MAX} per core; 0 = all cores)",
            cores()
        ));
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_up_to_the_cap_pass_and_beyond_it_are_refused() {
        let cap = THREADS_PER_CORE_MAX * cores();
        assert_eq!(check(0), Ok(0));
        assert_eq!(check(cap), Ok(cap));
        let message = check(cap + 1).unwrap_err();
        assert!(message.contains(&format!("at most {cap}")), "{message}");
    }
}
