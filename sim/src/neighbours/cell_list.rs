//! Linked cells: particles sorted by the cubic cell of the box they sit in, so that the
//! pairs closer than a cut-off are found in O(N).
use crate::integrate::periodic_box::PeriodicBox;
use crate::Vec3;

/// Particles bucketed into a grid of cells at least `cutoff` wide.
pub struct CellList {
    dims: [usize; 3],
    cell_size: Vec3,
    /// `start[c]..start[c+1]` indexes `particles` for cell c.
    start: Vec<usize>,
    particles: Vec<u32>,
}

impl CellList {
    /// Buckets `positions` (inside the box) into cells no narrower than `cutoff`.
    pub fn build(positions: &[Vec3], pbox: &PeriodicBox, cutoff: f64) -> Self {
        let mut dims = [1usize; 3];
        let mut cell_size = Vec3::zeros();
        for k in 0..3 {
            dims[k] = ((pbox.len[k] / cutoff).floor() as usize).max(1);
            cell_size[k] = pbox.len[k] / dims[k] as f64;
        }
        let n_cells = dims[0] * dims[1] * dims[2];
        let cells: Vec<usize> = positions
            .iter()
            .map(|x| Self::cell_index(&dims, &cell_size, x))
            .collect();
        let mut start = vec![0usize; n_cells + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for c in 0..n_cells {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut particles = vec![0u32; positions.len()];
        for (i, &c) in cells.iter().enumerate() {
            particles[fill[c]] = i as u32;
            fill[c] += 1;
        }
        Self {
            dims,
            cell_size,
            start,
            particles,
        }
    }

    fn cell_index(dims: &[usize; 3], size: &Vec3, x: &Vec3) -> usize {
        let mut c = [0usize; 3];
        for k in 0..3 {
            c[k] = ((x[k] / size[k]) as usize).min(dims[k] - 1);
        }
        (c[1] * dims[2] + c[2]) * dims[0] + c[0]
    }

    /// Particle indices sorted by cell (x fastest, then z, then y; by index inside a
    /// cell): a memory order in which neighbours sit close together, and in which rows of
    /// constant (y, z) stay together under a shear flow along x.
    pub fn order(&self) -> &[u32] {
        &self.particles
    }

    /// Calls `visit(j)` once for every particle in the cells adjacent to (and including)
    /// the cell of position `x`; each distinct cell is visited once even when the grid
    /// has fewer than three cells along an axis.
    pub fn for_each_near(&self, x: &Vec3, mut visit: impl FnMut(u32)) {
        let mut axes: [([usize; 3], usize); 3] = [([0; 3], 0); 3];
        for k in 0..3 {
            let n = self.dims[k];
            let c = ((x[k] / self.cell_size[k]) as usize).min(n - 1);
            let (list, len) = &mut axes[k];
            for off in [n - 1, 0, 1] {
                let v = (c + off) % n;
                if !list[..*len].contains(&v) {
                    list[*len] = v;
                    *len += 1;
                }
            }
        }
        let (xs, ys, zs) = (&axes[0], &axes[1], &axes[2]);
        for &cx in &xs.0[..xs.1] {
            for &cy in &ys.0[..ys.1] {
                for &cz in &zs.0[..zs.1] {
                    let c = (cy * self.dims[2] + cz) * self.dims[0] + cx;
                    for &j in &self.particles[self.start[c]..self.start[c + 1]] {
                        visit(j);
                    }
                }
            }
        }
    }
}
