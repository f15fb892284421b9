//! Steady-state detection (docs/physics.md section 7). The run is cut into windows of equal strain;
//! the run is steady once u(y), sigma_xy(y) and phi_loc(y) show no significant linear
//! trend over the last [`TREND_WINDOWS`] window averages, and in a Brownian scene also the
//! structural Brownian pressure(y), which counts the pairs within 0.05 a of contact: the
//! near-contact structure of a fresh packing relaxes over several Brownian times while the
//! profiles are already flat (docs/physics.md section 11). Windows, not snapshots, are the
//! samples: the noise is the scatter of the window means about the fitted trend, pooled
//! over bins, so time correlation inside a window does not fake a drift.
use crate::error::SimError;
use crate::sampling::bin_averages::{observables, BinningContext};
use crate::sampling::block_sums::BlockSums;
use crate::sampling::snapshot::field::{BROWNIAN, COUNT, VX};
use serde::{Deserialize, Serialize};

/// Windows in the trend test.
pub const TREND_WINDOWS: usize = 4;

/// Trend of the last windows: for each quantity, the mean over bins of the squared
/// z-score of the fitted slope, about 1 when the windows differ by noise only.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Drift {
    /// Strain at the end of the last window.
    pub strain: f64,
    pub chi2_u: f64,
    pub chi2_sigma_xy: f64,
    pub chi2_phi_loc: f64,
    /// The structural Brownian pressure's (0 without Brownian forces, and in the records
    /// of runs made before it was watched).
    #[serde(default)]
    pub chi2_structure: f64,
}

impl Drift {
    /// Largest of the four.
    pub fn worst(&self) -> f64 {
        self.chi2_u
            .max(self.chi2_sigma_xy)
            .max(self.chi2_phi_loc)
            .max(self.chi2_structure)
    }
}

/// The detector's state, saved in checkpoints.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SteadyState {
    /// Snapshot sums of the window being filled.
    pub window: BlockSums,
    /// Mean u, sigma_xy and phi_loc profiles of every completed window.
    pub window_means: Vec<[Vec<f64>; 3]>,
    /// Mean structural Brownian pressure (trace of its per-bin sums, any units) of every
    /// completed window of a Brownian scene; empty otherwise.
    #[serde(default)]
    pub structure_means: Vec<Vec<f64>>,
    /// Trend statistics after every completed window from the [`TREND_WINDOWS`]-th on.
    pub history: Vec<Drift>,
    threshold: f64,
}

/// Mean over bins of the squared z-score of the least-squares slope of `series[w][k]`
/// (window w, bin k), with the residual variance pooled over bins.
fn trend_chi2(series: &[&Vec<f64>]) -> f64 {
    let m = series.len();
    let nb = series[0].len();
    let centre = (m as f64 - 1.0) / 2.0;
    let xs: Vec<f64> = (0..m).map(|w| w as f64 - centre).collect();
    let sxx: f64 = xs.iter().map(|x| x * x).sum();
    let (mut slope2, mut resid2) = (0.0, 0.0);
    for k in 0..nb {
        let mean = series.iter().map(|s| s[k]).sum::<f64>() / m as f64;
        let slope = xs.iter().zip(series).map(|(x, s)| x * s[k]).sum::<f64>() / sxx;
        slope2 += slope * slope;
        resid2 += xs
            .iter()
            .zip(series)
            .map(|(x, s)| (s[k] - mean - slope * x).powi(2))
            .sum::<f64>();
    }
    let var_slope = resid2 / (nb * (m - 2)) as f64 / sxx;
    if var_slope > 0.0 {
        slope2 / nb as f64 / var_slope
    } else if slope2 == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

impl SteadyState {
    /// Windows of `snapshots_per_window` snapshots over `n_bins` bins; steady when every
    /// chi2 of [`Drift`] is below `threshold`.
    pub fn new(n_bins: usize, snapshots_per_window: usize, threshold: f64) -> Self {
        Self {
            window: BlockSums::new(n_bins, 1, snapshots_per_window.max(1)),
            window_means: Vec::new(),
            structure_means: Vec::new(),
            history: Vec::new(),
            threshold,
        }
    }

    /// Closes a full window at `strain`: returns whether the run is now steady, and
    /// starts the next window.
    pub fn close_window(&mut self, ctx: &BinningContext, strain: f64) -> Result<bool, SimError> {
        let sums = self.window.total();
        let nb = self.window.n_bins;
        let u_star: Vec<f64> = (0..nb)
            .map(|k| sums[VX * nb + k] / sums[COUNT * nb + k].max(1.0))
            .collect();
        let o = observables(ctx, &sums, self.window.taken, &u_star)?;
        self.window_means.push([o.u, o.sigma_xy, o.phi_loc]);
        let structure: Vec<f64> = (0..nb)
            .map(|k| (0..3).map(|c| sums[(BROWNIAN + c) * nb + k]).sum::<f64>())
            .collect();
        if structure.iter().any(|&x| x != 0.0) {
            self.structure_means.push(structure);
        }
        self.window = BlockSums::new(nb, 1, self.window.per_block);
        let n = self.window_means.len();
        if n < TREND_WINDOWS {
            return Ok(false);
        }
        let last = &self.window_means[n - TREND_WINDOWS..];
        let chi2 = |q: usize| trend_chi2(&last.iter().map(|w| &w[q]).collect::<Vec<_>>());
        let ns = self.structure_means.len();
        let chi2_structure = if ns >= TREND_WINDOWS {
            trend_chi2(
                &self.structure_means[ns - TREND_WINDOWS..]
                    .iter()
                    .collect::<Vec<_>>(),
            )
        } else {
            0.0
        };
        let drift = Drift {
            strain,
            chi2_u: chi2(0),
            chi2_sigma_xy: chi2(1),
            chi2_phi_loc: chi2(2),
            chi2_structure,
        };
        self.history.push(drift);
        Ok(drift.worst() < self.threshold)
    }

    /// A readable account of the last trend test, for errors and summaries.
    pub fn describe_last(&self) -> String {
        match self.history.last() {
            Some(d) => format!(
                "trend over the last {TREND_WINDOWS} windows at strain {:.2}: chi2 u = {:.2}, sigma_xy = {:.2}, \
                 phi_loc = {:.2}{} (steady below {})",
                d.strain, d.chi2_u, d.chi2_sigma_xy, d.chi2_phi_loc,
                if self.structure_means.is_empty() { String::new() } else { format!(", structural Brownian pressure = {:.2}", d.chi2_structure) },
                self.threshold),
            None => format!("fewer than {TREND_WINDOWS} windows completed"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::trend_chi2;

    #[test]
    fn trend_statistic_separates_noise_from_drift() {
        // Deterministic pseudo-noise of unit size on 20 bins over 4 windows.
        let noise = |w: usize, k: usize| (((w * 31 + k * 17) % 13) as f64 - 6.0) / 3.5;
        let flat: Vec<Vec<f64>> = (0..4)
            .map(|w| (0..20).map(|k| 5.0 + noise(w, k)).collect())
            .collect();
        let drifting: Vec<Vec<f64>> = (0..4)
            .map(|w| {
                (0..20)
                    .map(|k| 5.0 + 3.0 * w as f64 + noise(w, k))
                    .collect()
            })
            .collect();
        let chi2 = |s: &Vec<Vec<f64>>| trend_chi2(&s.iter().collect::<Vec<_>>());
        assert!(chi2(&flat) < 3.0, "noise alone: {}", chi2(&flat));
        assert!(chi2(&drifting) > 20.0, "drift: {}", chi2(&drifting));
    }
}
