//! Per-range buffers of the force evaluation's parallel pair loop: range 0 adds straight
//! into the output, range k >= 1 into its own buffer covering particles from its first
//! row on (a half list has j > i), and the buffers are added in range order, so the same
//! ranges always give the same bits.
use crate::state::particle_ranges::each_range;
use crate::state::Vec3;

/// Buffers (forces, torques) of the ranges after the first, reused from call to call (no
/// allocation once they have grown to size).
#[derive(Default)]
pub struct RangeBuffers {
    buffers: Vec<(Vec<Vec3>, Vec<Vec3>)>,
}

/// Where one range writes: its force and torque arrays and the index of their first
/// particle.
pub type RangeTarget<'a> = (&'a mut [Vec3], &'a mut [Vec3], usize);

impl RangeBuffers {
    /// One target per range of `bounds` (range k covers rows `bounds[k]..bounds[k + 1]`):
    /// `first` for range 0, buffers covering `bounds[k]..n` for the others. The buffers
    /// hold the last call's values: each range zeroes its own with [`zero_buffer`], in
    /// its parallel task.
    pub fn targets<'a>(
        &'a mut self,
        bounds: &[usize],
        n: usize,
        first: (&'a mut [Vec3], &'a mut [Vec3]),
    ) -> Vec<RangeTarget<'a>> {
        let ranges = bounds.len() - 1;
        self.buffers.resize_with(ranges - 1, Default::default);
        let mut targets: Vec<RangeTarget<'a>> = Vec::with_capacity(ranges);
        targets.push((first.0, first.1, 0));
        for (k, (bf, bt)) in self.buffers.iter_mut().enumerate() {
            let offset = bounds[k + 1];
            bf.resize(n - offset, Vec3::zeros());
            bt.resize(n - offset, Vec3::zeros());
            targets.push((bf.as_mut_slice(), bt.as_mut_slice(), offset));
        }
        targets
    }

    /// Adds every buffer into `a` and `b`, particle by particle in range order, each
    /// range of `bounds` as one task (see `particle_ranges`).
    pub fn reduce_into(&self, bounds: &[usize], a: &mut [Vec3], b: &mut [Vec3]) {
        let buffers = &self.buffers;
        each_range(bounds, (a, b), &|k, first, (a, b)| {
            // Range k receives the buffers of the ranges before it, which cover it.
            let earlier = &buffers[..k];
            for (r, (f, t)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
                let i = first + r;
                for (c, (bf, bt)) in earlier.iter().enumerate() {
                    let offset = bounds[c + 1];
                    *f += bf[i - offset];
                    *t += bt[i - offset];
                }
            }
        });
    }
}

/// Zeroes `target` if it is a range's buffer (offset > 0); range 0's target, the output
/// itself, keeps what the caller put there.
pub fn zero_buffer(target: &mut RangeTarget<'_>) {
    if target.2 > 0 {
        target.0.fill(Vec3::zeros());
        target.1.fill(Vec3::zeros());
    }
}
