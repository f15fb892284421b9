//! Random non-overlapping polydisperse packing in a fully periodic box (docs/physics.md section 3).
//!
//! Method: centres are drawn uniformly in the box with the spheres at full size, so they
//! overlap heavily; the harmonic overlap energy `E = 1/2 sum (d_ij - r_ij)^2` over pairs
//! with `r_ij < d_ij`, `d_ij = (a_i + a_j)(1 + min_gap/2 + MARGIN)`, is then minimised by
//! FIRE (Bitzek et al., PRL 97, 170201 (2006), in the FIRE 2.0 form of Guenole et al.,
//! Comput. Mater. Sci. 175, 109584 (2020)) over a private Verlet pair list built with a
//! cell list, O(N) per iteration.
//! Below jamming (phi_J ~ 0.64 for radii 1:1.4) the minimum is `E = 0`: the relaxation
//! stops as soon as every pair clears `min_gap`. Above it, FIRE settles in a minimum with
//! `E > 0` and vanishing forces, which is reported as an error, as is running out of
//! iterations. Serial and free of hashing, so the same RNG state gives the same bits.
//!
//! Lengths are in the units of `radii` and `box_len` (the small radius `a` by convention).

use crate::error::SimError;
use crate::state::particles::sphere_volume;
use rand::Rng;

/// Extra inflation of the contact distance beyond `min_gap / 2` (relative to `a_i + a_j`),
/// so that residual overlaps of the relaxation below `MARGIN / 2` already satisfy the gap.
const MARGIN: f64 = 1e-3;
/// Verlet skin, relative to the smallest radius: the pair list holds pairs closer than
/// `d_ij + skin` and is rebuilt once a particle has moved `skin / 2`.
const SKIN: f64 = 0.5;
/// Iteration cap of the relaxation.
const MAX_ITERATIONS: usize = 100_000;
/// Jamming test: `sum |F_i|^2 < JAMMED_FORCE_RATIO * 2E` means a minimum with overlaps left.
const JAMMED_FORCE_RATIO: f64 = 1e-12;
/// FIRE parameters (unit masses, unit stiffness): time steps, mixing, step adaptation.
const DT_START: f64 = 0.05;
const DT_MAX: f64 = 0.25;
const DT_MIN: f64 = 1e-3;
const ALPHA_START: f64 = 0.1;
const F_ALPHA: f64 = 0.99;
const F_INC: f64 = 1.1;
const F_DEC: f64 = 0.5;
const N_DELAY: usize = 5;

/// Centres (each coordinate in `[0, L)`) of spheres with the given `radii` in the periodic
/// box `box_len`, such that every pair's surface gap under the minimum image satisfies
/// `|r_ij| - (a_i + a_j) >= min_gap * (a_i + a_j) / 2`, i.e. the dimensionless gap `xi`
/// of docs/physics.md section 4 is at least `min_gap`.
///
/// Deterministic for a given RNG state. Errors (never panics, never loops forever) on
/// invalid input, a box whose smallest side is below twice the largest contact distance,
/// or a volume fraction the relaxation cannot reach (jammed, or out of iterations).
pub fn random_packing(
    radii: &[f64],
    box_len: [f64; 3],
    rng: &mut impl Rng,
    min_gap: f64,
) -> Result<Vec<[f64; 3]>, SimError> {
    random_packing_watched(radii, box_len, rng, min_gap, &mut |_| true)
}

