//! Steady-state detection (SPEC section 7): successive windows of equal strain are
//! averaged, and the run is steady once u(y), sigma_xy(y) and phi_loc(y) no longer
//! change between two windows beyond their statistical error.
use crate::block_sums::BlockSums;
use crate::error::SimError;
use crate::profile::{Profile, ProfileContext};
use serde::{Deserialize, Serialize};

/// Blocks per window (standard errors of a window's profile).
pub const WINDOW_BLOCKS: usize = 5;

/// Drift between two consecutive windows: for each quantity, the mean over bins of
/// `(A_k - A_{k-1})^2 / (se_k^2 + se_{k-1}^2)`, about 1 when only noise differs.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Drift {
    /// Strain at the end of the later window.
    pub strain: f64,
    pub chi2_u: f64,
    pub chi2_sigma_xy: f64,
    pub chi2_phi_loc: f64,
}

impl Drift {
    /// Largest of the three.
    pub fn worst(&self) -> f64 {
        self.chi2_u.max(self.chi2_sigma_xy).max(self.chi2_phi_loc)
    }
}

/// Window means and errors of the three watched quantities.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct WindowSummary {
    values: [Vec<f64>; 3],
    errors: [Vec<f64>; 3],
}

/// The detector's state, saved in checkpoints.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SteadyState {
    /// Snapshots of the window being filled.
    pub window: BlockSums,
    previous: Option<WindowSummary>,
    /// Drift of every completed window pair.
    pub history: Vec<Drift>,
    threshold: f64,
}

fn chi2(a: &[f64], sa: &[f64], b: &[f64], sb: &[f64]) -> f64 {
    let n = a.len() as f64;
    (0..a.len())
        .map(|k| {
            let d = a[k] - b[k];
            let var = sa[k] * sa[k] + sb[k] * sb[k];
            if var > 0.0 { d * d / var } else if d == 0.0 { 0.0 } else { f64::INFINITY }
        })
        .sum::<f64>()
        / n
}

impl SteadyState {
    /// Windows of `snapshots_per_window` snapshots over `n_bins` bins; steady when every
    /// chi2 of [`Drift`] is below `threshold`.
    pub fn new(n_bins: usize, snapshots_per_window: usize, threshold: f64) -> Self {
        let per_block = snapshots_per_window.div_ceil(WINDOW_BLOCKS).max(1);
        Self { window: BlockSums::new(n_bins, WINDOW_BLOCKS, per_block), previous: None, history: Vec::new(), threshold }
    }

    /// Closes a full window at `strain`: returns whether the run is now steady, and
    /// starts the next window.
    pub fn close_window(&mut self, ctx: &ProfileContext, strain: f64) -> Result<bool, SimError> {
        let p = Profile::from_blocks(ctx, &self.window)?;
        let summary = WindowSummary {
            values: [p.mean.u, p.mean.sigma_xy, p.mean.phi_loc],
            errors: [p.se.u, p.se.sigma_xy, p.se.phi_loc],
        };
        let mut steady = false;
        if let Some(prev) = &self.previous {
            let c = |q: usize| chi2(&summary.values[q], &summary.errors[q], &prev.values[q], &prev.errors[q]);
            let drift = Drift { strain, chi2_u: c(0), chi2_sigma_xy: c(1), chi2_phi_loc: c(2) };
            steady = drift.worst() < self.threshold;
            self.history.push(drift);
        }
        self.previous = Some(summary);
        self.window = BlockSums::new(self.window.n_bins, WINDOW_BLOCKS, self.window.per_block);
        Ok(steady)
    }

    /// A readable account of the last drift, for errors and summaries.
    pub fn describe_last(&self) -> String {
        match self.history.last() {
            Some(d) => format!(
                "last window-to-window drift at strain {:.2}: chi2 u = {:.2}, sigma_xy = {:.2}, phi_loc = {:.2} (steady below {})",
                d.strain, d.chi2_u, d.chi2_sigma_xy, d.chi2_phi_loc, self.threshold),
            None => "fewer than two windows completed".into(),
        }
    }
}
