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
        self.prepare(p, network, drag, dt);
        let mut stats = SolveStats::default();
        // Start: the product of the warm start, then r = b - A x, z = P r, d = z.
        for (d, row) in self.direction.iter_mut().zip(&self.rows) {
            *d = row.x;
        }
        network.apply(&self.direction, &mut self.product);
        let b_norm = self
            .rows
            .iter()
            .map(|row| row.b.norm_squared())
            .sum::<f64>()
            .sqrt();
        let mut rz = self.sweep(|row, d, q| {
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
            let dq = self.sweep(|row, d, q| {
                *q = *q * dt + *d * row.diagonal;
                (d.dot(q), 0.0)
            });
            let alpha = rz.0 / dq.0;
            let next = self.sweep(|row, d, q| {
                row.x += *d * alpha;
                row.r -= *q * alpha;
                row.z = row.preconditioner * row.r;
                (row.r.dot(&row.z), row.r.norm_squared())
            });
            let beta = next.0 / rz.0;
            rz = next;
            self.sweep(|row, d, _| {
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

    /// Applies `f(row, direction, product)` to every row, in parallel chunks when the
    /// system is large enough, and returns the sums of its two outputs in chunk order.
    fn sweep(
        &mut self,
        f: impl Fn(&mut Row, &mut Vec3, &mut Vec3) -> (f64, f64) + Sync + Send,
    ) -> (f64, f64) {
        let chunk = |(rows, (d, q)): (&mut [Row], (&mut [Vec3], &mut [Vec3]))| {
            let mut s = (0.0, 0.0);
            for (row, (d, q)) in rows.iter_mut().zip(d.iter_mut().zip(q.iter_mut())) {
                let (a, b) = f(row, d, q);
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
            self.partial_sums.extend(chunks.map(chunk));
        } else {
            self.rows
                .par_chunks_mut(ROW_CHUNK)
                .zip(
                    self.direction
                        .par_chunks_mut(ROW_CHUNK)
                        .zip(self.product.par_chunks_mut(ROW_CHUNK)),
                )
                .map(chunk)
                .collect_into_vec(&mut self.partial_sums);
        }
        self.partial_sums
            .iter()
            .fold((0.0, 0.0), |s, p| (s.0 + p.0, s.1 + p.1))
    }

    /// Sizes the work arrays and fills each row's right-hand side, diagonal, block
    /// preconditioner and warm start `x = V`.
    fn prepare(
        &mut self,
        p: &Particles,
        network: &ResistanceNetwork,
        drag: Option<(f64, &FlowProfile)>,
        dt: f64,
    ) {
        let n = p.len();
        self.rows.resize(2 * n, Row::default());
        self.direction.resize(2 * n, Vec3::zeros());
        self.product.resize(2 * n, Vec3::zeros());
        let inv_dt = 1.0 / dt;
        let (lin, ang) = self.rows.split_at_mut(n);
        for (i, (tr, rot)) in lin.iter_mut().zip(ang.iter_mut()).enumerate() {
            let (m, inertia) = (p.mass[i], p.inertia(i));
            tr.x = p.vel[i];
            rot.x = p.omega[i];
            tr.b = p.vel[i] * m + p.force[i] * dt;
            rot.b = p.omega[i] * inertia + p.torque[i] * dt;
            (tr.diagonal, rot.diagonal) = (m, inertia);
            if let Some((eta, profile)) = drag {
                let a = p.radius[i];
                let (u, du_dy) = profile.u_and_slope(p.pos[i].y);
                // The drag load at rest is the inflow term `D V_inf`.
                tr.b += drag::force(eta, a, u, &Vec3::zeros()) * dt;
                rot.b += drag::torque(eta, a, du_dy, &Vec3::zeros()) * dt;
                tr.diagonal += dt * drag::translational_resistance(eta, a);
                rot.diagonal += dt * drag::rotational_resistance(eta, a);
            }
            // The blocks are assembled as (A / dt) and inverted below.
            tr.preconditioner = Matrix3::identity() * (tr.diagonal * inv_dt);
            rot.preconditioner = Matrix3::identity() * (rot.diagonal * inv_dt);
        }
        network.add_diagonal_blocks(&mut self.rows, n, |row| &mut row.preconditioner);
        for row in &mut self.rows {
            // Symmetric positive definite (its diagonal part alone is), so invertible.
            row.preconditioner = row
                .preconditioner
                .try_inverse()
                .unwrap_or_else(Matrix3::zeros)
                * inv_dt;
        }
    }
}
