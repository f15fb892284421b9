//! Backward-Euler update of the dissipative loads, Stokes drag and lubrication
//! (docs/physics.md section 5): given the velocities `V` of the last step and the
//! conservative loads `F_c` at the new positions, solve
//! `(M + dt (D + R)) V' = M V + dt F_c + dt D V_inf`
//! for the new translational and angular velocities `V'`, with `M` the masses and moments
//! of inertia, `D` the one-body drag (3.5, 3.6), `V_inf` the streaming motion at each
//! particle and `R` the lubrication resistance of every pair (3.8-3.18). `M + dt (D + R)`
//! is symmetric positive definite, so the solve is preconditioned conjugate gradients
//! (each particle's own 3x3 blocks inverted), warm-started from `V`.
//!
//! The product `A d` of the search direction is carried by recurrence: with `z` the
//! preconditioned residual, `d' = z + beta d` gives `A d' = A z + beta A d`, so each
//! iteration takes one product of the network (`R z`) and two sweeps over the rows, the
//! least the two scalar products of conjugate gradients allow.
use crate::forces::drag;
use crate::forces::force_accumulation::PARALLEL_MIN_PARTICLES;
use crate::forces::resistance_network::ResistanceNetwork;
use crate::input::flow_profile::FlowProfile;
use crate::integrate::particles::Particles;
use crate::Vec3;
use nalgebra::Matrix3;
use rayon::prelude::*;

/// Rows per chunk of the sweeps. Partial sums of the dot products are taken chunk by chunk
/// and added in chunk order, so they do not depend on the thread count.
const ROW_CHUNK: usize = 1024;

/// The conjugate-gradient state of one row of the system (one particle's translation or
/// rotation).
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    /// Current solution.
    x: Vec3,
    /// Residual `b - A x` (the right-hand side `b` before the first sweep).
    r: Vec3,
    /// Search direction.
    d: Vec3,
    /// `A d`.
    q: Vec3,
    /// `m + dt 6 pi eta a` (translation) or `I + dt 8 pi eta a^3` (rotation).
    diagonal: f64,
    /// Inverse of the row's 3x3 block of the system matrix.
    preconditioner: Matrix3<f64>,
}

/// One chunk of the rows with their `z` and `w` entries.
type RowChunk<'a> = (&'a mut [Row], (&'a mut [Vec3], &'a mut [Vec3]));

/// Outcome of one solve.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveStats {
    /// Conjugate-gradient iterations taken.
    pub iterations: usize,
    /// Final residual relative to the right-hand side, `|b - A V'| / |b|`.
    pub residual: f64,
}

/// Why a solve failed: the iterations ran out or the residual stopped being finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveFailure {
    pub stats: SolveStats,
    /// The particle with the largest residual.
    pub particle: usize,
}

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveSettings {
    /// Relative residual at which the iterations stop.
    pub tolerance: f64,
    /// Iterations after which the solve is declared failed.
    pub max_iterations: usize,
}

/// Work arrays of the solve, reused every step: the N translational rows, then the N
/// rotational ones. The input and output of the network's product are kept apart,
/// contiguous: `z` (the preconditioned residual, or the warm start for the first product)
/// and `w` (the product, zeroed by the sweep that uses it).
#[derive(Default)]
pub struct ImplicitDissipation {
    rows: Vec<Row>,
    z: Vec<Vec3>,
    w: Vec<Vec3>,
    /// Each row's 3x3 block of `R` (the pairs' share of its preconditioner).
    blocks: Vec<Matrix3<f64>>,
    partial_sums: Vec<(f64, f64)>,
}

