//! Damped Newton iterations on the binned momentum balance, and on the Theta balance when
//! the closure reads Theta.
//!
//! Unknowns: the bin velocities `u_k` (units a/time), the uniform pressure `P` (units
//! eta/time; solved as `ln P` so it stays positive) and, for the nonlocal closure, the bin
//! temperatures `Theta_k` (solved as `ln Theta_k`). Equations, on `n` periodic bins of width
//! `w` (the same balance `simulate` checks, stresses positive in compression):
//! - per bin `(sigma_{k+1/2} - sigma_{k-1/2}) / w = f_k`: the particle shear stress at the bin
//!   faces balances the drag density `f_k = c phi_loc_k (u_inf,k - u_k)` (`u_inf,k` the
//!   forcing averaged over the bin, [`ProfileProblem::u_inf_mean`]), with
//!   `c = 6 pi eta <a> / <V_p>` (Stokes drag per particle over mean particle volume, thesis
//!   eq 3.5) and `sigma_{k+1/2} = -sign(gdot) mu P`, `gdot = (u_{k+1} - u_k) / w`;
//! - the normal stress is uniform along y (one `P`), and `phi_loc` averages to `phi`;
//! - for the nonlocal closure, per bin the Theta balance
//!   `(l/w)^2 (Theta_{k+1} - 2 Theta_k + Theta_{k-1}) = Theta_k - c J_k^beta`
//!   ([`crate::theta_balance`]), divided by `Theta_k`;
//! - closure at every face and bin centre: `J = eta |gdot| / P` and the closure's second
//!   feature, `Delta_v = |u_inf - u| / (|u_inf| + 1e-5)` (eq 6.2), `Theta` (the bin's, and
//!   the geometric mean of the two bins' at a face) or `d_ext`, the distance of the face or
//!   bin centre to the nearest zero of the faces' shear rates (`surrogate::shear_zeros`),
//!   give `(phi_loc, mu)`: mu at the faces, phi_loc at the bin centres. A solved bin's stress is the mean of its two faces'
//!   ([`ProfileSolution::sigma_xy`]).
//!
//! `|gdot|` is regularised as `sqrt(gdot^2 + delta^2)` with `delta` a thousandth of the
//! forcing's largest shear rate: at a velocity extremum `gdot` changes sign, and both laws
//! have an infinite slope at `J = 0` that would otherwise stall Newton's method.
//! A learned closure made of trees is piecewise constant; it is evaluated as the expected
//! prediction over a small box around each input (`Forest::expected`), which is continuous.
//! The Jacobian is assembled from finite differences: every row depends only on the
//! unknowns of its own bin and its two neighbours (and on `ln P`), so the columns of bins
//! three or more apart are perturbed together, in three to five residual evaluations per
//! block of unknowns, and each change is credited to the rows beside the bin it perturbed.
//! `d_ext` is the exception: where the velocity extrema lie depends on the three bins around
//! each one, however far from the bin that reads it. The coloured differences are taken with
//! the extrema held where they are (a perturbed bin would otherwise move an extremum and
//! credit the change of distant rows to its neighbours), and each extremum's effect is
//! added: the change of every row when it moves (one more residual per extremum) times its
//! exact gradient in its bins' velocities (`surrogate::ShearZero::gradient`).

use nalgebra::{linalg::LU, DMatrix, DVector, Dyn};

use surrogate::{distance_to_nearest, extremum_distances, shear_zero_faces, shear_zeros};

use crate::closure::{Closure, Descriptor, MU, PHI_LOC};
use crate::error::{Result, SolverError, Stall};
use crate::problem::ProfileProblem;
use crate::solution::ProfileSolution;
use crate::theta_balance::ThetaBalance;