/// [`random_packing`], calling `watch` with the number of overlapping pairs after every
/// relaxation iteration (an iteration of a million spheres takes a fraction of a second,
/// the relaxation up to [`MAX_ITERATIONS`] of them): the packing stops with
/// [`SimError::InterruptedPacking`] as soon as `watch` returns false.
pub fn random_packing_watched(
    radii: &[f64],
    box_len: [f64; 3],
    rng: &mut impl Rng,
    min_gap: f64,
    watch: &mut dyn FnMut(usize) -> bool,
) -> Result<Vec<[f64; 3]>, SimError> {
    let fail = |message: String| Err(SimError::Packing(message));
    if radii.is_empty() {
        return fail("no particles".into());
    }
    if let Some((i, a)) = radii
        .iter()
        .enumerate()
        .find(|(_, a)| !(a.is_finite() && **a > 0.0))
    {
        return fail(format!(
            "radius of particle {i} must be finite and positive, got {a}"
        ));
    }
    if box_len.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
        return fail(format!(
            "box lengths must be finite and positive, got {box_len:?}"
        ));
    }
    if !(min_gap.is_finite() && min_gap >= 0.0) {
        return fail(format!(
            "min_gap must be finite and non-negative, got {min_gap}"
        ));
    }
    let inflation = 1.0 + 0.5 * min_gap + MARGIN;
    let max_contact = 2.0 * radii.iter().fold(0.0_f64, |m, &a| m.max(a)) * inflation;
    let skin = SKIN * radii.iter().fold(f64::INFINITY, |m, &a| m.min(a));
    let min_side = box_len.iter().fold(f64::INFINITY, |m, &l| m.min(l));
    if max_contact > 0.5 * min_side {
        return fail(format!(
            "box {box_len:?} too small: its smallest side must be at least twice the largest \
             contact distance {max_contact:.4} (minimum image convention)"
        ));
    }
    let volume = box_len.iter().product::<f64>();
    let solid: f64 = radii.iter().map(|&a| sphere_volume(a)).sum();
    let phi = solid / volume;
    if phi * inflation.powi(3) >= 1.0 {
        return fail(format!(
            "volume fraction {phi:.4} with min_gap {min_gap} exceeds 1"
        ));
    }

    let mut x: Vec<[f64; 3]> = radii
        .iter()
        .map(|_| std::array::from_fn(|k| wrap(rng.gen::<f64>() * box_len[k], box_len[k])))
        .collect();
    let relaxation = Relaxation {
        radii,
        box_len,
        inflation,
        clearance: 1.0 + 0.5 * min_gap + 0.5 * MARGIN,
        skin,
        cells: CellList::new(box_len, max_contact + skin, radii.len()),
        pairs: Vec::new(),
        reference: Vec::new(),
    };
    relaxation.run(&mut x, phi, watch)?;
    Ok(x)
}

/// The overlap-energy minimisation of one packing.
struct Relaxation<'a> {
    radii: &'a [f64],
    box_len: [f64; 3],
    /// Contact distance `d_ij` over `a_i + a_j`.
    inflation: f64,
    /// Required centre distance over `a_i + a_j`, slightly above `1 + min_gap / 2`.
    clearance: f64,
    /// Verlet skin (length).
    skin: f64,
    cells: CellList,
    /// Pairs `i < j` closer than `d_ij + skin` at the last rebuild.
    pairs: Vec<(usize, usize)>,
    /// Positions at the last rebuild.
    reference: Vec<[f64; 3]>,
}

/// What one force evaluation found.
struct Overlaps {
    /// Pairs closer than the required clearance.
    violations: usize,
    /// Harmonic overlap energy `E`.
    energy: f64,
}