impl ImplicitDissipation {
    /// Replaces `p.vel` and `p.omega` by the backward-Euler velocities, taking the
    /// conservative loads from `p.force` and `p.torque`. `drag` gives the fluid viscosity
    /// and the streaming flow when Stokes drag is on.
    pub fn solve(
        &mut self,
        p: &mut Particles,
        network: &mut ResistanceNetwork,
        drag: Option<(f64, &FlowProfile)>,
        dt: f64,
        settings: SolveSettings,
    ) -> Result<SolveStats, SolveFailure> {
        let n = p.len();
        let b_norm = self.prepare(p, network, drag, dt).sqrt();
        let mut stats = SolveStats::default();
        // Start: the product of the warm start (in z after `prepare`), the preconditioner
        // blocks inverted, r = b - A x, z = P r.
        network.apply(&self.z, &mut self.w);
        let blocks = std::mem::take(&mut self.blocks);
        let mut rz = self.sweep(|k, row, z, w| {
            // Symmetric positive definite (its diagonal part alone is), so invertible.
            row.preconditioner = (Matrix3::identity() * row.diagonal + blocks[k] * dt)
                .try_inverse()
                .unwrap_or_else(Matrix3::zeros);
            row.r -= *w * dt + row.x * row.diagonal;
            *w = Vec3::zeros();
            *z = row.preconditioner * row.r;
            (row.r.dot(z), row.r.norm_squared())
        });
        self.blocks = blocks;
        let mut rz_last = 0.0;
        loop {
            stats.residual = if b_norm > 0.0 {
                rz.1.sqrt() / b_norm
            } else {
                0.0
            };
            if stats.residual <= settings.tolerance {
                break;
            }
            if !stats.residual.is_finite() || stats.iterations >= settings.max_iterations {
                let particle = (0..2 * n)
                    .max_by(|&a, &c| self.rows[a].r.norm().total_cmp(&self.rows[c].r.norm()))
                    .map_or(0, |row| row % n.max(1));
                return Err(SolveFailure { stats, particle });
            }
            // d = z + beta d and A d = A z + beta A d (d = z on the first iteration).
            network.apply(&self.z, &mut self.w);
            let beta = (stats.iterations > 0).then(|| rz.0 / rz_last);
            let dq = self.sweep(|_, row, z, w| {
                let az = *w * dt + *z * row.diagonal;
                *w = Vec3::zeros();
                (row.d, row.q) = match beta {
                    Some(beta) => (*z + row.d * beta, az + row.q * beta),
                    None => (*z, az),
                };
                (row.d.dot(&row.q), 0.0)
            });
            let alpha = rz.0 / dq.0;
            let next = self.sweep(|_, row, z, _| {
                row.x += row.d * alpha;
                row.r -= row.q * alpha;
                *z = row.preconditioner * row.r;
                (row.r.dot(z), row.r.norm_squared())
            });
            rz_last = rz.0;
            rz = next;
            stats.iterations += 1;
        }
        for (i, (v, w)) in p.vel.iter_mut().zip(p.omega.iter_mut()).enumerate() {
            (*v, *w) = (self.rows[i].x, self.rows[n + i].x);
        }
        Ok(stats)
    }

    /// Applies `f(index, row, z, w)` to every row, in parallel chunks when the system is
    /// large enough, and returns the sums of its two outputs in chunk order.
    fn sweep(
        &mut self,
        f: impl Fn(usize, &mut Row, &mut Vec3, &mut Vec3) -> (f64, f64) + Sync + Send,
    ) -> (f64, f64) {
        let chunk = |(k, (rows, (z, w))): (usize, RowChunk)| {
            let mut s = (0.0, 0.0);
            let rows = rows.iter_mut().zip(z.iter_mut().zip(w.iter_mut()));
            for (r, (row, (z, w))) in rows.enumerate() {
                let (a, b) = f(k * ROW_CHUNK + r, row, z, w);
                s.0 += a;
                s.1 += b;
            }
            s
        };
        // Below the parallel threshold, one task runs every chunk in order.
        let min_chunks = if self.rows.len() < 2 * PARALLEL_MIN_PARTICLES {
            usize::MAX
        } else {
            1
        };
        self.rows
            .par_chunks_mut(ROW_CHUNK)
            .zip(
                self.z
                    .par_chunks_mut(ROW_CHUNK)
                    .zip(self.w.par_chunks_mut(ROW_CHUNK)),
            )
            .enumerate()
            .with_min_len(min_chunks)
            .map(chunk)
            .collect_into_vec(&mut self.partial_sums);
        self.partial_sums
            .iter()
            .fold((0.0, 0.0), |s, p| (s.0 + p.0, s.1 + p.1))
    }

    /// Sizes the work arrays, sums each row's block of `R` into `blocks` and fills each
    /// row's warm start `x = V` (also in `z`, the input of the first product), right-hand
    /// side (in `r`) and diagonal; returns `|b|^2`.
    fn prepare(
        &mut self,
        p: &Particles,
        network: &mut ResistanceNetwork,
        drag: Option<(f64, &FlowProfile)>,
        dt: f64,
    ) -> f64 {
        let n = p.len();
        self.rows.resize(2 * n, Row::default());
        self.z.resize(2 * n, Vec3::zeros());
        self.w.resize(2 * n, Vec3::zeros());
        self.blocks.resize(2 * n, Matrix3::zeros());
        let b_squared = self.sweep(|k, row, z, w| {
            let (i, rotational) = (k % n, k >= n);
            let (v, load, mass) = if rotational {
                (p.omega[i], p.torque[i], p.inertia(i))
            } else {
                (p.vel[i], p.force[i], p.mass[i])
            };
            row.x = v;
            *z = v;
            *w = Vec3::zeros();
            row.r = v * mass + load * dt;
            row.diagonal = mass;
            if let Some((eta, profile)) = drag {
                let a = p.radius[i];
                let y = p.pos[i].y;
                // The drag load at rest is the inflow term `D V_inf`.
                if rotational {
                    row.r += drag::torque(eta, a, profile.du_dy(y), &Vec3::zeros()) * dt;
                    row.diagonal += dt * drag::rotational_resistance(eta, a);
                } else {
                    row.r += drag::force(eta, a, profile.u(y), &Vec3::zeros()) * dt;
                    row.diagonal += dt * drag::translational_resistance(eta, a);
                }
            }
            (row.r.norm_squared(), 0.0)
        });
        self.blocks.fill(Matrix3::zeros());
        let (translation, rotation) = self.blocks.split_at_mut(n);
        network.diagonal_blocks(translation, rotation);
        b_squared.0
    }
}
