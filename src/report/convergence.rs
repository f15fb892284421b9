//! Statistical error of a simulation against its run length: one run
//! of a scene, steady state as usual, then `partial + reference` snapshots. The first
//! `partial` snapshots give profiles averaged over n = partial / 2^k snapshots; the last
//! `reference` snapshots, independent of them, give the long reference profile. The error
//! of a short run is the relative L2 difference (over bins, as eq 6.6 but unscaled)
//! between its profile and the reference; for independent averages of a steady, mixing
//! run its square is expected to be `c (1/n + 1/reference)`, so it falls as 1/sqrt(n)
//! until n approaches the reference length.
use schema::Observable;
use sim::input::scene::Scene;
use sim::run_length::{self, PartialAverage, SampledRun};
use sim::SimError;

/// Observables whose error is measured.
pub const OBSERVABLES: [Observable; 3] = [Observable::PhiLoc, Observable::Mu, Observable::U];

/// A partial average with what the report measures on it.
pub struct MeasuredPartial {
    pub average: PartialAverage,
    /// Strain averaged over, `snapshots * sample_strain`.
    pub averaging_strain: f64,
    /// Relative L2 difference from the reference of each of [`OBSERVABLES`].
    pub error: [f64; 3],
}

/// One scene's convergence run.
pub type ConvergenceRun = SampledRun<MeasuredPartial>;

/// `||a - b|| / ||b - offset||` over the bins where both are finite (NaN when none are):
/// the metric of eq 6.6 (`surrogate::relative_l2_error`) on values shifted by `offset`.
pub fn relative_l2(a: &[f64], b: &[f64], offset: f64) -> f64 {
    let pairs: Vec<(f64, f64)> = a
        .iter()
        .zip(b)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(&x, &y)| (x - offset, y - offset))
        .collect();
    let shifted = |pick: fn(&(f64, f64)) -> f64| {
        ndarray::Array2::from_shape_fn((pairs.len(), 1), |(k, _)| pick(&pairs[k]))
    };
    let (predicted, truth) = (shifted(|p| p.0), shifted(|p| p.1));
    surrogate::relative_l2_error(truth.view(), predicted.view()).map_or(f64::NAN, |e| e[0])
}

/// Runs `scene` (its `run.snapshots` and `run.blocks` are replaced) to the steady state,
/// then `partial + reference` snapshots (`sim::run_length`), and measures the
/// partial averages against the reference. `partial` must be a multiple of 4 and
/// `reference` of 10.
pub fn run(scene: &Scene, partial: usize, reference: usize) -> Result<ConvergenceRun, SimError> {
    let sampled = run_length::sample(scene, partial, reference)?;
    let sample_strain = sampled.scene.file.run.sample_strain;
    Ok(sampled.map_partials(|average, reference| MeasuredPartial {
        averaging_strain: average.snapshots as f64 * sample_strain,
        error: OBSERVABLES.map(|o| {
            relative_l2(
                average.averages.mean.column(o),
                reference.mean.column(o),
                0.0,
            )
        }),
        average,
    }))
}

/// Averaging strain beyond which snapshot averages decorrelate: in the validation scenes
/// the error hardly falls between 0.08 and 0.32 strain of averaging (reports/full).
pub const DECORRELATED_STRAIN: f64 = 1.0;

/// `c` of the noise law `error^2 = c (1/n + 1/reference)` through one point `(n, error)`,
/// the longest partial average: the law then holds at least where it is used to extrapolate.
pub fn noise_constant(n: f64, error: f64, reference: f64) -> f64 {
    error * error / (1.0 / n + 1.0 / reference)
}

/// Least-squares slope of `ln error` against `ln n`, over `points` `(n, error)`; NaN with
/// fewer than two usable points.
pub fn log_slope(points: &[(f64, f64)]) -> f64 {
    let p: Vec<(f64, f64)> = points
        .iter()
        .filter(|(n, e)| *n > 0.0 && *e > 0.0 && e.is_finite())
        .map(|(n, e)| (n.ln(), e.ln()))
        .collect();
    if p.len() < 2 {
        return f64::NAN;
    }
    let m = p.len() as f64;
    let (mx, my) = (
        p.iter().map(|q| q.0).sum::<f64>() / m,
        p.iter().map(|q| q.1).sum::<f64>() / m,
    );
    let sxy: f64 = p.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = p.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// The slope of [`log_slope`] over the partial averages of at least
/// [`DECORRELATED_STRAIN`], with the reference's own noise taken out of each error
/// (`error * sqrt(R / (R + n))`, the noise law's share of the partial average): -1/2 when
/// the error is purely statistical.
pub fn decorrelated_slope(run: &ConvergenceRun, observable: usize) -> f64 {
    let r = run.reference_snapshots as f64;
    let points: Vec<(f64, f64)> = run
        .partials
        .iter()
        .filter(|p| p.averaging_strain >= DECORRELATED_STRAIN - 1e-9)
        .map(|p| {
            (
                p.average.snapshots as f64,
                p.error[observable] * (r / (r + p.average.snapshots as f64)).sqrt(),
            )
        })
        .collect();
    log_slope(&points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_law_through_a_point_and_the_slope_of_a_power_law() {
        let c: f64 = 0.3;
        let e = (c * (1.0 / 8.0 + 1.0 / 100.0)).sqrt();
        assert!((noise_constant(8.0, e, 100.0) - c).abs() < 1e-12);
        let pure: Vec<(f64, f64)> = [4.0, 40.0, 400.0]
            .iter()
            .map(|&n: &f64| (n, 2.0 / n.sqrt()))
            .collect();
        assert!((log_slope(&pure) + 0.5).abs() < 1e-12);
        assert!(log_slope(&pure[..1]).is_nan());
    }

    #[test]
    fn relative_l2_skips_undefined_bins_and_uses_the_offset() {
        let e = relative_l2(&[1.0, f64::NAN, 3.0], &[2.0, 5.0, 3.0], 1.0);
        assert!((e - (1.0f64 / 5.0).sqrt()).abs() < 1e-12);
    }
}