/// Regulariser of Delta_v's denominator (eq 6.2).
const DELTA_V_EPSILON: f64 = 1e-5;
/// Shear-rate floor as a fraction of the forcing's largest shear rate.
const SHEAR_FLOOR: f64 = 1e-3;
/// Newton iterations before giving up, from `u = u_inf`.
const MAX_ITERATIONS: usize = 30;
/// Newton iterations of a closure from the law's solution before the continuation.
const DIRECT_ITERATIONS: usize = 12;
/// Newton iterations from `u = u_inf` before the continuation: where the law's solution
/// misleads a tree closure, the forcing is often a good start (1-3 iterations on the shipped
/// tables), and a continuation that stalls costs tens of Jacobians.
const FORCING_ITERATIONS: usize = 6;
/// Newton iterations before a step of the continuation is halved: a converging step takes
/// 3-8 from the last solution.
const STEP_ITERATIONS: usize = 12;
/// Newton's method gives up when this many fresh Jacobians in a row have not brought the
/// residual below [`PROGRESS_REDUCTION`] of what it was before them: an attempt stuck on a
/// kink of the trees then leaves room for the next one. Chosen on the shipped models' solves
/// (the 192 of the bands' calibration and the 48 of 50-bin scenes, every closure): no
/// converging call went through such a stretch (the longest plateau before convergence
/// lasted 4 Jacobians), and the attempts that failed took 45-47 % fewer Jacobians.
const PROGRESS_WINDOW: usize = 5;
/// The reduction of the residual's largest entry expected over [`PROGRESS_WINDOW`] fresh
/// Jacobians.
const PROGRESS_REDUCTION: f64 = 0.5;
/// Converged when every scaled residual is below this.
pub const TOLERANCE: f64 = 1e-9;
/// A kept Jacobian's full step is taken when it brings the residual's norm below this
/// fraction of the last one.
const KEPT_JACOBIAN_REDUCTION: f64 = 0.5;
/// Relative finite-difference step of the Jacobian.
const FD_STEP: f64 = 1e-7;
/// Smallest step in the continuation weight before the solve gives up.
const MIN_CONTINUATION_STEP: f64 = 1.0 / 64.0;

/// One bin centre's drag density and local state.
struct BinState {
    f: f64,
    phi_loc: f64,
    j: f64,
    delta_v: f64,
    gdot: f64,
}

/// The residuals at one point, with each bin's `phi_loc` (for the volume row's Jacobian).
pub(crate) struct Evaluation {
    pub(crate) r: DVector<f64>,
    phi_loc: Vec<f64>,
}

/// `(1 - weight) law + weight closure`, reading the closure's second feature (a law of J
/// alone ignores it): the path of the continuation in [`ProfileProblem::solve`].
struct Blend<'a> {
    law: &'a dyn Closure,
    closure: &'a dyn Closure,
    weight: f64,
}

impl Closure for Blend<'_> {
    fn evaluate(&self, j: f64, descriptor: f64, phi: f64) -> Result<(f64, f64)> {
        let (p0, m0) = self.law.evaluate(j, descriptor, phi)?;
        let (p1, m1) = self.closure.evaluate(j, descriptor, phi)?;
        let w = self.weight;
        Ok(((1.0 - w) * p0 + w * p1, (1.0 - w) * m0 + w * m1))
    }

    fn evaluate_output(&self, j: f64, descriptor: f64, phi: f64, output: usize) -> Result<f64> {
        let v0 = self.law.evaluate_output(j, descriptor, phi, output)?;
        let v1 = self.closure.evaluate_output(j, descriptor, phi, output)?;
        let w = self.weight;
        Ok((1.0 - w) * v0 + w * v1)
    }

    fn descriptor(&self) -> Descriptor<'_> {
        self.closure.descriptor()
    }
}

/// A point where Newton's method converged, and how it got there.
struct Converged {
    x: DVector<f64>,
    iterations: usize,
    residual: f64,
}

/// Where the unknowns sit in the state vector.
#[derive(Clone, Copy)]
pub(crate) struct Layout<'a> {
    pub(crate) n: usize,
    pub(crate) balance: Option<&'a ThetaBalance>,
}

impl Layout<'_> {
    pub(crate) fn ln_p(&self) -> usize {
        self.n
    }

    /// Index of bin `k`'s `ln Theta`.
    pub(crate) fn theta(&self, k: usize) -> usize {
        self.n + 1 + k
    }

    pub(crate) fn len(&self) -> usize {
        self.n + 1 + if self.balance.is_some() { self.n } else { 0 }
    }
}

impl ProfileProblem {
    pub(crate) fn floor(&self) -> f64 {
        let w = self.bin_width;
        let n = self.n_bins();
        let max_shear = (0..n)
            .map(|k| (self.u_inf[(k + 1) % n] - self.u_inf[k]).abs() / w)
            .fold(0.0, f64::max);
        SHEAR_FLOOR * max_shear
    }

