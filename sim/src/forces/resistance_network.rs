//! The lubrication resistance of every pair within the cut-off, frozen at one configuration:
//! the sparse symmetric operator `R` that maps the particles' motion to minus their
//! lubrication loads (docs/physics.md sections 4 and 5). The implicit step solves with it.
//!
//! The pairs stay in the ranges of the force evaluation that found them: range k holds the
//! pairs whose first particle lies in `bounds[k]..bounds[k + 1]`. Work
//! on the network is done range by range, each range's rows written by one thread only:
//! a pair whose second particle lies in a later range (a crossing pair) is evaluated by
//! both ranges, each keeping its own particle's share. No per-thread buffers, no
//! reduction pass, and a range's rows stay in the cache of the thread that owns them.
use crate::forces::lubrication::PairResistance;
use crate::state::Vec3;
use nalgebra::Matrix3;
use rayon::prelude::*;

/// One pair of the network: particles `i < j`, unit vector `n` from i to j and the
/// resistance functions at their gap.
#[derive(Clone, Copy, Debug)]
pub struct ResistancePair {
    pub i: u32,
    pub j: u32,
    pub n: Vec3,
    pub resistance: PairResistance,
}

/// A translational and a rotational quantity of one particle (velocity and spin, force
/// and torque).
pub type Motion = [Vec3; 2];

/// The pairs in the ranges of the force evaluation that found them, with the crossing
/// pairs of each range indexed.
#[derive(Default)]
pub struct ResistanceNetwork {
    pub ranges: Vec<Vec<ResistancePair>>,
    pub bounds: Vec<usize>,
    /// For each range, the positions of its crossing pairs (second particle in a later
    /// range), in the range's order.
    crossing: Vec<Vec<u32>>,
}

impl ResistanceNetwork {
    /// Empties the network for `bounds` (one list of pairs per range), keeping its memory.
    pub fn reset(&mut self, bounds: &[usize]) {
        let ranges = bounds.len() - 1;
        self.ranges.resize_with(ranges, Vec::new);
        for c in &mut self.ranges {
            c.clear();
        }
        self.bounds.clear();
        self.bounds.extend_from_slice(bounds);
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.ranges.iter().map(Vec::len).sum()
    }

    /// Whether no pair is within the lubrication cut-off.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Indexes each range's crossing pairs; call once the ranges are filled.
    pub fn index_crossings(&mut self) {
        self.crossing.resize_with(self.ranges.len(), Vec::new);
        let bounds = &self.bounds;
        self.crossing
            .par_iter_mut()
            .zip(self.ranges.par_iter())
            .enumerate()
            .for_each(|(k, (crossing, pairs))| {
                // Filled as a local vector (see `pair_range` on false sharing).
                let mut local = std::mem::take(crossing);
                local.clear();
                let end = bounds[k + 1] as u32;
                local.extend(
                    (0u32..)
                        .zip(pairs)
                        .filter(|(_, p)| p.j >= end)
                        .map(|(m, _)| m),
                );
                *crossing = local;
            });
    }

    /// Calls `visit(pair, i, j)` for every pair with a particle in range `k`, with the
    /// positions of i and j in the range (`None` outside it): first the range's own pairs
    /// in order, then the crossing pairs of earlier ranges that end in the range.
    #[inline]
    pub fn visit(
        &self,
        k: usize,
        mut visit: impl FnMut(&ResistancePair, Option<usize>, Option<usize>),
    ) {
        let (start, end) = (self.bounds[k], self.bounds[k + 1]);
        let inside = |q: u32| {
            (start..end)
                .contains(&(q as usize))
                .then(|| q as usize - start)
        };
        for p in &self.ranges[k] {
            visit(p, Some(p.i as usize - start), inside(p.j));
        }
        for (pairs, crossing) in self.ranges[..k].iter().zip(&self.crossing[..k]) {
            for &m in crossing {
                let p = &pairs[m as usize];
                if let Some(j) = inside(p.j) {
                    visit(p, None, Some(j));
                }
            }
        }
    }

    /// Sets `out` (the particles of range `k`) to `R motion`: minus the lubrication forces
    /// and torques that `motion` (every particle's velocity and spin) would meet (3.13,
    /// 3.14).
    pub fn product_on(&self, k: usize, motion: &[Motion], out: &mut [Motion]) {
        out.fill([Vec3::zeros(); 2]);
        self.visit(k, |p, i, j| {
            let (a, b) = (&motion[p.i as usize], &motion[p.j as usize]);
            let load = p.resistance.load(&p.n, &(b[0] - a[0]), &a[1], &b[1]);
            if let Some(i) = i {
                out[i][0] -= load.force_i;
                out[i][1] -= load.torque_i;
            }
            if let Some(j) = j {
                out[j][0] += load.force_i;
                out[j][1] -= load.torque_j;
            }
        });
    }

