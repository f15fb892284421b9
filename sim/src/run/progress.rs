//! Where a run is, and the progress lines of a run whose output is not a terminal (a batch
//! job's log): one line every few percent or every few minutes, whichever comes first,
//! with the step, the clock and an estimate of the time left.
use crate::input::scene::Clock;
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// The two phases of a run: reaching the state to sample (the steady state, or a Brownian
/// warm-up), then sampling it.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Phase {
    Equilibrating,
    Averaging,
}

/// Progress report, once per sample.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    pub phase: Phase,
    /// The run's clock: strain, or Brownian times `tau_B` without flow.
    pub strain: f64,
    /// What `strain` counts.
    pub clock: Clock,
    /// Budget (steady run) or length (warm-up) of the equilibration, in units of the clock.
    pub max_strain: f64,
    pub snapshots: usize,
    pub snapshots_target: usize,
    pub step: u64,
    /// Samples taken since the run began (equilibration and averaging, counting those
    /// before a resume): 1 at the first call.
    pub samples: u64,
}

impl Progress {
    /// The fraction of the phase done, in [0, 1]: the clock over the equilibration's budget
    /// (a steady run may finish it sooner), or the snapshots over their target.
    pub fn fraction(&self) -> f64 {
        let f = match self.phase {
            Phase::Equilibrating => self.strain / self.max_strain,
            Phase::Averaging => self.snapshots as f64 / self.snapshots_target.max(1) as f64,
        };
        if f.is_finite() {
            f.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// What the run is doing, e.g. `equilibrating: strain 1.25 of budget 30.0` or
    /// `averaging: snapshot 120 / 1000 at strain 14.20` (`12.00 tau_B` without flow).
    pub fn describe(&self) -> String {
        let clock = self.clock.show(self.strain);
        match self.phase {
            Phase::Equilibrating => {
                format!("equilibrating: {clock} of budget {:.1}", self.max_strain)
            }
            Phase::Averaging => format!(
                "averaging: snapshot {} / {} at {clock}",
                self.snapshots, self.snapshots_target
            ),
        }
    }
}

/// Decides when a progress line is due: every `percent` percent of a phase and at least
/// every `interval`, whichever comes first (and at each change of phase).
pub struct ProgressLines {
    percent: f64,
    interval: Duration,
    last_line: Instant,
    last: Option<(Phase, f64)>,
    phase_started: Instant,
    /// The phase's fraction at its first line: more than zero when a run resumes.
    phase_start_fraction: f64,
}

/// Percent of a phase between two progress lines in a log (off a terminal).
pub const LOG_LINE_PERCENT: f64 = 10.0;
/// Longest time between two progress lines in a log.
pub const LOG_LINE_EVERY: Duration = Duration::from_secs(300);

impl ProgressLines {
    /// The schedule of a log (a batch job's output, nohup): a line every
    /// [`LOG_LINE_PERCENT`] percent of a phase or every [`LOG_LINE_EVERY`], whichever
    /// comes first; the command and the Python package both follow it.
    pub fn for_logs() -> Self {
        ProgressLines::new(LOG_LINE_PERCENT, LOG_LINE_EVERY)
    }

    /// A line at every report: the status line of a terminal.
    pub fn every_report() -> Self {
        ProgressLines::new(0.0, Duration::ZERO)
    }

    /// A line every `percent` percent of a phase, and at least every `interval`.
    pub fn new(percent: f64, interval: Duration) -> Self {
        ProgressLines {
            percent,
            interval,
            last_line: Instant::now(),
            last: None,
            phase_started: Instant::now(),
            phase_start_fraction: 0.0,
        }
    }

    /// The line for `p` when one is due: what the run does, its step and clock, the time
    /// in the phase (since this process reached it: a resumed run counts from the resume)
    /// and the time left at the phase's pace so far (while equilibrating, the most: to the
    /// end of the budget, which a steady run may not need).
    pub fn line(&mut self, p: &Progress) -> Option<String> {
        let fraction = p.fraction();
        let new_phase = self.last.is_none_or(|(phase, _)| phase != p.phase);
        let due = new_phase
            || self.last.is_some_and(|(_, done)| {
                100.0 * (fraction - done) >= self.percent
                    || self.last_line.elapsed() >= self.interval
            });
        if !due {
            return None;
        }
        if new_phase {
            if self.last.is_some() {
                self.phase_started = Instant::now();
            }
            self.phase_start_fraction = fraction;
        }
        self.last = Some((p.phase, fraction));
        self.last_line = Instant::now();
        let spent = self.phase_started.elapsed().as_secs_f64();
        let left = match time_left(spent, self.phase_start_fraction, fraction) {
            Some(left) => {
                let bound = match p.phase {
                    Phase::Equilibrating => "at most ",
                    Phase::Averaging => "",
                };
                format!(", {bound}about {} left", describe_seconds(left))
            }
            None => String::new(),
        };
        Some(format!(
            "{} ({:.0} %), step {}, {} in this phase{left}",
            p.describe(),
            100.0 * fraction,
            p.step,
            describe_seconds(spent)
        ))
    }
}

/// Seconds left to finish a phase at the pace of the `spent` seconds in which it went from
/// the fraction `from` (where this process began it: above zero after a resume) to
/// `fraction`; `None` before any progress or once done.
pub fn time_left(spent: f64, from: f64, fraction: f64) -> Option<f64> {
    (fraction > from && fraction < 1.0).then(|| spent * (1.0 - fraction) / (fraction - from))
}

/// A duration for a log: `42 s`, `12.5 min`, `3.2 h`.
pub fn describe_seconds(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.1} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(phase: Phase, strain: f64, snapshots: usize) -> Progress {
        Progress {
            phase,
            strain,
            clock: Clock::Strain,
            max_strain: 10.0,
            snapshots,
            snapshots_target: 200,
            step: 7,
            samples: 1,
        }
    }

    #[test]
    fn lines_come_every_few_percent_and_at_a_change_of_phase() {
        let mut lines = ProgressLines::new(10.0, Duration::from_secs(3600));
        assert!(lines.line(&at(Phase::Equilibrating, 0.1, 0)).is_some());
        assert!(lines.line(&at(Phase::Equilibrating, 0.5, 0)).is_none());
        let line = lines.line(&at(Phase::Equilibrating, 1.2, 0)).unwrap();
        assert!(
            line.contains("strain 1.20 of budget 10.0 (12 %), step 7")
                && line.contains(", at most about "),
            "{line}"
        );
        let averaging = lines.line(&at(Phase::Averaging, 3.0, 1)).unwrap();
        assert!(
            averaging.starts_with("averaging: snapshot 1 / 200 at strain 3.00 (0 %), step 7"),
            "{averaging}"
        );
        assert!(lines.line(&at(Phase::Averaging, 3.0, 20)).is_none());
        let later = lines.line(&at(Phase::Averaging, 3.0, 21)).unwrap();
        assert!(
            later.contains(", about ") && !later.contains("at most"),
            "{later}"
        );
        // Without progress, a line at least every interval.
        let mut slow = ProgressLines::new(10.0, Duration::ZERO);
        assert!(slow.line(&at(Phase::Averaging, 0.0, 1)).is_some());
        assert!(slow.line(&at(Phase::Averaging, 0.0, 1)).is_some());
    }

    /// A resumed run's pace is its progress since the resume: at 60 % of a phase, 120 s
    /// after resuming at 50 %, 480 s are left (not the 80 s of 60 % in 120 s).
    #[test]
    fn the_time_left_counts_from_the_resume() {
        assert_eq!(time_left(120.0, 0.5, 0.6).map(f64::round), Some(480.0));
        assert_eq!(time_left(120.0, 0.0, 0.6).map(f64::round), Some(80.0));
        assert_eq!(time_left(120.0, 0.5, 0.5), None);
        assert_eq!(time_left(120.0, 0.5, 1.0), None);
    }

    /// Without flow the clock counts Brownian times, and the lines say so.
    #[test]
    fn a_run_at_rest_counts_brownian_times() {
        let mut rest = at(Phase::Equilibrating, 12.0, 0);
        rest.clock = Clock::BrownianTimes;
        let line = rest.describe();
        assert_eq!(line, "equilibrating: 12.00 tau_B of budget 10.0", "{line}");
        rest.phase = Phase::Averaging;
        let line = rest.describe();
        assert_eq!(line, "averaging: snapshot 0 / 200 at 12.00 tau_B", "{line}");
    }
}
