//! Damped Newton iterations on the binned momentum balance.
//!
//! Unknowns: the bin velocities `u_k` (units a/time) and the uniform pressure `P` (units
//! eta/time; solved as `ln P` so it stays positive). Equations, on `n` periodic bins of width
//! `w` (the same balance `simulate` checks, stresses positive in compression):
//! - per bin `(sigma_{k+1/2} - sigma_{k-1/2}) / w = f_k`: the particle shear stress at the bin
//!   faces balances the drag density `f_k = c phi_loc_k (u_inf,k - u_k)`, with
//!   `c = 6 pi eta <a> / <V_p>` (Stokes drag per particle over mean particle volume, thesis
//!   eq 3.5) and `sigma_{k+1/2} = -sign(gdot) mu P`, `gdot = (u_{k+1} - u_k) / w`;
//! - the normal stress is uniform along y (one `P`), and `phi_loc` averages to `phi`;
//! - closure at every face and bin centre: `J = eta |gdot| / P`, `Delta_v = |u_inf - u| /
//!   (|u_inf| + 1e-5)` (eq 6.2), and `(phi_loc, mu)` from the closure.
//!
//! `|gdot|` is regularised as `sqrt(gdot^2 + delta^2)` with `delta` a thousandth of the
//! forcing's largest shear rate: at a velocity extremum `gdot` changes sign, and both laws
//! have an infinite slope at `J = 0` that would otherwise stall Newton's method.
//! A learned closure made of trees is piecewise constant; it is evaluated as the expected
//! prediction over a small box around each input (`Forest::expected`), which is continuous.
//! The Jacobian is assembled from finite differences of each face's and bin's local
//! function (a face depends on two velocities, a bin on three, all on `ln P`).

use nalgebra::{DMatrix, DVector};

use crate::closure::Closure;
use crate::error::{Result, SolverError, Stall};
use crate::problem::ProfileProblem;
use crate::solution::ProfileSolution;

/// Regulariser of Delta_v's denominator (eq 6.2).
const DELTA_V_EPSILON: f64 = 1e-5;
/// Shear-rate floor as a fraction of the forcing's largest shear rate.
const SHEAR_FLOOR: f64 = 1e-3;
/// Newton iterations before giving up.
const MAX_ITERATIONS: usize = 60;
/// Converged when every scaled residual is below this.
pub const TOLERANCE: f64 = 1e-9;
/// Relative finite-difference step of the Jacobian.
const FD_STEP: f64 = 1e-7;

/// One face's shear stress and the closure's local state there.
struct FaceState {
    sigma: f64,
}

/// One bin centre's drag density and local state.
struct BinState {
    f: f64,
    phi_loc: f64,
    mu: f64,
    j: f64,
    delta_v: f64,
    gdot: f64,
}

