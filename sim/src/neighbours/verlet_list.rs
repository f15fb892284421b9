//! Half Verlet neighbour list with a skin (pairs i < j closer than cut-off + skin),
//! rebuilt from a cell list when a particle has moved more than half the skin (less, in a
//! sheared box, what the sliding images have moved).
use crate::neighbours::size_classes::CandidateCells;
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;
use rayon::prelude::*;

/// Particles per chunk of the parallel build.
const BUILD_CHUNK: usize = 512;

/// Neighbour pairs in compressed-row form: the neighbours of i are
/// `neighbours[start[i]..start[i+1]]`, all greater than i and in increasing order.
#[derive(Clone, Debug, Default)]
pub struct VerletList {
    pub start: Vec<usize>,
    pub neighbours: Vec<u32>,
    /// Positions at the last build: the list is valid while no particle has moved more
    /// than `skin / 2` from here.
    pub reference: Vec<Vec3>,
    /// Lees-Edwards offset of the box at the build (0 without shear).
    pub reference_offset: f64,
    /// For every cut `b` of the particle order (0..=N), the listed pairs it separates
    /// (`i < b <= j`).
    pub crossing: Vec<usize>,
    skin: f64,
}

impl VerletList {
    /// Lists every pair whose distance is below `cutoff(i, j) + skin`, using `cells`
    /// built over `positions` for those distances.
    pub fn build(
        positions: &[Vec3],
        pbox: &PeriodicBox,
        cells: &CandidateCells,
        skin: f64,
        cutoff: impl Fn(usize, usize) -> f64 + Sync,
    ) -> Self {
        let n = positions.len();
        // Rows are found in parallel chunks and concatenated in order: the list does not
        // depend on the thread count.
        let chunks: Vec<(Vec<usize>, Vec<u32>)> = positions
            .par_chunks(BUILD_CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let mut row_ends = Vec::with_capacity(chunk.len());
                let mut found = Vec::with_capacity(8 * chunk.len());
                for (r, x_i) in chunk.iter().enumerate() {
                    let i = c * BUILD_CHUNK + r;
                    let row = found.len();
                    cells.for_each_candidate(i, x_i, |j| {
                        let ju = j as usize;
                        if ju > i {
                            let reach = cutoff(i, ju) + skin;
                            if pbox.separation(x_i, &positions[ju]).norm_squared() < reach * reach {
                                found.push(j);
                            }
                        }
                    });
                    found[row..].sort_unstable();
                    row_ends.push(found.len());
                }
                (row_ends, found)
            })
            .collect();
        let mut start = Vec::with_capacity(n + 1);
        let mut neighbours = Vec::with_capacity(chunks.iter().map(|c| c.1.len()).sum());
        start.push(0);
        for (row_ends, found) in &chunks {
            let offset = neighbours.len();
            start.extend(row_ends.iter().map(|end| offset + end));
            neighbours.extend_from_slice(found);
        }
        let crossing = crossings(&start, &neighbours);
        Self {
            start,
            neighbours,
            reference: positions.to_vec(),
            reference_offset: pbox.shear_offset(),
            crossing,
            skin,
        }
    }

    /// Whether the list may miss a pair. Without shear: some particle has moved more than
    /// half the skin since the build. In a sheared box the images have also slid by
    /// `s` (the change of the offset, modulo `L_x`), which moves a pair across a y face by
    /// up to `s` more, and a particle that crossed a y face is measured through the
    /// current offset, off by at most `s`; the pair distance has changed by at most
    /// `2 d_max + 3 s`, so the list is stale once `d_max > (skin - 3 s) / 2`.
    pub fn stale(&self, positions: &[Vec3], pbox: &PeriodicBox) -> bool {
        let slide = (pbox.shear_offset() - self.reference_offset).rem_euclid(pbox.len.x);
        let slide = slide.min(pbox.len.x - slide);
        let allowed = 0.5 * (self.skin - 3.0 * slide);
        if allowed < 0.0 {
            return true;
        }
        let limit = allowed * allowed;
        positions
            .par_iter()
            .zip(&self.reference)
            .with_min_len(BUILD_CHUNK)
            .any(|(x, r)| pbox.separation(r, x).norm_squared() > limit)
    }

    /// Number of listed pairs.
    pub fn len(&self) -> usize {
        self.neighbours.len()
    }

    /// Whether the list has no pairs.
    pub fn is_empty(&self) -> bool {
        self.neighbours.is_empty()
    }

    /// Carries per-pair values (tangential contact springs) from `old` to this list,
    /// where new particle k was particle `old_index[k]` of the old list: pairs present in
    /// both keep their value (sign-flipped by `flip` when the pair's order reversed), new
    /// pairs start at `T::default()`.
    pub fn carry_over<T: Copy + Default>(
        &self,
        old: &VerletList,
        old_values: &[T],
        old_index: &[u32],
        flip: impl Fn(T) -> T,
    ) -> Vec<T> {
        let mut values = vec![T::default(); self.len()];
        if old.start.len() != self.start.len() {
            return values;
        }
        for i in 0..self.start.len() - 1 {
            for q in self.start[i]..self.start[i + 1] {
                let (a, b) = (old_index[i], old_index[self.neighbours[q] as usize]);
                let (lo, hi) = (a.min(b) as usize, a.max(b));
                let row = &old.neighbours[old.start[lo]..old.start[lo + 1]];
                if let Ok(p) = row.binary_search(&hi) {
                    let v = old_values[old.start[lo] + p];
                    values[q] = if a < b { v } else { flip(v) };
                }
            }
        }
        values
    }
}

/// For every cut `b` of the particle order (0..=N), the pairs of the half list in
/// `start`, `neighbours` (`j > i`) that it separates, `i < b <= j`: each pair adds one to
/// the cuts `i + 1..=j` (a difference array, summed).
fn crossings(start: &[usize], neighbours: &[u32]) -> Vec<usize> {
    let n = start.len() - 1;
    let mut change = vec![0isize; n + 2];
    for i in 0..n {
        for &j in &neighbours[start[i]..start[i + 1]] {
            change[i + 1] += 1;
            change[j as usize + 1] -= 1;
        }
    }
    let mut count = 0isize;
    change[..=n]
        .iter()
        .map(|c| {
            count += c;
            count as usize
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The difference-array count equals the count of separated pairs at every cut.
    #[test]
    fn crossings_count_the_pairs_each_cut_separates() {
        // Particles 0..6; pairs (0,1) (0,4) (1,5) (2,3) (3,5) (4,5).
        let start = [0, 2, 3, 4, 5, 6, 6];
        let neighbours = [1, 4, 5, 3, 5, 5];
        let pairs = [(0, 1), (0, 4), (1, 5), (2, 3), (3, 5), (4, 5)];
        let counted = crossings(&start, &neighbours);
        assert_eq!(counted.len(), 7);
        for (b, &c) in counted.iter().enumerate() {
            let expected = pairs.iter().filter(|&&(i, j)| i < b && b <= j).count();
            assert_eq!(c, expected, "cut {b}");
        }
    }
}
