//! Half Verlet neighbour list with a skin (pairs i < j closer than cut-off + skin),
//! rebuilt from a cell list when a particle has moved more than half the skin.
use crate::integrate::periodic_box::PeriodicBox;
use crate::neighbours::cell_list::CellList;
use crate::Vec3;

/// Neighbour pairs in compressed-row form: the neighbours of i are
/// `neighbours[start[i]..start[i+1]]`, all greater than i and in increasing order.
#[derive(Clone, Debug, Default)]
pub struct VerletList {
    pub start: Vec<usize>,
    pub neighbours: Vec<u32>,
    /// Positions at the last build: the list is valid while no particle has moved more
    /// than `skin / 2` from here.
    pub reference: Vec<Vec3>,
    skin: f64,
}

impl VerletList {
    /// Lists every pair whose distance is below `cutoff(i, j) + skin`, using `cells`
    /// built over `positions` with cells at least as wide as the largest such distance.
    pub fn build(
        positions: &[Vec3],
        pbox: &PeriodicBox,
        cells: &CellList,
        skin: f64,
        cutoff: impl Fn(usize, usize) -> f64,
    ) -> Self {
        let n = positions.len();
        let mut start = Vec::with_capacity(n + 1);
        let mut neighbours = Vec::with_capacity(8 * n);
        start.push(0);
        for (i, x_i) in positions.iter().enumerate() {
            let row = neighbours.len();
            cells.for_each_near(x_i, |j| {
                let ju = j as usize;
                if ju > i {
                    let reach = cutoff(i, ju) + skin;
                    if pbox.separation(x_i, &positions[ju]).norm_squared() < reach * reach {
                        neighbours.push(j);
                    }
                }
            });
            neighbours[row..].sort_unstable();
            start.push(neighbours.len());
        }
        Self {
            start,
            neighbours,
            reference: positions.to_vec(),
            skin,
        }
    }

    /// Whether some particle has moved more than half the skin since the build.
    pub fn stale(&self, positions: &[Vec3], pbox: &PeriodicBox) -> bool {
        let limit = 0.25 * self.skin * self.skin;
        positions
            .iter()
            .zip(&self.reference)
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