    fn delta_v(u_inf: f64, u: f64) -> f64 {
        (u_inf - u).abs() / (u_inf.abs() + DELTA_V_EPSILON)
    }

    /// Where the faces' shear rates of the bin velocities in `x` change sign, when
    /// `closure` reads the distance to them (empty otherwise).
    pub(crate) fn zeros(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        x: &DVector<f64>,
    ) -> Vec<f64> {
        match closure.descriptor() {
            Descriptor::ExtremumDistance => shear_zeros(&x.as_slice()[..layout.n], self.bin_width),
            _ => Vec::new(),
        }
    }

    /// The local state at the face between bins `k` and `k + 1`: its `J`, the closure's
    /// second feature and its shear rate `gdot` with the regularised `|gdot|`.
    pub(crate) fn face_state(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        x: &DVector<f64>,
        k: usize,
        floor: f64,
        zeros: &[f64],
    ) -> (f64, f64, f64, f64) {
        let k1 = (k + 1) % layout.n;
        let p = x[layout.ln_p()].exp();
        let g = (x[k1] - x[k]) / self.bin_width;
        let magnitude = (g * g + floor * floor).sqrt();
        let j = self.eta * magnitude / p;
        let second = match closure.descriptor() {
            Descriptor::None => 0.0,
            Descriptor::DeltaV => Self::delta_v(
                0.5 * (self.u_inf_mean[k] + self.u_inf_mean[k1]),
                0.5 * (x[k] + x[k1]),
            ),
            Descriptor::Theta(_) => (0.5 * (x[layout.theta(k)] + x[layout.theta(k1)])).exp(),
            Descriptor::ExtremumDistance => distance_to_nearest(
                (k + 1) as f64 * self.bin_width,
                zeros,
                layout.n as f64 * self.bin_width,
            ),
        };
        (j, second, g, magnitude)
    }

    /// Shear stress at the face between bins `k` and `k + 1`.
    fn face(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        x: &DVector<f64>,
        k: usize,
        floor: f64,
        zeros: &[f64],
    ) -> Result<f64> {
        let p = x[layout.ln_p()].exp();
        let (j, second, g, magnitude) = self.face_state(closure, layout, x, k, floor, zeros);
        let mu = closure.evaluate_output(j, second, self.phi, MU)?;
        Ok(-(g / magnitude) * mu * p)
    }

    /// Bin `k`'s drag density and local state.
    fn bin(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        x: &DVector<f64>,
        k: usize,
        floor: f64,
        zeros: &[f64],
    ) -> Result<BinState> {
        let (j, second, delta_v, gdot) = self.bin_state(closure, layout, x, k, floor, zeros);
        let phi_loc = closure.evaluate_output(j, second, self.phi, PHI_LOC)?;
        Ok(BinState {
            f: self.drag_coefficient * phi_loc * (self.u_inf_mean[k] - x[k]),
            phi_loc,
            j,
            delta_v,
            gdot,
        })
    }

    /// Bin `k`'s `J`, the closure's second feature, `Delta_v` and centred shear rate.
    pub(crate) fn bin_state(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        x: &DVector<f64>,
        k: usize,
        floor: f64,
        zeros: &[f64],
    ) -> (f64, f64, f64, f64) {
        let n = layout.n;
        let (um, u, up, ui) = (x[(k + n - 1) % n], x[k], x[(k + 1) % n], self.u_inf_mean[k]);
        let p = x[layout.ln_p()].exp();
        let gdot = (up - um) / (2.0 * self.bin_width);
        let j = self.eta * (gdot * gdot + floor * floor).sqrt() / p;
        let delta_v = Self::delta_v(ui, u);
        let second = match closure.descriptor() {
            Descriptor::None => 0.0,
            Descriptor::DeltaV => delta_v,
            Descriptor::Theta(_) => x[layout.theta(k)].exp(),
            Descriptor::ExtremumDistance => distance_to_nearest(
                (k as f64 + 0.5) * self.bin_width,
                zeros,
                n as f64 * self.bin_width,
            ),
        };
        (j, second, delta_v, gdot)
    }