impl ProfileProblem {
    fn floor(&self) -> f64 {
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

    /// Face between bins with velocities `u0`, `u1` (streaming `ui0`, `ui1`).
    fn face(
        &self,
        closure: &dyn Closure,
        (u0, u1, ui0, ui1): (f64, f64, f64, f64),
        ln_p: f64,
        floor: f64,
    ) -> Result<FaceState> {
        let p = ln_p.exp();
        let g = (u1 - u0) / self.bin_width;
        let magnitude = (g * g + floor * floor).sqrt();
        let j = self.eta * magnitude / p;
        let dv = Self::delta_v(0.5 * (ui0 + ui1), 0.5 * (u0 + u1));
        let (_, mu) = closure.evaluate(j, dv, self.phi)?;
        Ok(FaceState {
            sigma: -(g / magnitude) * mu * p,
        })
    }

    /// Bin `k` with neighbours' velocities `um`, `up`.
    fn bin(
        &self,
        closure: &dyn Closure,
        (um, u, up, ui): (f64, f64, f64, f64),
        ln_p: f64,
        floor: f64,
    ) -> Result<BinState> {
        let p = ln_p.exp();
        let gdot = (up - um) / (2.0 * self.bin_width);
        let j = self.eta * (gdot * gdot + floor * floor).sqrt() / p;
        let delta_v = Self::delta_v(ui, u);
        let (phi_loc, mu) = closure.evaluate(j, delta_v, self.phi)?;
        Ok(BinState {
            f: self.drag_coefficient * phi_loc * (ui - u),
            phi_loc,
            mu,
            j,
            delta_v,
            gdot,
        })
    }

    /// Residuals (balance per bin scaled by the drag scale, then the volume constraint)
    /// and their Jacobian with respect to `(u_0 .. u_{n-1}, ln P)`.
    fn linearise(
        &self,
        closure: &dyn Closure,
        x: &DVector<f64>,
        floor: f64,
        with_jacobian: bool,
    ) -> Result<(DVector<f64>, Option<DMatrix<f64>>)> {
        let n = self.n_bins();
        let (w, ln_p) = (self.bin_width, x[n]);
        let scale = self.drag_scale();
        let face_args = |x: &DVector<f64>, k: usize| {
            let k1 = (k + 1) % n;
            (x[k], x[k1], self.u_inf[k], self.u_inf[k1])
        };
        let bin_args =
            |x: &DVector<f64>, k: usize| (x[(k + n - 1) % n], x[k], x[(k + 1) % n], self.u_inf[k]);
        let mut sigma = Vec::with_capacity(n);
        let mut bins = Vec::with_capacity(n);
        for k in 0..n {
            sigma.push(self.face(closure, face_args(x, k), ln_p, floor)?.sigma);
            bins.push(self.bin(closure, bin_args(x, k), ln_p, floor)?);
        }
        let mut r = DVector::zeros(n + 1);
        for k in 0..n {
            r[k] = ((sigma[k] - sigma[(k + n - 1) % n]) / w - bins[k].f) / scale;
        }
        r[n] = bins.iter().map(|b| b.phi_loc).sum::<f64>() / n as f64 - self.phi;
        if !with_jacobian {
            return Ok((r, None));
        }
        let mut jac = DMatrix::zeros(n + 1, n + 1);
        let h_u = FD_STEP * self.u_inf.iter().fold(0.0, |a: f64, &b| a.max(b.abs()));
        for k in 0..n {
            let (km, kp) = ((k + n - 1) % n, (k + 1) % n);
            // Face k+1/2 (between k and kp) enters rows k (+) and kp (-).
            let args = face_args(x, k);
            let d0 = self.face(closure, (args.0 + h_u, args.1, args.2, args.3), ln_p, floor)?;
            let d1 = self.face(closure, (args.0, args.1 + h_u, args.2, args.3), ln_p, floor)?;
            let dp = self.face(closure, args, ln_p + FD_STEP, floor)?;
            for (col, ds) in [
                (k, (d0.sigma - sigma[k]) / h_u),
                (kp, (d1.sigma - sigma[k]) / h_u),
                (n, (dp.sigma - sigma[k]) / FD_STEP),
            ] {
                jac[(k, col)] += ds / (w * scale);
                jac[(kp, col)] -= ds / (w * scale);
            }
            // Bin k enters row k through -f and row n through phi_loc / n.
            let args = bin_args(x, k);
            let base = &bins[k];
            let shifted = [
                (
                    km,
                    self.bin(closure, (args.0 + h_u, args.1, args.2, args.3), ln_p, floor)?,
                    h_u,
                ),
                (
                    k,
                    self.bin(closure, (args.0, args.1 + h_u, args.2, args.3), ln_p, floor)?,
                    h_u,
                ),
                (
                    kp,
                    self.bin(closure, (args.0, args.1, args.2 + h_u, args.3), ln_p, floor)?,
                    h_u,
                ),
                (n, self.bin(closure, args, ln_p + FD_STEP, floor)?, FD_STEP),
            ];
            for (col, state, h) in shifted {
                jac[(k, col)] -= (state.f - base.f) / (h * scale);
                jac[(n, col)] += (state.phi_loc - base.phi_loc) / (h * n as f64);
            }
        }
        Ok((r, Some(jac)))
    }

    /// The drag density of the forcing, `c phi max|u_inf|`: the unit of the balance residuals.
    fn drag_scale(&self) -> f64 {
        let u_max = self.u_inf.iter().fold(0.0, |a: f64, &b| a.max(b.abs()));
        (self.drag_coefficient * self.phi * u_max).max(f64::MIN_POSITIVE)
    }

    /// Solves the balance with `closure`, starting from `u = u_inf` and `P = p_start`.
    /// A solve that does not reach [`TOLERANCE`] is an error saying how far it got.
    pub fn solve(&self, closure: &dyn Closure, p_start: f64) -> Result<ProfileSolution> {
        let n = self.n_bins();
        if n < 3
            || self.bin_width.is_nan()
            || self.bin_width <= 0.0
            || p_start.is_nan()
            || p_start <= 0.0
        {
            return Err(SolverError::InvalidArgument(format!(
                "the profile solver needs at least 3 bins of positive width and a positive \
                 starting pressure ({n} bins of width {}, P {p_start})",
                self.bin_width
            )));
        }
        let floor = self.floor();
        if floor <= 0.0 {
            return Err(SolverError::InvalidArgument(
                "the forcing u_inf has no shear: nothing drives a profile".to_owned(),
            ));
        }
        let mut x = DVector::from_iterator(n + 1, self.u_inf.iter().copied().chain([p_start.ln()]));
        let norm = |r: &DVector<f64>| r.amax();
        let mut iterations = 0;
        let (mut r, _) = self.linearise(closure, &x, floor, false)?;
        while norm(&r) > TOLERANCE {
            if iterations == MAX_ITERATIONS {
                return Err(SolverError::NotConverged {
                    stall: Stall::IterationLimit(MAX_ITERATIONS),
                    iterations,
                    residual: norm(&r),
                    tolerance: TOLERANCE,
                });
            }
            iterations += 1;
            let (_, jac) = self.linearise(closure, &x, floor, true)?;
            let step = jac.and_then(|j| j.lu().solve(&(-&r))).ok_or_else(|| {
                SolverError::NotConverged {
                    stall: Stall::SingularJacobian,
                    iterations,
                    residual: norm(&r),
                    tolerance: TOLERANCE,
                }
            })?;
            // Backtracking: halve the step until the residual falls.
            let mut t = 1.0;
            loop {
                let trial = &x + &step * t;
                let (r_trial, _) = self.linearise(closure, &trial, floor, false)?;
                if norm(&r_trial) < norm(&r) || t < 1e-4 {
                    x = trial;
                    r = r_trial;
                    break;
                }
                t *= 0.5;
            }
        }
        self.solution(closure, &x, floor, iterations, norm(&r))
    }

    fn solution(
        &self,
        closure: &dyn Closure,
        x: &DVector<f64>,
        floor: f64,
        iterations: usize,
        residual: f64,
    ) -> Result<ProfileSolution> {
        let n = self.n_bins();
        let ln_p = x[n];
        let mut s = ProfileSolution {
            pressure: ln_p.exp(),
            iterations,
            residual,
            ..ProfileSolution::default()
        };
        for k in 0..n {
            let b = self.bin(
                closure,
                (x[(k + n - 1) % n], x[k], x[(k + 1) % n], self.u_inf[k]),
                ln_p,
                floor,
            )?;
            s.u.push(x[k]);
            s.gdot.push(b.gdot);
            s.sigma_xy.push(-b.gdot.signum() * b.mu * s.pressure);
            s.phi_loc.push(b.phi_loc);
            s.j.push(b.j);
            s.mu.push(b.mu);
            s.delta_v.push(b.delta_v);
            s.f_x.push(b.f);
        }
        Ok(s)
    }
}
