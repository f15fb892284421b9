//! The lubrication resistance of every pair within the cut-off, frozen at one configuration:
//! the sparse symmetric operator `R` that maps the particles' motion to minus their
//! lubrication loads (docs/physics.md sections 4 and 5). The implicit step solves with it.
use crate::forces::chunk_buffers::{zero_buffer, ChunkBuffers, ChunkTarget};
use crate::forces::lubrication::PairResistance;
use crate::Vec3;
use nalgebra::Matrix3;
use rayon::prelude::*;
use std::ops::AddAssign;

/// One pair of the network: particles `i < j`, unit vector `n` from i to j and the
/// resistance functions at their gap.
#[derive(Clone, Copy, Debug)]
pub struct ResistancePair {
    pub i: u32,
    pub j: u32,
    pub n: Vec3,
    pub resistance: PairResistance,
}

impl ResistancePair {
    /// The pair's lubrication load for translational velocities `lin` and spins `ang`.
    #[inline]
    fn load(&self, lin: &[Vec3], ang: &[Vec3]) -> crate::forces::pair_load::PairLoad {
        let (i, j) = (self.i as usize, self.j as usize);
        self.resistance
            .load(&self.n, &(lin[j] - lin[i]), &ang[i], &ang[j])
    }
}

/// The pairs in the chunks of the force evaluation that found them (chunk k holds the
/// pairs whose first particle lies in `bounds[k]..bounds[k + 1]`), so that products run
/// over the same chunks in parallel with a fixed summation order.
#[derive(Default)]
pub struct ResistanceNetwork {
    pub chunks: Vec<Vec<ResistancePair>>,
    pub bounds: Vec<usize>,
    buffers: ChunkBuffers,
    block_buffers: ChunkBuffers<Matrix3<f64>>,
}

impl ResistanceNetwork {
    /// Empties the network for `bounds` (one chunk per range), keeping its memory.
    pub fn reset(&mut self, bounds: &[usize]) {
        let chunks = bounds.len() - 1;
        self.chunks.resize_with(chunks, Vec::new);
        for c in &mut self.chunks {
            c.clear();
        }
        self.bounds.clear();
        self.bounds.extend_from_slice(bounds);
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.chunks.iter().map(Vec::len).sum()
    }

    /// Whether no pair is within the lubrication cut-off.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Adds `R motion` to `out`, for a motion of 2N rows (N translational velocities, then
    /// N spins): minus the lubrication forces and torques that motion would meet (3.13,
    /// 3.14).
    pub fn apply(&mut self, motion: &[Vec3], out: &mut [Vec3]) {
        let n = motion.len() / 2;
        let (lin, ang) = motion.split_at(n);
        scatter(
            &mut self.buffers,
            &self.chunks,
            &self.bounds,
            out.split_at_mut(n),
            |pairs, target| add_products(pairs, lin, ang, target),
        );
    }

    /// Adds to `translation[i]` and `rotation[i]` particle i's own 3x3 blocks of `R`:
    /// `X11A N + Y11A T` for translation, `Y11C T` (or `Y22C T` for the second particle of
    /// a pair) for rotation, summed over its pairs.
    pub fn diagonal_blocks(
        &mut self,
        translation: &mut [Matrix3<f64>],
        rotation: &mut [Matrix3<f64>],
    ) {
        scatter(
            &mut self.block_buffers,
            &self.chunks,
            &self.bounds,
            (translation, rotation),
            add_blocks,
        );
    }
}

/// Adds `per_chunk(pairs, target)` for every chunk of pairs to `out`: chunk 0 straight,
/// the others (in parallel) through their buffers, added in chunk order.
fn scatter<T: Copy + Default + AddAssign + Send + Sync>(
    buffers: &mut ChunkBuffers<T>,
    chunks: &[Vec<ResistancePair>],
    bounds: &[usize],
    out: (&mut [T], &mut [T]),
    per_chunk: impl Fn(&[ResistancePair], ChunkTarget<T>) + Sync,
) {
    let (a, b) = out;
    if chunks.len() == 1 {
        per_chunk(&chunks[0], (a, b, 0));
        return;
    }
    let n = a.len();
    let targets = buffers.targets(bounds, n, (&mut *a, &mut *b));
    targets
        .into_par_iter()
        .zip(chunks.par_iter())
        .for_each(|(mut target, pairs)| {
            zero_buffer(&mut target);
            per_chunk(pairs, target)
        });
    buffers.reduce_into(bounds, a, b);
}

/// Adds each pair's diagonal blocks of `R` (see [`ResistanceNetwork::diagonal_blocks`])
/// into `target`, which holds particles from its offset on.
fn add_blocks(
    pairs: &[ResistancePair],
    (translation, rotation, offset): ChunkTarget<Matrix3<f64>>,
) {
    for p in pairs {
        let (i, j) = (p.i as usize - offset, p.j as usize - offset);
        let nn = p.n * p.n.transpose();
        let t = Matrix3::identity() - nn;
        let r = &p.resistance;
        let block = nn * r.x11a + t * r.y11a;
        translation[i] += block;
        translation[j] += block;
        rotation[i] += t * r.y11c;
        rotation[j] += t * r.y22c;
    }
}

/// Adds `R` times the motion for `pairs` into `target`, which holds particles from its
/// offset on.
fn add_products(
    pairs: &[ResistancePair],
    lin: &[Vec3],
    ang: &[Vec3],
    (out_lin, out_ang, offset): ChunkTarget,
) {
    for p in pairs {
        let load = p.load(lin, ang);
        let (i, j) = (p.i as usize - offset, p.j as usize - offset);
        out_lin[i] -= load.force_i;
        out_lin[j] += load.force_i;
        out_ang[i] -= load.torque_i;
        out_ang[j] -= load.torque_j;
    }
}