    /// Residuals: the balance per bin scaled by the drag scale, the volume constraint, and
    /// (nonlocal closure) the Theta balance per bin divided by the bin's Theta. The
    /// velocity extrema are those of `x`, or `frozen` ones (the Jacobian's).
    pub(crate) fn evaluate(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        x: &DVector<f64>,
        floor: f64,
        frozen: Option<&[f64]>,
    ) -> Result<Evaluation> {
        let n = layout.n;
        let (w, scale) = (self.bin_width, self.drag_scale());
        let own;
        let zeros = match frozen {
            Some(z) => z,
            None => {
                own = self.zeros(closure, layout, x);
                &own
            }
        };
        let mut r = DVector::zeros(layout.len());
        let mut phi_loc = Vec::with_capacity(n);
        let mut sigma_before = self.face(closure, layout, x, n - 1, floor, zeros)?;
        for k in 0..n {
            let sigma = self.face(closure, layout, x, k, floor, zeros)?;
            let b = self.bin(closure, layout, x, k, floor, zeros)?;
            r[k] = ((sigma - sigma_before) / w - b.f) / scale;
            sigma_before = sigma;
            if let Some(balance) = layout.balance {
                let theta = |i: usize| x[layout.theta(i)].exp();
                let (tm, t, tp) = (theta((k + n - 1) % n), theta(k), theta((k + 1) % n));
                r[layout.theta(k)] = (balance.diffusion_weight(w) * (tp - 2.0 * t + tm)
                    + balance.production(b.j))
                    / t
                    - 1.0;
            }
            phi_loc.push(b.phi_loc);
        }
        r[n] = phi_loc.iter().sum::<f64>() / n as f64 - self.phi;
        Ok(Evaluation { r, phi_loc })
    }

    /// The Jacobian at `x`, whose residuals are `base`, by coloured finite differences
    /// (module documentation).
    pub(crate) fn jacobian(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        x: &DVector<f64>,
        base: &Evaluation,
        floor: f64,
    ) -> Result<DMatrix<f64>> {
        let n = layout.n;
        let zeros = self.zeros(closure, layout, x);
        let mut jac = DMatrix::zeros(layout.len(), layout.len());
        let h_u = FD_STEP * self.u_inf.iter().fold(0.0, |a: f64, &b| a.max(b.abs()));
        let mut blocks = vec![(0, h_u)];
        if layout.balance.is_some() {
            blocks.push((layout.theta(0), FD_STEP));
        }
        let mut trial = x.clone();
        for (offset, h) in blocks {
            for group in colours(n) {
                trial.copy_from(x);
                for &j in &group {
                    trial[offset + j] += h;
                }
                let e = self.evaluate(closure, layout, &trial, floor, Some(&zeros))?;
                for &j in &group {
                    let mut volume = 0.0;
                    for i in [(j + n - 1) % n, j, (j + 1) % n] {
                        jac[(i, offset + j)] = (e.r[i] - base.r[i]) / h;
                        if layout.balance.is_some() {
                            let row = layout.theta(i);
                            jac[(row, offset + j)] = (e.r[row] - base.r[row]) / h;
                        }
                        volume += e.phi_loc[i] - base.phi_loc[i];
                    }
                    jac[(n, offset + j)] = volume / (h * n as f64);
                }
            }
        }
        trial.copy_from(x);
        trial[layout.ln_p()] += FD_STEP;
        let e = self.evaluate(closure, layout, &trial, floor, Some(&zeros))?;
        jac.set_column(layout.ln_p(), &((&e.r - &base.r) / FD_STEP));
        // The extrema move with the bins around them: each one's effect on every row, by a
        // difference in its position, times its exact gradient in those bins' velocities.
        if !zeros.is_empty() {
            let h = FD_STEP * self.bin_width;
            let mut moved = zeros.clone();
            for (c, zero) in shear_zero_faces(&x.as_slice()[..n], self.bin_width)
                .iter()
                .enumerate()
            {
                moved[c] = zeros[c] + h;
                let e = self.evaluate(closure, layout, x, floor, Some(&moved))?;
                moved[c] = zeros[c];
                let dr_dz = (&e.r - &base.r) / h;
                for (i, dz) in zero.gradient(self.bin_width).into_iter().enumerate() {
                    let mut column = jac.column_mut((zero.face + i) % n);
                    column.axpy(dz, &dr_dz, 1.0);
                }
            }
        }
        Ok(jac)
    }

