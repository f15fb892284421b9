//! Backward-Euler update of the dissipative loads, Stokes drag and lubrication
//! (docs/physics.md section 5): given the velocities `V` of the last step and the
//! conservative loads `F_c` at the new positions, solve
//! `(M + dt (D + R)) V' = M V + dt F_c + dt D V_inf`
//! for the new translational and angular velocities `V'`, with `M` the masses and moments
//! of inertia, `D` the one-body drag (3.5, 3.6), `V_inf` the streaming motion at each
//! particle and `R` the lubrication resistance of every pair (3.8-3.18). `M + dt (D + R)`
//! is symmetric positive definite, so the solve is preconditioned conjugate gradients
//! (each particle's own 3x3 blocks inverted), warm-started from `V`.
use crate::forces::drag;
use crate::forces::force_accumulation::PARALLEL_MIN_PARTICLES;
use crate::forces::resistance_network::ResistanceNetwork;
use crate::input::flow_profile::FlowProfile;
use crate::integrate::particles::Particles;
use crate::Vec3;
use nalgebra::Matrix3;
use rayon::prelude::*;

/// Rows per chunk of the vector operations. Partial sums of the dot products are taken
/// chunk by chunk and added in chunk order, so they do not depend on the thread count.
const ROW_CHUNK: usize = 1024;

/// One chunk of the rows with their direction and product entries.
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

/// The conjugate-gradient state of one row of the system (one particle's translation or
/// rotation).
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    /// Current solution.
    x: Vec3,
    /// Residual `b - A x`.
    r: Vec3,
    /// Preconditioned residual.
    z: Vec3,
    /// Right-hand side.
    b: Vec3,
    /// `m + dt 6 pi eta a` (translation) or `I + dt 8 pi eta a^3` (rotation).
    diagonal: f64,
    /// Inverse of the row's 3x3 block of the system matrix.
    preconditioner: Matrix3<f64>,
}

/// Work arrays of the solve, reused every step: the N translational rows, then the N
/// rotational ones. The search direction and its product are kept apart, contiguous, as
/// the input and output of the resistance product.
#[derive(Default)]
pub struct ImplicitDissipation {
    rows: Vec<Row>,
    direction: Vec<Vec3>,
    product: Vec<Vec3>,
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
        // Start: the product of the warm start (d = x after `prepare`), then r = b - A x,
        // z = P r, d = z.
        network.apply(&self.direction, &mut self.product);
        let mut rz = self.sweep(|_, row, d, q| {
            let ax = *q * dt + row.x * row.diagonal;
            row.r = row.b - ax;
            row.z = row.preconditioner * row.r;
            *d = row.z;
            (row.r.dot(&row.z), row.r.norm_squared())
        });
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
            network.apply(&self.direction, &mut self.product);
            let dq = self.sweep(|_, row, d, q| {
                *q = *q * dt + *d * row.diagonal;
                (d.dot(q), 0.0)
            });
            let alpha = rz.0 / dq.0;
            let next = self.sweep(|_, row, d, q| {
                row.x += *d * alpha;
                row.r -= *q * alpha;
                row.z = row.preconditioner * row.r;
                (row.r.dot(&row.z), row.r.norm_squared())
            });
            let beta = next.0 / rz.0;
            rz = next;
            self.sweep(|_, row, d, _| {
                *d = row.z + *d * beta;
                (0.0, 0.0)
            });
            stats.iterations += 1;
        }
        for (i, (v, w)) in p.vel.iter_mut().zip(p.omega.iter_mut()).enumerate() {
            (*v, *w) = (self.rows[i].x, self.rows[n + i].x);
        }
        Ok(stats)
    }

    /// Applies `f(index, row, direction, product)` to every row, in parallel chunks when
    /// the system is large enough, and returns the sums of its two outputs in chunk order.
    fn sweep(
        &mut self,
        f: impl Fn(usize, &mut Row, &mut Vec3, &mut Vec3) -> (f64, f64) + Sync + Send,
    ) -> (f64, f64) {
        let chunk = |(k, (rows, (d, q))): (usize, RowChunk)| {
            let mut s = (0.0, 0.0);
            let rows = rows.iter_mut().zip(d.iter_mut().zip(q.iter_mut()));
            for (r, (row, (d, q))) in rows.enumerate() {
                let (a, b) = f(k * ROW_CHUNK + r, row, d, q);
                s.0 += a;
                s.1 += b;
            }
            s
        };
        self.partial_sums.clear();
        if self.rows.len() < 2 * PARALLEL_MIN_PARTICLES {
            let chunks = self.rows.chunks_mut(ROW_CHUNK).zip(
                self.direction
                    .chunks_mut(ROW_CHUNK)
                    .zip(self.product.chunks_mut(ROW_CHUNK)),
            );
            self.partial_sums.extend(chunks.enumerate().map(chunk));
        } else {
            self.rows
                .par_chunks_mut(ROW_CHUNK)
                .zip(
                    self.direction
                        .par_chunks_mut(ROW_CHUNK)
                        .zip(self.product.par_chunks_mut(ROW_CHUNK)),
                )
                .enumerate()
                .map(chunk)
                .collect_into_vec(&mut self.partial_sums);
        }
        self.partial_sums
            .iter()
            .fold((0.0, 0.0), |s, p| (s.0 + p.0, s.1 + p.1))
    }

    /// Sizes the work arrays and fills each row's right-hand side, diagonal, block
    /// preconditioner `(diagonal + dt R_block)^-1` and warm start `x = V` (also in the
    /// direction array); returns `|b|^2`.
    fn prepare(
        &mut self,
        p: &Particles,
        network: &mut ResistanceNetwork,
        drag: Option<(f64, &FlowProfile)>,
        dt: f64,
    ) -> f64 {
        let n = p.len();
        self.rows.resize(2 * n, Row::default());
        self.direction.resize(2 * n, Vec3::zeros());
        self.product.resize(2 * n, Vec3::zeros());
        self.blocks.resize(2 * n, Matrix3::zeros());
        let (translation, rotation) = self.blocks.split_at_mut(n);
        network.diagonal_blocks(translation, rotation);
        let blocks = std::mem::take(&mut self.blocks);
        let b_squared = self.sweep(|k, row, d, _| {
            let (i, rotational) = (k % n, k >= n);
            let (v, load, mass) = if rotational {
                (p.omega[i], p.torque[i], p.inertia(i))
            } else {
                (p.vel[i], p.force[i], p.mass[i])
            };
            row.x = v;
            *d = v;
            row.b = v * mass + load * dt;
            row.diagonal = mass;
            if let Some((eta, profile)) = drag {
                let a = p.radius[i];
                let (u, du_dy) = profile.u_and_slope(p.pos[i].y);
                // The drag load at rest is the inflow term `D V_inf`.
                if rotational {
                    row.b += drag::torque(eta, a, du_dy, &Vec3::zeros()) * dt;
                    row.diagonal += dt * drag::rotational_resistance(eta, a);
                } else {
                    row.b += drag::force(eta, a, u, &Vec3::zeros()) * dt;
                    row.diagonal += dt * drag::translational_resistance(eta, a);
                }
            }
            // Symmetric positive definite (its diagonal part alone is), so invertible.
            row.preconditioner = (Matrix3::identity() * row.diagonal + blocks[k] * dt)
                .try_inverse()
                .unwrap_or_else(Matrix3::zeros);
            (row.b.norm_squared(), 0.0)
        });
        self.blocks = blocks;
        b_squared.0
    }
}
