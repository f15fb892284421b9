//! The Green-Kubo Brownian viscosity of an unsheared suspension (paper section 3.3 and Fig.
//! 3b, thesis section 4.2.3 and Fig. 4.3b; docs/physics.md section 11):
//! `eta_B = (V / kT) int_0^inf <Sigma^B_xy(t + s) Sigma^B_xy(t)> ds`, with `Sigma^B` the
//! structural Brownian stress of thesis eq 3.54 over the box. The seeds add it to the
//! hydrodynamic viscosity at their lowest Peclet number to fit the low-Pe jamming point.
use crate::error::SimError;
use crate::forces::brownian_shell;
use crate::integrate::simulation::Simulation;
use serde::Serialize;

/// The xy component of the structural Brownian stress of the whole box (units energy /
/// volume, positive in compression like the pair stresslets): `sum of w n_x n_y / V` over
/// the pairs in the shell ([`brownian_shell::weight`]); 0 without thermal noise.
pub fn shell_shear_stress(sim: &Simulation) -> f64 {
    let Some(kt) = sim.kt() else {
        return 0.0;
    };
    let p = &sim.particles;
    let mut sum = 0.0;
    for i in 0..p.len() {
        for q in sim.list.start[i]..sim.list.start[i + 1] {
            let j = sim.list.neighbours[q] as usize;
            let r = sim.pbox.separation(&p.pos[i], &p.pos[j]);
            let d = r.norm();
            if let Some(w) = brownian_shell::weight(kt, p.radius[i], p.radius[j], d) {
                sum += w * r.x * r.y / (d * d);
            }
        }
    }
    sum / (sim.pbox.len.x * sim.pbox.len.y * sim.pbox.len.z)
}

/// A Green-Kubo integral and what it was made of.
#[derive(Clone, Debug, Serialize)]
pub struct GreenKubo {
    /// Lags (time units) of the correlation, from 0.
    pub lags: Vec<f64>,
    /// `<dS(t + s) dS(t)>` at each lag, `dS` the deviation from the series' mean.
    pub correlation: Vec<f64>,
    /// `(V / kT) int_0^s C` at each lag (trapezoidal rule): the viscosity's running
    /// integral, whose plateau is the viscosity.
    pub running: Vec<f64>,
    /// The running integral at the largest lag.
    pub viscosity: f64,
    /// Its standard error: the spread of the integrals of `blocks` consecutive parts of the
    /// series over `sqrt(blocks)`.
    pub viscosity_se: f64,
    pub blocks: usize,
}

/// Refuses a series of `samples` too short for `blocks` parts of at least four times the
/// largest lag `max_lag` (in samples) each.
pub(crate) fn check_length(samples: usize, max_lag: usize, blocks: usize) -> Result<(), SimError> {
    if blocks >= 2 && max_lag > 0 && samples >= blocks.saturating_mul(4).saturating_mul(max_lag) {
        return Ok(());
    }
    Err(SimError::GreenKubo(format!(
        "{samples} samples are too few for {blocks} blocks (at least 2) of at least 4 x \
         {max_lag} samples (the largest lag, at least 1): sample longer, or use a smaller lag \
         or fewer blocks"
    )))
}

/// `(correlation, running integral)` of `series` sampled every `dt` up to `max_lag` samples.
fn integral(series: &[f64], dt: f64, scale: f64, max_lag: usize) -> (Vec<f64>, Vec<f64>) {
    let n = series.len();
    let mean = series.iter().sum::<f64>() / n as f64;
    let d: Vec<f64> = series.iter().map(|x| x - mean).collect();
    let correlation: Vec<f64> = (0..=max_lag)
        .map(|s| (0..n - s).map(|t| d[t] * d[t + s]).sum::<f64>() / (n - s) as f64)
        .collect();
    let mut running = Vec::with_capacity(correlation.len());
    let mut acc = 0.0;
    running.push(0.0);
    for w in correlation.windows(2) {
        acc += 0.5 * (w[0] + w[1]) * dt * scale;
        running.push(acc);
    }
    (correlation, running)
}

impl GreenKubo {
    /// The Green-Kubo integral of the stress `series` (sampled every `dt`) of a box of
    /// volume `volume` at thermal energy `kt`, up to a lag of `max_lag` samples, with the
    /// error from `blocks` consecutive parts (each at least `4 max_lag` samples long).
    pub fn of_series(
        series: &[f64],
        dt: f64,
        (volume, kt): (f64, f64),
        max_lag: usize,
        blocks: usize,
    ) -> Result<GreenKubo, SimError> {
        check_length(series.len(), max_lag, blocks)?;
        let scale = volume / kt;
        let (correlation, running) = integral(series, dt, scale, max_lag);
        let per_block = series.len() / blocks;
        let parts: Vec<f64> = series
            .chunks_exact(per_block)
            .map(|c| *integral(c, dt, scale, max_lag).1.last().expect("lags"))
            .collect();
        let m = parts.iter().sum::<f64>() / blocks as f64;
        let var = parts.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (blocks - 1) as f64;
        Ok(GreenKubo {
            lags: (0..=max_lag).map(|s| s as f64 * dt).collect(),
            viscosity: *running.last().expect("lags"),
            viscosity_se: (var / blocks as f64).sqrt(),
            correlation,
            running,
            blocks,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// An Ornstein-Uhlenbeck series of variance `s2` and correlation time `tau` has
    /// `int_0^inf C = s2 tau`: 2e5 samples at dt = tau / 10, integrated to 10 tau; the
    /// integral's relative error is about sqrt(2 * 10 tau / T) = 4.5 %, so 15 % is three
    /// standard errors, and the blocks' error must be of that size too.
    #[test]
    fn an_ornstein_uhlenbeck_series_integrates_to_variance_times_time() {
        let (s2, tau, dt, n): (f64, f64, f64, usize) = (4.0, 1.0, 0.1, 200_000);
        let a = (-dt / tau).exp();
        let kick = (s2 * (1.0 - a * a)).sqrt();
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        let mut x = 0.0;
        let series: Vec<f64> = (0..n)
            .map(|_| {
                // Box-Muller.
                let (u, v): (f64, f64) = (1.0 - rng.gen::<f64>(), rng.gen());
                let z = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos();
                x = a * x + kick * z;
                x
            })
            .collect();
        let gk = GreenKubo::of_series(&series, dt, (1.0, 1.0), 100, 10).unwrap();
        assert!(
            (gk.correlation[0] / s2 - 1.0).abs() < 0.05,
            "{}",
            gk.correlation[0]
        );
        assert!(
            (gk.viscosity / (s2 * tau) - 1.0).abs() < 0.15,
            "{}",
            gk.viscosity
        );
        let expected_se = 0.045 * s2 * tau;
        assert!(
            gk.viscosity_se > 0.4 * expected_se && gk.viscosity_se < 2.5 * expected_se,
            "{}",
            gk.viscosity_se
        );
        assert!(GreenKubo::of_series(&series[..1000], dt, (1.0, 1.0), 100, 10).is_err());
    }
}
