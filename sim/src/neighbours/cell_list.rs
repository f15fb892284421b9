//! Linked cells: particles sorted by the cubic cell of the box they sit in, so that the
//! pairs closer than a cut-off are found in O(N).
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;

/// Particles bucketed into a grid of cells at least `cutoff` wide.
pub struct CellList {
    dims: [usize; 3],
    cell_size: Vec3,
    /// Box length along x and the Lees-Edwards offset of the box the list was built in.
    len_x: f64,
    shear_offset: f64,
    /// `start[c]..start[c+1]` indexes `particles` for cell c.
    start: Vec<usize>,
    particles: Vec<u32>,
}

impl CellList {
    /// Buckets `positions` (inside the box) into cells no narrower than `cutoff`. A
    /// sheared box needs at least three cells along y (the scene validation ensures it),
    /// so that the rows across the y faces are distinct from the row inside.
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
        debug_assert!(!pbox.is_sheared() || dims[1] >= 3);
        Self {
            dims,
            cell_size,
            len_x: pbox.len.x,
            shear_offset: pbox.shear_offset(),
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

    /// Cells along axis k within one cell of coordinate `c` (deduplicated when the grid
    /// has fewer than three cells along k), each with the periodic image it is reached
    /// through: -1 across the lower face, 1 across the upper face, 0 inside.
    fn axis_cells(&self, k: usize, c: f64) -> ([(usize, i32); 3], usize) {
        let n = self.dims[k];
        let home = ((c / self.cell_size[k]) as usize).min(n - 1);
        let mut cells = [(0, 0); 3];
        let mut len = 0;
        for step in [-1i64, 0, 1] {
            let raw = home as i64 + step;
            let image = if raw < 0 {
                -1
            } else if raw >= n as i64 {
                1
            } else {
                0
            };
            let v = raw.rem_euclid(n as i64) as usize;
            if !cells[..len].iter().any(|&(u, _)| u == v) {
                cells[len] = (v, image);
                len += 1;
            }
        }
        (cells, len)
    }

    /// Calls `visit(j)` once for every particle in the cells adjacent to (and including)
    /// the cell of position `x`; each distinct cell is visited once even when the grid
    /// has fewer than three cells along an axis. In a sheared box the cells across a y
    /// face are those around `x` moved by the image offset along x (docs/physics.md
    /// section 10): the row beyond the upper face is seen through its image above, shifted
    /// by `+offset`, so its particles near `x_x - offset` are the neighbours.
    pub fn for_each_near(&self, x: &Vec3, mut visit: impl FnMut(u32)) {
        let (ys, ny) = self.axis_cells(1, x.y);
        let (zs, nz) = self.axis_cells(2, x.z);
        for &(cy, image) in &ys[..ny] {
            let x_search = if image == 0 {
                x.x
            } else {
                (x.x - image as f64 * self.shear_offset).rem_euclid(self.len_x)
            };
            let (xs, nx) = self.axis_cells(0, x_search);
            for &(cx, _) in &xs[..nx] {
                for &(cz, _) in &zs[..nz] {
                    let c = (cy * self.dims[2] + cz) * self.dims[0] + cx;
                    for &j in &self.particles[self.start[c]..self.start[c + 1]] {
                        visit(j);
                    }
                }
            }
        }
    }
}
