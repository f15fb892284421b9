//! The parts of the stress, per bin and over the box (docs/physics.md section 11): the
//! contact springs' and the lubrication's stresslets, whose sum is the profile's pair
//! stress, the Stokes drag's stresslet, and the structural Brownian stress (thesis eq 3.54, paper
//! eq 2.27), reported beside them and not added. Stresses are positive in compression, over
//! the bin volume (per bin) or the box volume (box totals), like the profile's.
use crate::sampling::bin_averages::BinningContext;
use crate::sampling::block_sums::{BlockSums, Estimate};
use crate::sampling::snapshot::field::{BROWNIAN, CONTACT, SXX, SXY_DRAG};
use schema::columns::STRESS_PARTS;
use std::collections::BTreeMap;

/// Where each part of [`STRESS_PARTS`] comes from in a snapshot.
#[derive(Clone, Copy)]
enum Source {
    /// The shear (xy) or pressure (trace / 3) of the four tensor fields from `base`.
    Shear(usize),
    Pressure(usize),
    /// The pair stresslets minus their contact part, shear or pressure.
    LubricationShear,
    LubricationPressure,
    DragShear,
}

/// The sources of [`STRESS_PARTS`], in its order.
const SOURCES: [Source; 7] = [
    Source::Shear(CONTACT),
    Source::Pressure(CONTACT),
    Source::LubricationShear,
    Source::LubricationPressure,
    Source::DragShear,
    Source::Shear(BROWNIAN),
    Source::Pressure(BROWNIAN),
];

/// Stress parts of a run, with batch-means standard errors.
#[derive(Clone, Debug)]
pub struct StressParts {
    /// `bins[q][k]`: part `q` of [`STRESS_PARTS`] in bin `k`.
    pub bins: Vec<Vec<Estimate>>,
    /// Box totals, by part name.
    pub box_totals: BTreeMap<String, Estimate>,
}

/// Summed value of one part in bin `k` of summed snapshots `s` (`nb` bins), unnormalised.
fn part_sum(s: &[f64], nb: usize, k: usize, source: Source) -> f64 {
    let at = |f: usize| s[f * nb + k];
    let trace = |base: usize| (at(base) + at(base + 1) + at(base + 2)) / 3.0;
    match source {
        Source::Shear(base) => at(base + 3),
        Source::Pressure(base) => trace(base),
        Source::LubricationShear => at(SXX + 3) - at(CONTACT + 3),
        Source::LubricationPressure => trace(SXX) - trace(CONTACT),
        Source::DragShear => at(SXY_DRAG),
    }
}

/// For each part of [`STRESS_PARTS`] in turn, its box total and then its value in every
/// bin, of summed snapshots `s` (`n` snapshots): `STRESS_PARTS.len() * (n_bins + 1)`
/// numbers.
fn values(ctx: &BinningContext, s: &[f64], n: usize) -> Vec<f64> {
    let nb = ctx.bins.count;
    let norm = 1.0 / (n as f64 * ctx.bin_volume);
    let mut out = Vec::with_capacity(SOURCES.len() * (nb + 1));
    for &source in &SOURCES {
        let per_bin: Vec<f64> = (0..nb).map(|k| part_sum(s, nb, k, source) * norm).collect();
        out.push(per_bin.iter().sum::<f64>() / nb as f64);
        out.extend(per_bin);
    }
    out
}

impl StressParts {
    /// The stress parts of the snapshots in `blocks`.
    pub fn from_blocks(ctx: &BinningContext, blocks: &BlockSums) -> StressParts {
        let nb = ctx.bins.count;
        let e = blocks.estimates(|s, n| values(ctx, s, n));
        let mut bins = Vec::with_capacity(SOURCES.len());
        let mut box_totals = BTreeMap::new();
        for (q, chunk) in e.chunks(nb + 1).enumerate() {
            box_totals.insert(STRESS_PARTS[q].to_string(), chunk[0]);
            bins.push(chunk[1..].to_vec());
        }
        StressParts { bins, box_totals }
    }
}
