//! One run sampled for the study of statistical error against run length: after the steady
//! state, the first `partial` snapshots averaged over their first `n = partial / 2^k`
//! snapshots, and the last `reference` snapshots, independent of those, averaged into a long
//! reference (docs/physics.md section 7). The errors of the partial averages against the
//! reference are the report's business; this module only samples.
use crate::input::scene::Scene;
use crate::output::run_summary::RunSummary;
use crate::run::{Phase, RunOptions};
use crate::sampling::bin_averages::{BinAverages, BinningContext};
use crate::sampling::block_sums::BlockSums;
use crate::sampling::snapshot::{field::FIELDS, Sampler, StepPairSums};
use crate::SimError;
use std::time::Instant;

/// Number of blocks of the partial averages' batch-means standard errors.
pub const PARTIAL_BLOCKS: usize = 4;

/// The average over the first `snapshots` steady snapshots.
pub struct PartialAverage {
    pub snapshots: usize,
    /// Wall time from the start of the run (equilibration included) to its last snapshot, s.
    pub wall_s: f64,
    pub averages: BinAverages,
}

/// One scene's sampled run. `P` is what is kept of each partial average: the average
/// itself, or the average with what a caller measured on it ([`SampledRun::map_partials`]).
pub struct SampledRun<P = PartialAverage> {
    pub scene: Scene,
    pub summary: RunSummary,
    /// Wall time to the steady state, s.
    pub wall_to_steady_s: f64,
    /// Shortest first, `partial / 2^k` snapshots down to 2 per block.
    pub partials: Vec<P>,
    /// The last `reference` snapshots, 10 blocks.
    pub reference: BinAverages,
    pub reference_snapshots: usize,
}

impl<P> SampledRun<P> {
    /// The same run with each partial average `p` replaced by `f(p, reference)`.
    pub fn map_partials<Q>(self, mut f: impl FnMut(P, &BinAverages) -> Q) -> SampledRun<Q> {
        let partials = self
            .partials
            .into_iter()
            .map(|p| f(p, &self.reference))
            .collect();
        SampledRun {
            scene: self.scene,
            summary: self.summary,
            wall_to_steady_s: self.wall_to_steady_s,
            partials,
            reference: self.reference,
            reference_snapshots: self.reference_snapshots,
        }
    }
}

/// Snapshot counts of the partial profiles: `partial / 2^k`, at least 2 per block.
fn partial_counts(partial: usize) -> Vec<usize> {
    let mut n: Vec<usize> = std::iter::successors(Some(partial), |&n| Some(n / 2))
        .take_while(|&n| n >= 2 * PARTIAL_BLOCKS)
        .collect();
    n.reverse();
    n
}

/// `snaps` (one sum per snapshot) grouped into `blocks` consecutive blocks.
fn blocks_of(snaps: &[Vec<f64>], blocks: usize, n_bins: usize) -> BlockSums {
    let mut b = BlockSums::new(n_bins, blocks, snaps.len() / blocks);
    for s in &snaps[..b.capacity()] {
        b.current().iter_mut().zip(s).for_each(|(acc, v)| *acc += v);
        b.commit();
    }
    b
}

/// Runs `scene` (its `run.snapshots` and `run.blocks` are replaced) to the steady state,
/// then `partial + reference` snapshots, and averages the partial runs and the
/// reference. `partial` must be a multiple of 4 and `reference` of 10.
pub fn sample(scene: &Scene, partial: usize, reference: usize) -> Result<SampledRun, SimError> {
    let mut file = scene.file.clone();
    file.run.snapshots = partial + reference;
    file.run.blocks = 2;
    let scene = Scene::from_file(file, false)?;
    let ctx = BinningContext::for_scene(&scene);
    let nb = scene.n_bins;
    let started = Instant::now();
    let mut snaps: Vec<Vec<f64>> = Vec::with_capacity(partial);
    let mut walls: Vec<f64> = Vec::with_capacity(partial);
    let mut reference_sums = BlockSums::new(nb, 10, reference / 10);
    let mut wall_to_steady_s = f64::NAN;
    let mut seen = 0;
    let mut sampler = Sampler::new(ctx.bins, ctx.a_mean);
    let outcome = crate::run::run(&scene, &RunOptions::default(), &mut |p, s| {
        if p.phase != Phase::Averaging {
            return;
        }
        if wall_to_steady_s.is_nan() {
            wall_to_steady_s = started.elapsed().as_secs_f64();
        }
        if p.snapshots == seen {
            return;
        }
        seen = p.snapshots;
        let mut sums = vec![0.0; FIELDS * nb];
        sampler.accumulate(s, &mut StepPairSums::default(), &mut sums);
        if snaps.len() < partial {
            snaps.push(sums);
            walls.push(started.elapsed().as_secs_f64());
        } else if !reference_sums.full() {
            reference_sums
                .current()
                .iter_mut()
                .zip(&sums)
                .for_each(|(acc, v)| *acc += v);
            reference_sums.commit();
        }
    })?;
    let reference_profile = BinAverages::from_blocks(&ctx, &reference_sums)?;
    let partials = partial_counts(partial)
        .into_iter()
        .map(|n| {
            Ok(PartialAverage {
                snapshots: n,
                wall_s: walls[n - 1],
                averages: BinAverages::from_blocks(
                    &ctx,
                    &blocks_of(&snaps[..n], PARTIAL_BLOCKS, nb),
                )?,
            })
        })
        .collect::<Result<Vec<_>, SimError>>()?;
    Ok(SampledRun {
        summary: outcome.summary,
        scene,
        wall_to_steady_s,
        partials,
        reference: reference_profile,
        reference_snapshots: reference,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_counts_halve_down_to_two_snapshots_per_block() {
        assert_eq!(partial_counts(64), vec![8, 16, 32, 64]);
        assert_eq!(partial_counts(512), vec![8, 16, 32, 64, 128, 256, 512]);
    }
}
