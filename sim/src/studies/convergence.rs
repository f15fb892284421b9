//! Statistical error of a simulation against its run length: one run of a scene, steady
//! state as usual, then `partial + reference` snapshots ([`run_length`]). The first
//! `partial` snapshots give profiles averaged over n = partial / 2^k snapshots; the last
//! `reference` snapshots, independent of them, give the long reference profile. The error
//! of a short run is a distance between its profile and the reference, given by the caller
//! (the report's is the relative L2 difference over bins, as eq 6.6 but unscaled); for
//! independent averages of a steady, mixing run its square is expected to be
//! `c (1/n + 1/reference)`, so it falls as 1/sqrt(n) until n approaches the reference
//! length.
use crate::input::scene::Scene;
use crate::studies::run_length::{self, PartialAverage, SampledRun};
use crate::SimError;
use schema::Observable;

/// Observables whose error is measured.
pub const OBSERVABLES: [Observable; 3] = [Observable::PhiLoc, Observable::Mu, Observable::U];

/// A partial average with what the study measures on it.
pub struct MeasuredPartial {
    pub average: PartialAverage,
    /// Strain averaged over, `snapshots * sample_strain`.
    pub averaging_strain: f64,
    /// Distance from the reference of each of [`OBSERVABLES`].
    pub error: [f64; 3],
}

/// One scene's convergence run.
pub type ConvergenceRun = SampledRun<MeasuredPartial>;

/// Runs `scene` (its `run.snapshots` and `run.blocks` are replaced) to the steady state,
/// then `partial + reference` snapshots ([`run_length::sample`]), and measures the partial
/// averages against the reference: `distance(partial profile, reference profile)` per
/// observable, bin by bin. `partial` must be a multiple of 4 and `reference` of 10.
pub fn run(
    scene: &Scene,
    partial: usize,
    reference: usize,
    distance: impl Fn(&[f64], &[f64]) -> f64,
) -> Result<ConvergenceRun, SimError> {
    let sampled = run_length::sample(scene, partial, reference)?;
    let sample_strain = sampled.scene.file.run.sample_strain;
    Ok(sampled.map_partials(|average, reference| MeasuredPartial {
        averaging_strain: average.snapshots as f64 * sample_strain,
        error: OBSERVABLES
            .map(|o| distance(average.averages.mean.column(o), reference.mean.column(o))),
        average,
    }))
}

/// Averaging strain beyond which snapshot averages decorrelate: in the validation scenes
/// the error hardly falls between 0.08 and 0.32 strain of averaging (reports/full).
pub const DECORRELATED_STRAIN: f64 = 1.0;

/// `c` of the noise law `error^2 = c (1/n + 1/reference)` through one point `(n, error)`,
/// the longest partial average: the law then holds at least where it is used to extrapolate.
/// `n` and `reference` are snapshot counts; `c` has the units of `error^2`.
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

/// How long a simulation must run to match an error.
pub enum SimulationCost {
    /// A partial run reached it: snapshots, total strain, wall time (s).
    Measured(usize, f64, f64),
    /// Beyond the partial runs: the same, from the noise law.
    Extrapolated(f64, f64, f64),
    /// Not below the reference's own noise, `sqrt(c / reference)`.
    BelowReferenceNoise(f64),
}

/// The shortest run of `run`'s scene whose `output` profile is within `target` of the
/// reference in the caller's `distance(profile, reference)`, and the reference's own noise
/// in that metric, `sqrt(c / R)`. Measured among the partial averages when one gets
/// there; else extrapolated from the longest with `error^2 = c (1/n + 1/R)`, so
/// `n = 1 / (target^2 / c - 1/R)`, at the strain `strain_to_steady + n sample_strain` and
/// the wall time to the steady state plus n times the longest average's wall time per
/// snapshot (s).
pub fn simulation_cost(
    run: &ConvergenceRun,
    output: Observable,
    target: f64,
    distance: impl Fn(&[f64], &[f64]) -> f64,
) -> (SimulationCost, f64) {
    let reference = run.reference.mean.column(output);
    let points: Vec<(f64, f64)> = run
        .partials
        .iter()
        .map(|p| {
            (
                p.average.snapshots as f64,
                distance(p.average.averages.mean.column(output), reference),
            )
        })
        .collect();
    let strain_at = |n: f64| run.summary.strain_to_steady + n * run.scene.file.run.sample_strain;
    let r = run.reference_snapshots as f64;
    let (last, &(n_last, e_last)) = (
        &run.partials
            .last()
            .expect("a convergence run has partial profiles")
            .average,
        points.last().expect("one error per partial profile"),
    );
    let c = noise_constant(n_last, e_last, r);
    let floor = (c / r).sqrt();
    if let Some((p, _)) = run
        .partials
        .iter()
        .zip(&points)
        .find(|(_, (_, e))| *e <= target)
    {
        return (
            SimulationCost::Measured(
                p.average.snapshots,
                strain_at(p.average.snapshots as f64),
                p.average.wall_s,
            ),
            floor,
        );
    }
    let inverse_n = target * target / c - 1.0 / r;
    if inverse_n <= 0.0 {
        return (SimulationCost::BelowReferenceNoise(floor), floor);
    }
    let wall_per_snapshot = (last.wall_s - run.wall_to_steady_s) / last.snapshots as f64;
    let n = 1.0 / inverse_n;
    (
        SimulationCost::Extrapolated(
            n,
            strain_at(n),
            run.wall_to_steady_s + n * wall_per_snapshot,
        ),
        floor,
    )
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
}
