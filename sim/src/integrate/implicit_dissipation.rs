//! Backward-Euler update of the dissipative loads, Stokes drag and lubrication
//! (docs/physics.md section 5): given the velocities `V` of the last step and the
//! conservative loads `F_c` at the new positions, solve
//! `(M + dt (D + R)) V' = M V + dt F_c + dt D V_inf`
//! for the new translational and angular velocities `V'`, with `M` the masses and moments
//! of inertia, `D` the one-body drag (3.5, 3.6), `V_inf` the streaming motion at each
//! particle and `R` the lubrication resistance of every pair (3.8-3.18). `M + dt (D + R)`
//! is symmetric positive definite, so the solve is preconditioned conjugate gradients
//! (each particle's own 3x3 blocks inverted), warm-started from `V` or from a guess the
//! caller has (the midpoint step's corrector starts from its predictor's solution).
//!
//! The product `A d` of the search direction is carried by recurrence: with `z` the
//! preconditioned residual, `d' = z + beta d` gives `A d' = A z + beta A d`. Each
//! iteration is then two parallel passes, the least its two scalar products allow: the
//! product `R z` with the update of `d` and `A d` (and `d . A d`), then the update of the
//! solution, residual and `z` (and `r . z`). Every pass works range by range on the
//! network's ranges of particles (see `resistance_network`), each range's rows written by
//! one thread.
use crate::forces::drag;
use crate::forces::resistance_network::{Motion, ResistanceNetwork};
use crate::input::flow_profile::FlowProfile;
use crate::integrate::pass_times::{PassTimes, RangeBusy};
use crate::state::particle_ranges::{each_range, over_ranges};
use crate::state::particles::Particles;
use crate::state::Vec3;
use nalgebra::Matrix3;
use std::time::Instant;

/// The conjugate-gradient state of one row of the system (one particle's translation or
/// rotation).
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    /// Current solution.
    x: Vec3,
    /// Residual `b - A x` (the right-hand side `b` before the first product).
    r: Vec3,
    /// Search direction.
    d: Vec3,
    /// `A d`.
    q: Vec3,
    /// `m + dt 6 pi eta a` (translation) or `I + dt 8 pi eta a^3` (rotation).
    diagonal: f64,
    /// Inverse of the row's 3x3 block of the system matrix (before the first product: the
    /// row's block of `R`).
    preconditioner: Matrix3<f64>,
}

/// A particle's two rows: translation, rotation.
type Rows = [Row; 2];

/// Two scalar products summed over rows.
#[derive(Clone, Copy, Debug, Default)]
struct Sums(f64, f64);

impl std::ops::Add for Sums {
    type Output = Sums;
    fn add(self, o: Sums) -> Sums {
        Sums(self.0 + o.0, self.1 + o.1)
    }
}

/// Runs `f(k, first, rows, entries)` on every range `k` of `bounds` (particles
/// `first..bounds[k + 1]`, with their rows and entries) in parallel and adds the sums in
/// range order, so the same bounds give the same bits. With `times` the pass is timed
/// into it; without, no clock is read.
fn sum_ranges(
    bounds: &[usize],
    times: Option<&mut PassTimes>,
    rows: &mut [Rows],
    entries: &mut [Motion],
    f: &(impl Fn(usize, usize, &mut [Rows], &mut [Motion]) -> Sums + Sync),
) -> Sums {
    let Some(times) = times else {
        return over_ranges(
            bounds,
            (rows, entries),
            &|k, first, (rows, entries)| f(k, first, rows, entries),
            &|a, b| a + b,
        );
    };
    let start = Instant::now();
    let (sums, busy) = over_ranges(
        bounds,
        (rows, entries),
        &|k, first, (rows, entries)| {
            let t = Instant::now();
            (f(k, first, rows, entries), RangeBusy::until_now(t))
        },
        &|a, b| (a.0 + b.0, a.1.merge(b.1)),
    );
    times.add(busy, start);
    sums
}

/// Applies `f(m, c, row, entry)` to row `c` (0 translation, 1 rotation) of every particle
/// `m` of a range, in order, and sums its outputs.
fn each_row(
    rows: &mut [Rows],
    entries: &mut [Motion],
    mut f: impl FnMut(usize, usize, &mut Row, &mut Vec3) -> Sums,
) -> Sums {
    let mut sums = Sums::default();
    for (m, (rows, entries)) in rows.iter_mut().zip(entries).enumerate() {
        for (c, (row, entry)) in rows.iter_mut().zip(entries).enumerate() {
            sums = sums + f(m, c, row, entry);
        }
    }
    sums
}