    /// The drag density of the forcing, `c phi max|u_inf|`: the unit of the balance residuals.
    fn drag_scale(&self) -> f64 {
        let u_max = self.u_inf.iter().fold(0.0, |a: f64, &b| a.max(b.abs()));
        (self.drag_coefficient * self.phi * u_max).max(f64::MIN_POSITIVE)
    }

    /// The starting point: `u` and `P` of `from` (default `u = u_inf`, `P = p_start`) and,
    /// for the nonlocal closure, the Theta that the balance gives for the J of that state.
    fn start(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        from: Option<&DVector<f64>>,
        p_start: f64,
        floor: f64,
    ) -> Result<DVector<f64>> {
        let n = layout.n;
        let mut x = DVector::zeros(layout.len());
        match from {
            Some(from) => x.rows_mut(0, n + 1).copy_from(&from.rows(0, n + 1)),
            None => {
                x.rows_mut(0, n).copy_from_slice(&self.u_inf_mean);
                x[layout.ln_p()] = p_start.ln();
            }
        }
        if let Some(balance) = layout.balance {
            let j = (0..n)
                .map(|k| self.bin_state(closure, layout, &x, k, floor, &[]).0)
                .collect::<Vec<_>>();
            for (k, theta) in balance.profile(self.bin_width, &j).into_iter().enumerate() {
                x[layout.theta(k)] = theta.ln();
            }
        }
        Ok(x)
    }

    /// Solves the balance with `closure`. Without `law`, Newton's method starts from
    /// `u = u_inf` and `P = p_start`. With `law` (a closure that converges, the local
    /// rheology), three attempts in turn, the cheapest first, until one reaches
    /// [`TOLERANCE`]:
    /// 1. Newton's method from the law's solution, for [`DIRECT_ITERATIONS`];
    /// 2. Newton's method from `u = u_inf`, for [`FORCING_ITERATIONS`];
    /// 3. the continuation: the closures `(1 - s) law + s closure` from the law's solution at
    ///    `s = 0` to `s = 1`, each from the last, with steps in `s` of 1/4 that grow by half on
    ///    success and halve when [`STEP_ITERATIONS`] are not enough (down to 1/64);
    /// 4. Newton's method from `u = u_inf` for [`MAX_ITERATIONS`] (a closure of trees can
    ///    have several solutions; a continuation branch that folds back misses the one
    ///    reached from the forcing).
    ///
    /// Each attempt also ends early when [`PROGRESS_WINDOW`] fresh Jacobians in a row did not
    /// halve its residual ([`Stall::NoProgress`]).
    ///
    /// A solve that does not reach [`TOLERANCE`] is an error saying how far each got.
    pub fn solve(
        &self,
        closure: &dyn Closure,
        law: Option<&dyn Closure>,
        p_start: f64,
    ) -> Result<ProfileSolution> {
        let n = self.n_bins();
        if n < 3
            || self.u_inf_mean.len() != n
            || self.bin_width.is_nan()
            || self.bin_width <= 0.0
            || p_start.is_nan()
            || p_start <= 0.0
        {
            return Err(SolverError::InvalidArgument(format!(
                "the profile solver needs at least 3 bins of positive width, the forcing's \
                 centre and mean values on each, and a positive starting pressure ({n} bins \
                 of width {}, {} bin means, P {p_start})",
                self.bin_width,
                self.u_inf_mean.len()
            )));
        }
        let floor = self.floor();
        if floor <= 0.0 {
            return Err(SolverError::InvalidArgument(
                "the forcing u_inf has no shear: nothing drives a profile".to_owned(),
            ));
        }
        let layout = self.layout(closure);
        let Some(law) = law else {
            let x = self.start(closure, layout, None, p_start, floor)?;
            let done = self.newton(closure, layout, x, floor, MAX_ITERATIONS)?;
            return self.solution(closure, layout, &done, floor, false);
        };
        let law_layout = self.layout(law);
        let x = self.start(law, law_layout, None, p_start, floor)?;
        let law_done = self.newton(law, law_layout, x, floor, MAX_ITERATIONS)?;
        let from_law = self
            .start(closure, layout, Some(&law_done.x), p_start, floor)
            .and_then(|x| self.newton(closure, layout, x, floor, DIRECT_ITERATIONS));
        match from_law {
            Ok(done) => {
                let done = Converged {
                    iterations: law_done.iterations + done.iterations,
                    ..done
                };
                return self.solution(closure, layout, &done, floor, false);
            }
            Err(SolverError::NotConverged { .. }) => {}
            Err(e) => return Err(e),
        }
        let from_forcing = self
            .start(closure, layout, None, p_start, floor)
            .and_then(|x| self.newton(closure, layout, x, floor, FORCING_ITERATIONS));
        match from_forcing {
            Ok(done) => return self.solution(closure, layout, &done, floor, false),
            Err(SolverError::NotConverged { .. }) => {}
            Err(e) => return Err(e),
        }
        let (reached, residual) =
            match self.continuation(closure, law, layout, law_done, p_start, floor)? {
                Ok(done) => return self.solution(closure, layout, &done, floor, true),
                Err(stalled) => stalled,
            };
        let from_forcing = self
            .start(closure, layout, None, p_start, floor)
            .and_then(|x| self.newton(closure, layout, x, floor, MAX_ITERATIONS));
        match from_forcing {
            Ok(done) => self.solution(closure, layout, &done, floor, false),
            Err(e @ SolverError::NotConverged { .. }) => Err(SolverError::ContinuationStalled {
                direct: Box::new(e),
                reached,
                residual,
            }),
            Err(e) => Err(e),
        }
    }