impl Relaxation<'_> {
    /// FIRE 2.0 with semi-implicit Euler steps until no pair violates the clearance.
    fn run(
        mut self,
        x: &mut [[f64; 3]],
        phi: f64,
        watch: &mut dyn FnMut(usize) -> bool,
    ) -> Result<(), SimError> {
        let n = x.len();
        let mut v = vec![[0.0; 3]; n];
        let mut f = vec![[0.0; 3]; n];
        let (mut dt, mut alpha, mut n_positive) = (DT_START, ALPHA_START, 0);
        for _ in 0..MAX_ITERATIONS {
            let overlaps = self.forces(x, &mut f);
            if overlaps.violations == 0 {
                return Ok(());
            }
            if !watch(overlaps.violations) {
                return Err(SimError::InterruptedPacking);
            }
            let f_sq: f64 = f.iter().map(|fi| dot(fi, fi)).sum();
            if f_sq < JAMMED_FORCE_RATIO * 2.0 * overlaps.energy {
                return Err(SimError::Packing(format!(
                    "jammed at phi = {phi:.4} ({} pairs still overlap, {n} particles): the \
                     volume fraction is above random close packing for these radii",
                    overlaps.violations
                )));
            }
            let power: f64 = f.iter().zip(&v).map(|(fi, vi)| dot(fi, vi)).sum();
            if power > 0.0 {
                n_positive += 1;
                if n_positive > N_DELAY {
                    dt = (dt * F_INC).min(DT_MAX);
                    alpha *= F_ALPHA;
                }
            } else {
                n_positive = 0;
                dt = (dt * F_DEC).max(DT_MIN);
                alpha = ALPHA_START;
                for (xi, vi) in x.iter_mut().zip(&mut v) {
                    self.translate(xi, vi, -0.5 * dt);
                    *vi = [0.0; 3];
                }
            }
            for (vi, fi) in v.iter_mut().zip(&f) {
                vi.iter_mut().zip(fi).for_each(|(vk, fk)| *vk += dt * fk);
            }
            let v_norm = v.iter().map(|vi| dot(vi, vi)).sum::<f64>().sqrt();
            let mix = alpha * v_norm / f_sq.sqrt();
            for ((xi, vi), fi) in x.iter_mut().zip(&mut v).zip(&f) {
                vi.iter_mut()
                    .zip(fi)
                    .for_each(|(vk, fk)| *vk = (1.0 - alpha) * *vk + mix * fk);
                self.translate(xi, vi, dt);
            }
        }
        Err(SimError::Packing(format!(
            "no overlap-free configuration at phi = {phi:.4} ({n} particles) after \
             {MAX_ITERATIONS} relaxation iterations; lower phi or min_gap"
        )))
    }

    /// Moves `xi` by `vi * dt`, wrapped back into the box.
    fn translate(&self, xi: &mut [f64; 3], vi: &[f64; 3], dt: f64) {
        for k in 0..3 {
            xi[k] = wrap(xi[k] + dt * vi[k], self.box_len[k]);
        }
    }

    /// Harmonic overlap forces `f_i = -dE/dx_i` (unit stiffness) and overlap statistics.
    fn forces(&mut self, x: &[[f64; 3]], f: &mut [[f64; 3]]) -> Overlaps {
        if self.moved_half_skin(x) {
            self.rebuild_pairs(x);
        }
        f.iter_mut().for_each(|fi| *fi = [0.0; 3]);
        let mut overlaps = Overlaps {
            violations: 0,
            energy: 0.0,
        };
        for &(i, j) in &self.pairs {
            let r = self.separation(&x[i], &x[j]);
            let dist_sq = dot(&r, &r);
            let sum = self.radii[i] + self.radii[j];
            let contact = self.inflation * sum;
            if dist_sq >= contact * contact {
                continue;
            }
            let dist = dist_sq.sqrt();
            overlaps.violations += usize::from(dist < self.clearance * sum);
            let overlap = contact - dist;
            overlaps.energy += 0.5 * overlap * overlap;
            // Coincident centres: push apart along x rather than divide by zero.
            let n = if dist > 0.0 {
                r.map(|c| c / dist)
            } else {
                [1.0, 0.0, 0.0]
            };
            for k in 0..3 {
                f[i][k] -= overlap * n[k];
                f[j][k] += overlap * n[k];
            }
        }
        overlaps
    }

    /// Whether some particle moved more than half the skin since the last rebuild.
    fn moved_half_skin(&self, x: &[[f64; 3]]) -> bool {
        let limit = 0.25 * self.skin * self.skin;
        self.reference.is_empty()
            || x.iter().zip(&self.reference).any(|(xi, ri)| {
                let d = self.separation(ri, xi);
                dot(&d, &d) > limit
            })
    }

    fn rebuild_pairs(&mut self, x: &[[f64; 3]]) {
        self.cells.rebuild(x, self.box_len);
        let mut pairs = std::mem::take(&mut self.pairs);
        pairs.clear();
        self.cells.for_each_candidate(|i, j| {
            let r = self.separation(&x[i], &x[j]);
            let reach = self.inflation * (self.radii[i] + self.radii[j]) + self.skin;
            if dot(&r, &r) < reach * reach {
                pairs.push((i, j));
            }
        });
        self.pairs = pairs;
        self.reference.clear();
        self.reference.extend_from_slice(x);
    }

    /// Minimum-image vector from `a` to `b` (both inside the box).
    fn separation(&self, a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| {
            let (d, l) = (b[k] - a[k], self.box_len[k]);
            if d > 0.5 * l {
                d - l
            } else if d < -0.5 * l {
                d + l
            } else {
                d
            }
        })
    }
}