    /// Calls `add(position, translation, rotation)` with each pair's share of the own 3x3
    /// blocks of `R` of every particle of range `k`: `X11A N + Y11A T` for translation,
    /// `Y11C T` (or `Y22C T` for the second particle of a pair) for rotation.
    pub fn diagonal_blocks_on(
        &self,
        k: usize,
        mut add: impl FnMut(usize, Matrix3<f64>, Matrix3<f64>),
    ) {
        self.visit(k, |p, i, j| {
            let nn = p.n * p.n.transpose();
            let t = Matrix3::identity() - nn;
            let r = &p.resistance;
            let block = nn * r.x11a + t * r.y11a;
            if let Some(i) = i {
                add(i, block, t * r.y11c);
            }
            if let Some(j) = j {
                add(j, block, t * r.y22c);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::lubrication::LubricationCoefficients;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    fn random_vec(rng: &mut StdRng) -> Vec3 {
        Vec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        )
    }

    /// 12 particles in the ranges 0..4, 4..9, 9..12, with random pairs (some from the
    /// first range to the last) at random gaps and orientations.
    fn network(rng: &mut StdRng) -> ResistanceNetwork {
        let coefficients = LubricationCoefficients::new(1.0, 1.4, 1.0, 1e-3, 0.05);
        let mut net = ResistanceNetwork::default();
        net.reset(&[0, 4, 9, 12]);
        for i in 0..12u32 {
            for j in i + 1..12 {
                if rng.gen_bool(0.5) {
                    let k = net.bounds.iter().rposition(|&b| b <= i as usize).unwrap();
                    net.ranges[k].push(ResistancePair {
                        i,
                        j,
                        n: random_vec(rng).normalize(),
                        resistance: coefficients.resistance(rng.gen_range(1e-3..0.04)).unwrap(),
                    });
                }
            }
        }
        net.index_crossings();
        net
    }

    /// Range by range, the product and the diagonal blocks equal those summed over all
    /// pairs at once, each pair adding to both of its particles.
    #[test]
    fn ranges_give_the_product_and_blocks_of_all_pairs() {
        let mut rng = StdRng::seed_from_u64(7);
        let net = network(&mut rng);
        assert!(net.crossing[0]
            .iter()
            .any(|&m| net.ranges[0][m as usize].j >= 9));
        let motion: Vec<Motion> = (0..12)
            .map(|_| [random_vec(&mut rng), random_vec(&mut rng)])
            .collect();
        let mut expected = vec![[Vec3::zeros(); 2]; 12];
        let mut expected_blocks = vec![[Matrix3::zeros(); 2]; 12];
        for p in net.ranges.iter().flatten() {
            let (i, j) = (p.i as usize, p.j as usize);
            let (a, b) = (motion[i], motion[j]);
            let load = p.resistance.load(&p.n, &(b[0] - a[0]), &a[1], &b[1]);
            expected[i][0] -= load.force_i;
            expected[j][0] += load.force_i;
            expected[i][1] -= load.torque_i;
            expected[j][1] -= load.torque_j;
            let nn = p.n * p.n.transpose();
            let t = Matrix3::identity() - nn;
            let r = &p.resistance;
            for (m, spin) in [(i, r.y11c), (j, r.y22c)] {
                expected_blocks[m][0] += nn * r.x11a + t * r.y11a;
                expected_blocks[m][1] += t * spin;
            }
        }
        let mut product = vec![[Vec3::new(9.0, 9.0, 9.0); 2]; 12];
        let mut blocks = vec![[Matrix3::zeros(); 2]; 12];
        for k in 0..3 {
            let range = net.bounds[k]..net.bounds[k + 1];
            let start = range.start;
            net.product_on(k, &motion, &mut product[range]);
            net.diagonal_blocks_on(k, |m, t, r| {
                blocks[start + m][0] += t;
                blocks[start + m][1] += r;
            });
        }
        for m in 0..12 {
            for c in 0..2 {
                let scale = expected[m][c].norm().max(1.0);
                assert!((product[m][c] - expected[m][c]).norm() <= 1e-12 * scale);
                let scale = expected_blocks[m][c].norm().max(1.0);
                assert!((blocks[m][c] - expected_blocks[m][c]).norm() <= 1e-12 * scale);
            }
        }
        // R is positive semi-definite: no motion is driven by lubrication.
        let dissipation: f64 = (0..12)
            .map(|m| motion[m][0].dot(&product[m][0]) + motion[m][1].dot(&product[m][1]))
            .sum();
        assert!(dissipation > 0.0);
    }
}