    /// The continuation of [`ProfileProblem::solve`] from the law's solution `done`: the
    /// solution at `s = 1`, or where it stalled (the weight reached and the largest scaled
    /// residual of the last attempt).
    fn continuation(
        &self,
        closure: &dyn Closure,
        law: &dyn Closure,
        layout: Layout,
        mut done: Converged,
        p_start: f64,
        floor: f64,
    ) -> Result<std::result::Result<Converged, (f64, f64)>> {
        let (mut s, mut ds) = (0.0, 0.25);
        loop {
            let target = f64::min(s + ds, 1.0);
            let blend = Blend {
                law,
                closure,
                weight: target,
            };
            let attempt = self
                .start(&blend, layout, Some(&done.x), p_start, floor)
                .and_then(|x0| self.newton(&blend, layout, x0, floor, STEP_ITERATIONS));
            match attempt {
                Ok(next) => {
                    done = Converged {
                        iterations: done.iterations + next.iterations,
                        ..next
                    };
                    s = target;
                    if s == 1.0 {
                        return Ok(Ok(done));
                    }
                    ds *= 1.5;
                }
                Err(SolverError::NotConverged { .. }) if ds > MIN_CONTINUATION_STEP => ds *= 0.5,
                Err(SolverError::NotConverged { residual, .. }) => return Ok(Err((s, residual))),
                Err(e) => return Err(e),
            }
        }
    }