/// Uniform grid of cells at least as wide as the largest pair reach, with at most
/// about one cell per particle; particles are bucketed by a counting sort.
struct CellList {
    dims: [usize; 3],
    /// Particles of cell `c` are `sorted[start[c]..start[c + 1]]`.
    start: Vec<usize>,
    sorted: Vec<usize>,
    cell_of: Vec<usize>,
}

impl CellList {
    fn new(box_len: [f64; 3], cutoff: f64, n: usize) -> CellList {
        let side = cutoff.max((box_len.iter().product::<f64>() / n as f64).cbrt());
        let dims = box_len.map(|l| ((l / side) as usize).max(1));
        let cells = dims.iter().product::<usize>();
        CellList {
            dims,
            start: vec![0; cells + 1],
            sorted: vec![0; n],
            cell_of: vec![0; n],
        }
    }

    fn rebuild(&mut self, x: &[[f64; 3]], box_len: [f64; 3]) {
        self.start.iter_mut().for_each(|s| *s = 0);
        for (i, xi) in x.iter().enumerate() {
            let c: [usize; 3] = std::array::from_fn(|k| {
                ((xi[k] / box_len[k] * self.dims[k] as f64) as usize).min(self.dims[k] - 1)
            });
            self.cell_of[i] = (c[0] * self.dims[1] + c[1]) * self.dims[2] + c[2];
            self.start[self.cell_of[i] + 1] += 1;
        }
        for c in 1..self.start.len() {
            self.start[c] += self.start[c - 1];
        }
        let mut fill = self.start.clone();
        for (i, &c) in self.cell_of.iter().enumerate() {
            self.sorted[fill[c]] = i;
            fill[c] += 1;
        }
    }

