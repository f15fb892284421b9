//! The exit status of `suspflow`: 0 done; 2 bad input (a scene, grid or option refused,
//! as clap's own usage errors); 3 runs failed (recorded in their folders; running again
//! retries only when asked); 75 interrupted (`EX_TEMPFAIL`: the state is saved and the
//! same command continues it, e.g. a batch job requeued after its time limit); 1 any other
//! error (a file that cannot be read or written, ...).
use sim::run::run_folder::{Ended, RunFolder};
use sim::SimError;

/// Bad input (scene, grid, option).
pub const BAD_INPUT: u8 = 2;
/// Runs failed.
pub const FAILED: u8 = 3;
/// Interrupted with the state saved.
pub const INTERRUPTED: u8 = 75;
/// Anything else.
pub const OTHER: u8 = 1;

/// How a command stopped short of its results, for the exit status.
#[derive(Debug)]
pub enum Stop {
    /// Interrupted, the state saved: what to do next.
    Interrupted(String),
    /// Runs failed: which, and why.
    Failed(String),
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stop::Interrupted(m) | Stop::Failed(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for Stop {}

/// The result of one run in `folder` that ended so, or how it stopped short: interrupted
/// (its checkpoint saved, continued with `--resume`) or failed.
pub fn finished<O>(ended: Ended<O>, folder: &RunFolder) -> anyhow::Result<O> {
    match ended {
        Ended::Finished(outcome) => Ok(outcome),
        Ended::Interrupted { step } => Err(Stop::Interrupted(format!(
            "interrupted at step {step}; state saved in {}; continue with --resume",
            folder.checkpoint().display()
        ))
        .into()),
        Ended::InterruptedPacking => {
            Err(Stop::Interrupted(SimError::InterruptedPacking.to_string()).into())
        }
        Ended::Failed(reason) => Err(Stop::Failed(reason).into()),
    }
}

/// The exit status of a command that failed with `e`.
pub fn of(e: &anyhow::Error) -> u8 {
    for cause in e.chain() {
        if let Some(stop) = cause.downcast_ref::<Stop>() {
            return match stop {
                Stop::Interrupted(_) => INTERRUPTED,
                Stop::Failed(_) => FAILED,
            };
        }
        if let Some(e) = cause.downcast_ref::<SimError>() {
            return match e {
                SimError::Field { .. }
                | SimError::Profile { .. }
                | SimError::SceneFile { .. }
                | SimError::Grid(_)
                | SimError::GreenKubo(_) => BAD_INPUT,
                SimError::Interrupted { .. } | SimError::InterruptedPacking => INTERRUPTED,
                _ => OTHER,
            };
        }
    }
    OTHER
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interrupted_failed_and_bad_input_are_told_apart() {
        let bad: anyhow::Error = SimError::field("particles.phi", "too large").into();
        assert_eq!(of(&bad.context("reading the scene")), BAD_INPUT);
        let failed: anyhow::Error = Stop::Failed("1 run failed".into()).into();
        assert_eq!(of(&failed), FAILED);
        let stopped: anyhow::Error = Stop::Interrupted("state saved".into()).into();
        assert_eq!(of(&stopped), INTERRUPTED);
        assert_eq!(of(&anyhow::anyhow!("disk full")), OTHER);
    }
}