    pub(crate) fn layout<'a>(&self, closure: &'a dyn Closure) -> Layout<'a> {
        Layout {
            n: self.n_bins(),
            balance: match closure.descriptor() {
                Descriptor::Theta(balance) => Some(balance),
                _ => None,
            },
        }
    }

    /// Newton's method from `x`: the solution, the iterations taken and the final residual;
    /// it gives up at `limit` Jacobians or when the last [`PROGRESS_WINDOW`] did not bring
    /// the residual's largest entry below [`PROGRESS_REDUCTION`] of what it was before them.
    /// The Jacobian's factorisation is kept while its full steps at least halve the residual
    /// (a closure of trees is piecewise linear once smoothed, so within one piece the kept
    /// Jacobian is the exact one); a step that does not is taken again with a fresh Jacobian,
    /// damped by halving until the sum of squared residuals falls.
    fn newton(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        mut x: DVector<f64>,
        floor: f64,
        limit: usize,
    ) -> Result<Converged> {
        let norm = |e: &Evaluation| e.r.amax();
        let mut iterations = 0;
        let mut current = self.evaluate(closure, layout, &x, floor, None)?;
        let mut kept: Option<LU<f64, Dyn, Dyn>> = None;
        // The residual before each fresh Jacobian, for the progress check.
        let mut before_jacobian = Vec::with_capacity(limit + 1);
        while norm(&current) > TOLERANCE {
            let stalled = |stall, iterations| SolverError::NotConverged {
                stall,
                iterations,
                residual: norm(&current),
                tolerance: TOLERANCE,
            };
            if let Some(step) = kept.as_ref().and_then(|lu| lu.solve(&(-&current.r))) {
                let trial = &x + &step;
                let e = self.evaluate(closure, layout, &trial, floor, None)?;
                if e.r.norm() <= KEPT_JACOBIAN_REDUCTION * current.r.norm() {
                    x = trial;
                    current = e;
                    continue;
                }
            }
            if iterations == limit {
                return Err(stalled(Stall::IterationLimit(limit), iterations));
            }
            if iterations >= PROGRESS_WINDOW
                && norm(&current)
                    > PROGRESS_REDUCTION * before_jacobian[iterations - PROGRESS_WINDOW]
            {
                return Err(stalled(Stall::NoProgress(PROGRESS_WINDOW), iterations));
            }
            before_jacobian.push(norm(&current));
            iterations += 1;
            let lu = self.jacobian(closure, layout, &x, &current, floor)?.lu();
            let step = lu
                .solve(&(-&current.r))
                .ok_or_else(|| stalled(Stall::SingularJacobian, iterations))?;
            kept = Some(lu);
            let mut t = 1.0;
            loop {
                let trial = &x + &step * t;
                let e = self.evaluate(closure, layout, &trial, floor, None)?;
                if e.r.norm() < current.r.norm() || t < 1e-4 {
                    x = trial;
                    current = e;
                    break;
                }
                t *= 0.5;
            }
        }
        Ok(Converged {
            residual: norm(&current),
            x,
            iterations,
        })
    }

    fn solution(
        &self,
        closure: &dyn Closure,
        layout: Layout,
        done: &Converged,
        floor: f64,
        continued: bool,
    ) -> Result<ProfileSolution> {
        let x = &done.x;
        let mut s = ProfileSolution {
            pressure: x[layout.ln_p()].exp(),
            iterations: done.iterations,
            residual: done.residual,
            continued,
            ..ProfileSolution::default()
        };
        let n = layout.n;
        let zeros = self.zeros(closure, layout, x);
        let faces: Vec<f64> = (0..n)
            .map(|k| self.face(closure, layout, x, k, floor, &zeros))
            .collect::<Result<_>>()?;
        s.d_ext = extremum_distances(&x.as_slice()[..n], self.bin_width);
        for k in 0..n {
            let b = self.bin(closure, layout, x, k, floor, &zeros)?;
            let sigma = 0.5 * (faces[(k + n - 1) % n] + faces[k]);
            s.u.push(x[k]);
            s.gdot.push(b.gdot);
            s.sigma_xy.push(sigma);
            s.phi_loc.push(b.phi_loc);
            s.j.push(b.j);
            s.mu.push(sigma.abs() / s.pressure);
            s.delta_v.push(b.delta_v);
            s.f_x.push(b.f);
            if layout.balance.is_some() {
                s.theta.push(x[layout.theta(k)].exp());
            }
        }
        Ok(s)
    }
}

/// Groups of bins at least three apart on `n` periodic bins: `k mod 3` for the first
/// `3 floor(n/3)` bins, each remaining bin alone.
fn colours(n: usize) -> Vec<Vec<usize>> {
    let full = 3 * (n / 3);
    let mut groups: Vec<Vec<usize>> = (0..3.min(n))
        .map(|c| (c..full).step_by(3).collect())
        .collect();
    groups.extend((full..n).map(|k| vec![k]));
    groups.retain(|g| !g.is_empty());
    groups
}

#[cfg(test)]
mod tests {
    use super::colours;

    #[test]
    fn colours_keep_bins_of_one_group_three_apart_periodically() {
        for n in 3..20 {
            let groups = colours(n);
            let mut seen: Vec<usize> = groups.iter().flatten().copied().collect();
            seen.sort_unstable();
            assert_eq!(seen, (0..n).collect::<Vec<_>>(), "n = {n}");
            for g in &groups {
                for &a in g {
                    for &b in g {
                        let d = (a + n - b) % n;
                        assert!(a == b || d.min(n - d) >= 3, "n = {n}: {a} and {b}");
                    }
                }
            }
        }
    }
}