/// A row's terms of `r . z` and `|r|^2`.
fn residual_terms(row: &Row, z: &Vec3) -> Sums {
    Sums(row.r.dot(z), row.r.norm_squared())
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

/// Work arrays of the solve, reused every step, one entry per particle. The input and
/// output of the network's product are kept apart: `z` (the preconditioned residual) and
/// `w` (the product `R z`; the warm start before the first product).
#[derive(Default)]
pub struct ImplicitDissipation {
    rows: Vec<Rows>,
    z: Vec<Motion>,
    w: Vec<Motion>,
    /// Time of the parallel passes of every solve since the timing was switched on
    /// (`None`: not timed, no clock read per pass).
    pub times: Option<PassTimes>,
}

impl ImplicitDissipation {
    /// Replaces `p.vel` and `p.omega` by the backward-Euler velocities, taking the
    /// conservative loads from `p.force` and `p.torque`. `drag` gives the fluid viscosity
    /// and the streaming flow when Stokes drag is on. The network's crossings must be
    /// indexed.
    /// `guess`, when given, is the warm start (each particle's velocity and spin) instead
    /// of `V`.
    pub fn solve(
        &mut self,
        p: &mut Particles,
        network: &ResistanceNetwork,
        drag: Option<(f64, &FlowProfile)>,
        (dt, settings): (f64, SolveSettings),
        guess: Option<&[Motion]>,
    ) -> Result<SolveStats, SolveFailure> {
        let n = p.len();
        self.rows.resize(n, Rows::default());
        self.z.resize(n, Motion::default());
        self.w.resize(n, Motion::default());
        let net: &ResistanceNetwork = network;
        let bounds = &net.bounds;
        let b_norm = self.prepare(p, net, drag, dt, guess).sqrt();
        let mut stats = SolveStats::default();
        // Start: the product of the warm start (in w after `prepare`), the preconditioner
        // blocks inverted, r = b - A x, z = P r.
        let w = &self.w;
        let mut rz = sum_ranges(
            bounds,
            self.times.as_mut(),
            &mut self.rows,
            &mut self.z,
            &|k, _, rows, z| {
                net.product_on(k, w, z);
                each_row(rows, z, |_, _, row, z| {
                    // Symmetric positive definite (its diagonal part alone is), so invertible.
                    row.preconditioner = (Matrix3::identity() * row.diagonal
                        + row.preconditioner * dt)
                        .try_inverse()
                        .unwrap_or_else(Matrix3::zeros);
                    row.r -= *z * dt + row.x * row.diagonal;
                    *z = row.preconditioner * row.r;
                    residual_terms(row, z)
                })
            },
        );
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
                let residual = |m: usize| self.rows[m][0].r.norm().max(self.rows[m][1].r.norm());
                let particle = (0..n)
                    .max_by(|&a, &c| residual(a).total_cmp(&residual(c)))
                    .unwrap_or(0);
                return Err(SolveFailure { stats, particle });
            }
            // w = R z, then d = z + beta d and A d = A z + beta A d (d = z on the first
            // iteration).
            let beta = (stats.iterations > 0).then(|| rz.0 / rz_last);
            let z = &self.z;
            let dq = sum_ranges(
                bounds,
                self.times.as_mut(),
                &mut self.rows,
                &mut self.w,
                &|k, first, rows, w| {
                    net.product_on(k, z, w);
                    each_row(rows, w, |m, c, row, w| {
                        let z = z[first + m][c];
                        let az = *w * dt + z * row.diagonal;
                        (row.d, row.q) = match beta {
                            Some(beta) => (z + row.d * beta, az + row.q * beta),
                            None => (z, az),
                        };
                        Sums(row.d.dot(&row.q), 0.0)
                    })
                },
            );
            let alpha = rz.0 / dq.0;
            let next = sum_ranges(
                bounds,
                self.times.as_mut(),
                &mut self.rows,
                &mut self.z,
                &|_, _, rows, z| {
                    each_row(rows, z, |_, _, row, z| {
                        row.x += row.d * alpha;
                        row.r -= row.q * alpha;
                        *z = row.preconditioner * row.r;
                        residual_terms(row, z)
                    })
                },
            );
            rz_last = rz.0;
            rz = next;
            stats.iterations += 1;
        }
        each_range(
            bounds,
            (&self.rows[..], (&mut p.vel[..], &mut p.omega[..])),
            &|_, _, (rows, (vel, omega))| {
                for ((v, w), rows) in vel.iter_mut().zip(omega.iter_mut()).zip(rows) {
                    (*v, *w) = (rows[0].x, rows[1].x);
                }
            },
        );
        Ok(stats)
    }

    /// Fills each row's warm start `x` (`guess`, or `V`; also in `w`, the input of the
    /// first product), right-hand side (in `r`), diagonal, and block of `R` (in
    /// `preconditioner`); returns `|b|^2`.
    fn prepare(
        &mut self,
        p: &Particles,
        network: &ResistanceNetwork,
        drag: Option<(f64, &FlowProfile)>,
        dt: f64,
        guess: Option<&[Motion]>,
    ) -> f64 {
        let sums = sum_ranges(
            &network.bounds,
            self.times.as_mut(),
            &mut self.rows,
            &mut self.w,
            &|k, first, rows, w| {
                let sums = each_row(rows, w, |m, c, row, w| {
                    let (i, rotational) = (first + m, c == 1);
                    let (v, load, mass) = if rotational {
                        (p.omega[i], p.torque[i], p.inertia(i))
                    } else {
                        (p.vel[i], p.force[i], p.mass[i])
                    };
                    row.x = guess.map_or(v, |g| g[i][c]);
                    *w = row.x;
                    row.r = v * mass + load * dt;
                    row.diagonal = mass;
                    row.preconditioner = Matrix3::zeros();
                    if let Some((eta, profile)) = drag {
                        let a = p.radius[i];
                        let rest = (&Vec3::zeros(), &Vec3::zeros());
                        let (force, torque) = drag::loads(eta, a, profile, p.pos[i].y, rest);
                        if rotational {
                            row.r += torque * dt;
                            row.diagonal += dt * drag::rotational_resistance(eta, a);
                        } else {
                            row.r += force * dt;
                            row.diagonal += dt * drag::translational_resistance(eta, a);
                        }
                    }
                    Sums(row.r.norm_squared(), 0.0)
                });
                network.diagonal_blocks_on(k, |m, translation, rotation| {
                    rows[m][0].preconditioner += translation;
                    rows[m][1].preconditioner += rotation;
                });
                sums
            },
        );
        sums.0
    }
}
