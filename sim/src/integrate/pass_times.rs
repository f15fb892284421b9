//! Where the implicit solve's parallel passes spend their wall time: in the ranges' own
//! work, in waiting for the busiest range, or between passes (forks, joins and the scalar
//! steps of conjugate gradients). `suspflow bench` reports them, so that a thread count's
//! gain can be taken apart.
use serde::Serialize;
use std::time::Instant;

/// Seconds of the solve's parallel passes, summed over passes.
///
/// With `n` ranges (one per thread): `work_s` against its one-thread value is the work
/// the split adds (pairs that cross between ranges are evaluated by both, and values along
/// the cut move between cores); `longest_s` against `work_s / n` is the imbalance between
/// ranges; `wall_s` against `longest_s` is the time outside the ranges' work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PassTimes {
    /// Every range's own busy time, added up.
    pub work_s: f64,
    /// The busiest range's busy time in each pass.
    pub longest_s: f64,
    /// The passes' wall time, from the fork to the join.
    pub wall_s: f64,
}

/// Busy seconds of one or more ranges of a pass: their sum and the longest.
#[derive(Clone, Copy, Debug, Default)]
pub struct RangeBusy {
    total: f64,
    longest: f64,
}

impl RangeBusy {
    /// One range busy from `start` until now.
    pub fn until_now(start: Instant) -> Self {
        let s = start.elapsed().as_secs_f64();
        RangeBusy {
            total: s,
            longest: s,
        }
    }

    /// The busy time of both sets of ranges.
    pub fn merge(self, other: RangeBusy) -> Self {
        RangeBusy {
            total: self.total + other.total,
            longest: self.longest.max(other.longest),
        }
    }
}

impl PassTimes {
    /// Adds a pass forked at `start` and joined now, its ranges busy for `busy`.
    pub fn add(&mut self, busy: RangeBusy, start: Instant) {
        self.work_s += busy.total;
        self.longest_s += busy.longest;
        self.wall_s += start.elapsed().as_secs_f64();
    }

    /// The time accumulated since `earlier` was read off these times.
    pub fn since(&self, earlier: &PassTimes) -> PassTimes {
        PassTimes {
            work_s: self.work_s - earlier.work_s,
            longest_s: self.longest_s - earlier.longest_s,
            wall_s: self.wall_s - earlier.wall_s,
        }
    }
}