    /// Calls `visit(i, j)` once for every pair `i < j` in the same or adjacent cells
    /// (periodic; an axis with fewer than 3 cells visits each neighbour cell once).
    fn for_each_candidate(&self, mut visit: impl FnMut(usize, usize)) {
        let offsets = self.dims.map(|d| match d {
            1 => vec![0],
            2 => vec![0, 1],
            _ => vec![d - 1, 0, 1],
        });
        let [nx, ny, nz] = self.dims;
        for (i, &cell) in self.cell_of.iter().enumerate() {
            let (cx, cy, cz) = (cell / (ny * nz), cell / nz % ny, cell % nz);
            for ox in &offsets[0] {
                for oy in &offsets[1] {
                    for oz in &offsets[2] {
                        let c = (((cx + ox) % nx) * ny + (cy + oy) % ny) * nz + (cz + oz) % nz;
                        for &j in &self.sorted[self.start[c]..self.start[c + 1]] {
                            if j > i {
                                visit(i, j);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// `x` wrapped into `[0, l)` (`rem_euclid` alone can round up to `l`).
fn wrap(x: f64, l: f64) -> f64 {
    let w = x.rem_euclid(l);
    if w < l {
        w
    } else {
        0.0
    }
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    const GAP: f64 = 2e-3;

    #[test]
    fn the_watch_sees_the_overlaps_of_every_iteration_and_stops_the_packing() {
        let (radii, box_len) = scene(400, 1.4, 0.55);
        let mut seen = Vec::new();
        let stopped = random_packing_watched(
            &radii,
            box_len,
            &mut StdRng::seed_from_u64(1),
            GAP,
            &mut |overlapping| {
                seen.push(overlapping);
                seen.len() < 3
            },
        );
        assert!(matches!(stopped, Err(SimError::InterruptedPacking)));
        assert_eq!(seen.len(), 3);
        assert!(seen.iter().all(|&o| o > 0), "{seen:?}");
    }

    /// Bidisperse radii 1 and `ratio` in equal numbers, in a box with `L_y = 2 L_x = 2 L_z`
    /// sized for volume fraction `phi`.
    fn scene(n: usize, ratio: f64, phi: f64) -> (Vec<f64>, [f64; 3]) {
        let radii: Vec<f64> = (0..n)
            .map(|i| if i % 2 == 0 { 1.0 } else { ratio })
            .collect();
        let solid: f64 = radii.iter().map(|&a| sphere_volume(a)).sum();
        let l = (solid / phi / 2.0).cbrt();
        (radii, [l, 2.0 * l, l])
    }

    fn pack(radii: &[f64], box_len: [f64; 3], seed: u64) -> Result<Vec<[f64; 3]>, SimError> {
        random_packing(radii, box_len, &mut StdRng::seed_from_u64(seed), GAP)
    }

    /// Brute-force check of the box bounds and every pair's minimum-image gap.
    fn assert_valid(radii: &[f64], box_len: [f64; 3], x: &[[f64; 3]]) {
        assert_eq!(x.len(), radii.len());
        for xi in x {
            assert!(
                (0..3).all(|k| xi[k] >= 0.0 && xi[k] < box_len[k]),
                "{xi:?} outside"
            );
        }
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                let r: Vec<f64> = (0..3)
                    .map(|k| {
                        let d = x[j][k] - x[i][k];
                        d - box_len[k] * (d / box_len[k]).round()
                    })
                    .collect();
                let dist = r.iter().map(|c| c * c).sum::<f64>().sqrt();
                let sum = radii[i] + radii[j];
                assert!(
                    dist - sum >= GAP * sum / 2.0,
                    "pair {i} {j} gap {}",
                    dist - sum
                );
            }
        }
    }

    #[test]
    fn bidisperse_packings_clear_the_gap() {
        for (n, phi) in [(500, 0.3), (1000, 0.54), (2000, 0.60)] {
            let (radii, box_len) = scene(n, 1.4, phi);
            assert_valid(&radii, box_len, &pack(&radii, box_len, 7).unwrap());
        }
    }

    #[test]
    fn large_size_ratio_and_few_particles() {
        let (radii, box_len) = scene(1000, 4.0, 0.5);
        assert_valid(&radii, box_len, &pack(&radii, box_len, 3).unwrap());
        let radii = [1.0, 1.4];
        assert_valid(&radii, [6.0; 3], &pack(&radii, [6.0; 3], 3).unwrap());
    }

    #[test]
    fn deterministic_per_seed() {
        let (radii, box_len) = scene(1000, 1.4, 0.54);
        let bits = |x: Vec<[f64; 3]>| x.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>();
        let first = bits(pack(&radii, box_len, 11).unwrap());
        assert_eq!(first, bits(pack(&radii, box_len, 11).unwrap()));
        assert_ne!(first, bits(pack(&radii, box_len, 12).unwrap()));
    }

    #[test]
    fn impossible_fraction_fails_fast() {
        let (radii, box_len) = scene(1000, 1.4, 0.70);
        let start = std::time::Instant::now();
        let message = pack(&radii, box_len, 1).unwrap_err().to_string();
        assert!(message.contains("jammed at phi = 0.70"), "{message}");
        assert!(start.elapsed().as_secs_f64() < 10.0);
    }

    #[test]
    fn refuses_bad_input() {
        let cases: [(&[f64], [f64; 3], f64, &str); 6] = [
            (&[], [10.0; 3], GAP, "no particles"),
            (&[1.0, -1.0], [10.0; 3], GAP, "particle 1"),
            (&[1.0, 1.0], [10.0, f64::NAN, 10.0], GAP, "box lengths"),
            (&[1.0, 1.0], [10.0; 3], f64::NAN, "min_gap"),
            (&[1.0, 1.4], [10.0, 5.0, 10.0], GAP, "too small"),
            (&[1.0; 60], [6.0; 3], GAP, "exceeds 1"),
        ];
        for (radii, box_len, gap, expected) in cases {
            let result = random_packing(radii, box_len, &mut StdRng::seed_from_u64(0), gap);
            let message = result.unwrap_err().to_string();
            assert!(message.contains(expected), "{message}");
        }
    }
}
