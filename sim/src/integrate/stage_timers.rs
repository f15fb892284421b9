//! Wall-clock time spent in each stage of a run, reported in summary.json.
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// Stages of a step.
#[derive(Clone, Copy, Debug)]
pub enum Stage {
    Neighbours,
    Forces,
    Integration,
    Sampling,
}

/// Accumulated seconds per stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StageTimers {
    pub neighbours_s: f64,
    pub forces_s: f64,
    pub integration_s: f64,
    pub sampling_s: f64,
}

impl StageTimers {
    /// A start mark.
    pub fn start(&self) -> Instant {
        Instant::now()
    }

    /// Adds the time since `since` to `stage`.
    pub fn stop(&mut self, stage: Stage, since: Instant) {
        let s = Duration::as_secs_f64(&since.elapsed());
        match stage {
            Stage::Neighbours => self.neighbours_s += s,
            Stage::Forces => self.forces_s += s,
            Stage::Integration => self.integration_s += s,
            Stage::Sampling => self.sampling_s += s,
        }
    }

    /// The time accumulated since `earlier` was read off these timers.
    pub fn since(&self, earlier: &StageTimers) -> StageTimers {
        StageTimers {
            neighbours_s: self.neighbours_s - earlier.neighbours_s,
            forces_s: self.forces_s - earlier.forces_s,
            integration_s: self.integration_s - earlier.integration_s,
            sampling_s: self.sampling_s - earlier.sampling_s,
        }
    }
}
