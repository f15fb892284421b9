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
//! least the two scalar products of conjugate gradients allow. The work arrays are kept
//! one per quantity, so a sweep streams only the arrays it uses.
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

/// One row's entries in every work array (a row is one particle's translation or rotation).
struct RowMut<'a> {
    /// Current solution.
    x: &'a mut Vec3,
    /// Residual `b - A x` (the right-hand side `b` before the first sweep).
    r: &'a mut Vec3,
    /// Preconditioned residual `P r`.
    z: &'a mut Vec3,
    /// Search direction.
    d: &'a mut Vec3,
    /// `A d`.
    q: &'a mut Vec3,
    /// The network's product (`R x`, then `R z`), zeroed once used.
    w: &'a mut Vec3,
    /// `m + dt 6 pi eta a` (translation) or `I + dt 8 pi eta a^3` (rotation).
    diagonal: &'a mut f64,
    /// The row's 3x3 block of `R` until the first sweep inverts the block of `A` in place.
    preconditioner: &'a mut Matrix3<f64>,
}

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

/// Work arrays of the solve, reused every step, 2N rows each: the N translational rows,
/// then the N rotational ones (see [`RowMut`] for what each holds).
#[derive(Default)]
pub struct ImplicitDissipation {
    x: Vec<Vec3>,
    r: Vec<Vec3>,
    z: Vec<Vec3>,
    d: Vec<Vec3>,
    q: Vec<Vec3>,
    w: Vec<Vec3>,
    diagonal: Vec<f64>,
    preconditioner: Vec<Matrix3<f64>>,
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
        // Start: invert the preconditioner blocks, r = b - A x, z = P r.
        network.apply(&self.x, &mut self.w);
        let mut rz = self.sweep(|_, row| {
            *row.preconditioner = (Matrix3::identity() * *row.diagonal + *row.preconditioner * dt)
                .try_inverse()
                .unwrap_or_else(Matrix3::zeros);
            *row.r -= *row.w * dt + *row.x * *row.diagonal;
            *row.w = Vec3::zeros();
            *row.z = *row.preconditioner * *row.r;
            (row.r.dot(row.z), row.r.norm_squared())
        });
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
                    .max_by(|&a, &c| self.r[a].norm().total_cmp(&self.r[c].norm()))
                    .map_or(0, |row| row % n.max(1));
                return Err(SolveFailure { stats, particle });
            }
            // d = z + beta d and A d = A z + beta A d (d = z on the first iteration).
            network.apply(&self.z, &mut self.w);
            let beta = (stats.iterations > 0).then(|| rz.0 / rz_last);
            let dq = self.sweep(|_, row| {
                let az = *row.w * dt + *row.z * *row.diagonal;
                *row.w = Vec3::zeros();
                (*row.d, *row.q) = match beta {
                    Some(beta) => (*row.z + *row.d * beta, az + *row.q * beta),
                    None => (*row.z, az),
                };
                (row.d.dot(row.q), 0.0)
            });
            let alpha = rz.0 / dq.0;
            let next = self.sweep(|_, row| {
                *row.x += *row.d * alpha;
                *row.r -= *row.q * alpha;
                *row.z = *row.preconditioner * *row.r;
                (row.r.dot(row.z), row.r.norm_squared())
            });
            rz_last = rz.0;
            rz = next;
            stats.iterations += 1;
        }
        p.vel.copy_from_slice(&self.x[..n]);
        p.omega.copy_from_slice(&self.x[n..]);
        Ok(stats)
    }

    /// Applies `f(index, row)` to every row, in parallel chunks when the system is large
    /// enough, and returns the sums of its two outputs in chunk order.
    fn sweep(&mut self, f: impl Fn(usize, RowMut) -> (f64, f64) + Sync + Send) -> (f64, f64) {
        let min_chunks = if self.x.len() < 2 * PARALLEL_MIN_PARTICLES {
            usize::MAX
        } else {
            1
        };
        (
            self.x.par_chunks_mut(ROW_CHUNK),
            self.r.par_chunks_mut(ROW_CHUNK),
            self.z.par_chunks_mut(ROW_CHUNK),
            self.d.par_chunks_mut(ROW_CHUNK),
            self.q.par_chunks_mut(ROW_CHUNK),
            self.w.par_chunks_mut(ROW_CHUNK),
            self.diagonal.par_chunks_mut(ROW_CHUNK),
            self.preconditioner.par_chunks_mut(ROW_CHUNK),
        )
            .into_par_iter()
            .enumerate()
            .with_min_len(min_chunks)
            .map(|(k, (x, r, z, d, q, w, diagonal, preconditioner))| {
                let mut sums = (0.0, 0.0);
                for i in 0..x.len() {
                    let row = RowMut {
                        x: &mut x[i],
                        r: &mut r[i],
                        z: &mut z[i],
                        d: &mut d[i],
                        q: &mut q[i],
                        w: &mut w[i],
                        diagonal: &mut diagonal[i],
                        preconditioner: &mut preconditioner[i],
                    };
                    let (a, b) = f(k * ROW_CHUNK + i, row);
                    sums.0 += a;
                    sums.1 += b;
                }
                sums
            })
            .collect_into_vec(&mut self.partial_sums);
        self.partial_sums
            .iter()
            .fold((0.0, 0.0), |s, p| (s.0 + p.0, s.1 + p.1))
    }

    /// Sizes the work arrays and fills each row's warm start `x = V`, right-hand side (in
    /// `r`), diagonal and its block of `R` (in `preconditioner`); returns `|b|^2`.
    fn prepare(
        &mut self,
        p: &Particles,
        network: &mut ResistanceNetwork,
        drag: Option<(f64, &FlowProfile)>,
        dt: f64,
    ) -> f64 {
        let n = p.len();
        for v in [
            &mut self.x,
            &mut self.r,
            &mut self.z,
            &mut self.d,
            &mut self.q,
            &mut self.w,
        ] {
            v.resize(2 * n, Vec3::zeros());
        }
        self.diagonal.resize(2 * n, 0.0);
        self.preconditioner.resize(2 * n, Matrix3::zeros());
        let b_squared = self.sweep(|k, row| {
            let (i, rotational) = (k % n, k >= n);
            let (v, load, mass) = if rotational {
                (p.omega[i], p.torque[i], p.inertia(i))
            } else {
                (p.vel[i], p.force[i], p.mass[i])
            };
            *row.x = v;
            *row.r = v * mass + load * dt;
            *row.diagonal = mass;
            if let Some((eta, profile)) = drag {
                let a = p.radius[i];
                let (u, du_dy) = profile.u_and_slope(p.pos[i].y);
                // The drag load at rest is the inflow term `D V_inf`.
                if rotational {
                    *row.r += drag::torque(eta, a, du_dy, &Vec3::zeros()) * dt;
                    *row.diagonal += dt * drag::rotational_resistance(eta, a);
                } else {
                    *row.r += drag::force(eta, a, u, &Vec3::zeros()) * dt;
                    *row.diagonal += dt * drag::translational_resistance(eta, a);
                }
            }
            *row.w = Vec3::zeros();
            *row.preconditioner = Matrix3::zeros();
            (row.r.norm_squared(), 0.0)
        });
        let (translation, rotation) = self.preconditioner.split_at_mut(n);
        network.diagonal_blocks(translation, rotation);
        b_squared.0
    }
}
