//! Linked cells: particles sorted by the cubic cell of the box they sit in, so that the
//! pairs closer than a cut-off are found in O(N).
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;

/// Most rings of cells around a particle's own that [`CellList::for_each_within`] searches.
pub const MAX_RINGS: usize = 8;

/// Particles bucketed into a grid of cells at least `cutoff` wide.
pub struct CellList {
    dims: [usize; 3],
    cell_size: Vec3,
    /// Box length along x and the Lees-Edwards offset of the box the list was built in.
    len_x: f64,
    shear_offset: f64,
    /// `start[c]..start[c+1]` indexes `particles` for cell c.
    start: Vec<usize>,
    /// Indices into the positions the list was built over.
    particles: Vec<u32>,
}

impl CellList {
    /// Buckets `positions` (inside the box) into cells no narrower than `cutoff`. A
    /// sheared box needs at least three cells along y (the scene validation ensures it),
    /// so that the rows across the y faces are distinct from the row inside.
    pub fn build(positions: &[Vec3], pbox: &PeriodicBox, cutoff: f64) -> Self {
        let all: Vec<u32> = (0..positions.len() as u32).collect();
        Self::build_of(positions, pbox, cutoff, &all)
    }

    /// [`Self::build`] over the `members` of `positions` only (indices into it, in
    /// increasing order): one size class of a mixture.
    pub fn build_of(positions: &[Vec3], pbox: &PeriodicBox, cutoff: f64, members: &[u32]) -> Self {
        let mut dims = [1usize; 3];
        let mut cell_size = Vec3::zeros();
        for k in 0..3 {
            dims[k] = ((pbox.len[k] / cutoff).floor() as usize).max(1);
            cell_size[k] = pbox.len[k] / dims[k] as f64;
        }
        let n_cells = dims[0] * dims[1] * dims[2];
        let cells: Vec<usize> = members
            .iter()
            .map(|&i| Self::cell_index(&dims, &cell_size, &positions[i as usize]))
            .collect();
        let mut start = vec![0usize; n_cells + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for c in 0..n_cells {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut particles = vec![0u32; members.len()];
        for (&i, &c) in members.iter().zip(&cells) {
            particles[fill[c]] = i;
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

    /// Cells along each axis.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// The narrowest cell width (over the three axes).
    pub fn min_cell_size(&self) -> f64 {
        self.cell_size.min()
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

    /// Cells along axis k within `rings` cells of coordinate `c` (deduplicated when the
    /// grid has fewer than `2 rings + 1` cells along k), each with the periodic image it
    /// is reached through: -1 across the lower face, 1 across the upper face, 0 inside.
    fn axis_cells(
        &self,
        k: usize,
        c: f64,
        rings: usize,
    ) -> ([(usize, i32); 2 * MAX_RINGS + 1], usize) {
        let n = self.dims[k];
        let home = ((c / self.cell_size[k]) as usize).min(n - 1);
        let mut cells = [(0, 0); 2 * MAX_RINGS + 1];
        let mut len = 0;
        let rings = rings as i64;
        for step in -rings..=rings {
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
    /// the cell of position `x`: [`Self::for_each_within`] one ring.
    pub fn for_each_near(&self, x: &Vec3, visit: impl FnMut(u32)) {
        self.for_each_within(x, 1, visit)
    }

    /// Calls `visit(j)` once for every particle in the cells within `rings` (at most
    /// [`MAX_RINGS`]) of the cell of position `x`; each distinct cell is visited once even
    /// when the grid has fewer than `2 rings + 1` cells along an axis. In a sheared box the
    /// cells across a y face are those around `x` moved by the image offset along x
    /// (docs/physics.md section 10): the row beyond the upper face is seen through its
    /// image above, shifted by `+offset`, so its particles near `x_x - offset` are the
    /// neighbours. That needs at least `2 rings + 1` cells along y, so that no row is
    /// reached both inside and through an image.
    pub fn for_each_within(&self, x: &Vec3, rings: usize, mut visit: impl FnMut(u32)) {
        debug_assert!(rings <= MAX_RINGS);
        let (ys, ny) = self.axis_cells(1, x.y, rings);
        let (zs, nz) = self.axis_cells(2, x.z, rings);
        for &(cy, image) in &ys[..ny] {
            let x_search = if image == 0 {
                x.x
            } else {
                (x.x - image as f64 * self.shear_offset).rem_euclid(self.len_x)
            };
            let (xs, nx) = self.axis_cells(0, x_search, rings);
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
