//! The balance of the suspension temperature (docs/physics.md section 8, the nonlocal
//! closure): `Theta(y)`, thesis eq 6.1, as a field with its own steady balance,
//!
//! `l^2 d^2 Theta / dy^2 = Theta - c J^beta`,
//!
//! diffusion of Theta over the length `l` (units a), production by the local shear work,
//! `c J^beta` (the temperature a homogeneous flow at the local viscous number J would
//! have), and dissipation, `Theta` (relaxation towards it). On the periodic bins of width `w`
//! it reads `(l/w)^2 (Theta_{k+1} - 2 Theta_k + Theta_{k-1}) = Theta_k - c J_k^beta`. A plug
//! (`J -> 0`) then keeps the temperature that diffuses in from the shear bands beside it,
//! over about `l`: the nonlocal effect a local law lacks (Bhowmik & Ness, J. Rheol. 69, 423
//! (2025); thesis section 6.1).
//!
//! Fitting on a dataset's profiles: for each `(l, beta)` the measured J of every scene is
//! the source and the balance is solved for `Theta`; `c` is the least-squares factor of the
//! relative error (the solution is linear in `c`), `beta` minimises the mean squared
//! relative error of Theta for each `l` and `l` minimises it overall (nested Brent
//! searches).

use schema::columns as col;
use serde::{Deserialize, Serialize};
use surrogate::rheology::brent::minimise;
use surrogate::Dataset;

use crate::error::{Result, SolverError};

/// Range of the diffusion length searched (units a).
const LENGTH_RANGE: (f64, f64) = (0.0, 10.0);
/// Range of the production exponent searched.
const EXPONENT_RANGE: (f64, f64) = (0.05, 2.0);

/// The fitted balance `l^2 Theta'' = Theta - c J^beta`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThetaBalance {
    /// `l`, the diffusion length of Theta (units a).
    pub length: f64,
    /// `c`, the production's prefactor.
    pub prefactor: f64,
    /// `beta`, the production's exponent.
    pub exponent: f64,
}

/// A fitted balance and how well it reproduces the data it was fitted on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThetaBalanceFit {
    pub balance: ThetaBalance,
    /// Root-mean-square relative error of Theta over the fitted bins.
    pub relative_rms: f64,
    /// The same for the best local law (`l = 0`, `Theta = c J^beta`), for comparison.
    pub local_relative_rms: f64,
    /// Profiles and bins fitted.
    pub profiles: usize,
    pub bins: usize,
}

/// One measured profile: bin width, J and Theta per bin.
struct Profile {
    width: f64,
    j: Vec<f64>,
    theta: Vec<f64>,
}

impl ThetaBalance {
    /// Production `c J^beta`: the temperature of homogeneous flow at viscous number `j`.
    pub fn production(&self, j: f64) -> f64 {
        self.prefactor * j.powf(self.exponent)
    }

    /// `(l / w)^2`, the diffusion term's weight on bins of width `w`.
    pub fn diffusion_weight(&self, width: f64) -> f64 {
        (self.length / width).powi(2)
    }

    /// The steady Theta on periodic bins of width `width` for the viscous numbers `j`.
    pub fn profile(&self, width: f64, j: &[f64]) -> Vec<f64> {
        let source: Vec<f64> = j.iter().map(|&j| self.production(j)).collect();
        periodic_relaxation(self.diffusion_weight(width), &source)
    }

    /// Fits the balance on every complete profile of `data` (rows of one scene and seed, in
    /// order of y, with J and Theta in every bin; profiles with an empty J are left out).
    pub fn fit(data: &Dataset) -> Result<ThetaBalanceFit> {
        let profiles = profiles(data)?;
        let bins = profiles.iter().map(|p| p.j.len()).sum();
        if profiles.is_empty() {
            return Err(SolverError::InvalidArgument(format!(
                "{} holds no profile with J and Theta in every bin: the Theta balance has \
                 nothing to be fitted on",
                data.source_name()
            )));
        }
        let best_exponent = |length: f64| -> Result<(f64, f64, f64)> {
            let exponent = minimise(
                |b| error_at(&profiles, length, b).1,
                EXPONENT_RANGE.0,
                EXPONENT_RANGE.1,
                "fitting the exponent of the Theta balance",
            )?;
            let (prefactor, error) = error_at(&profiles, length, exponent);
            Ok((exponent, prefactor, error))
        };
        let length = minimise(
            |l| best_exponent(l).map_or(f64::INFINITY, |(_, _, e)| e),
            LENGTH_RANGE.0,
            LENGTH_RANGE.1,
            "fitting the diffusion length of the Theta balance",
        )?;
        let (exponent, prefactor, error) = best_exponent(length)?;
        let (_, _, local_error) = best_exponent(0.0)?;
        Ok(ThetaBalanceFit {
            balance: ThetaBalance {
                length,
                prefactor,
                exponent,
            },
            relative_rms: error.sqrt(),
            local_relative_rms: local_error.sqrt(),
            profiles: profiles.len(),
            bins,
        })
    }
}

/// For length `l` and exponent `b`: the least-squares prefactor `c` of the relative error and
/// the mean squared relative error of Theta with it.
fn error_at(profiles: &[Profile], length: f64, exponent: f64) -> (f64, f64) {
    let unit = ThetaBalance {
        length,
        prefactor: 1.0,
        exponent,
    };
    let ratios: Vec<f64> = profiles
        .iter()
        .flat_map(|p| {
            let shape = unit.profile(p.width, &p.j);
            shape
                .into_iter()
                .zip(&p.theta)
                .map(|(s, &t)| s / t)
                .collect::<Vec<_>>()
        })
        .collect();
    let (sum, sum_sq) = ratios
        .iter()
        .fold((0.0, 0.0), |(a, b), &r| (a + r, b + r * r));
    let prefactor = sum / sum_sq;
    let error = ratios
        .iter()
        .map(|&r| (prefactor * r - 1.0).powi(2))
        .sum::<f64>()
        / ratios.len() as f64;
    (prefactor, error)
}

/// The complete profiles of `data`, one per scene and seed.
fn profiles(data: &Dataset) -> Result<Vec<Profile>> {
    let ids = data.group_keys()?;
    let seeds = data.text(col::SEED).ok();
    let (y, j, theta) = (
        data.column(col::Y)?,
        data.column(col::J)?,
        data.column(col::THETA)?,
    );
    let key = |r: usize| (&ids[r], seeds.map(|s| &s[r]));
    let mut out = Vec::new();
    let mut start = 0;
    while start < data.n_rows() {
        let end = (start..data.n_rows())
            .find(|&r| key(r) != key(start))
            .unwrap_or(data.n_rows());
        let rows = start..end;
        start = end;
        let complete = rows
            .clone()
            .all(|r| j[r].is_finite() && j[r] >= 0.0 && theta[r].is_finite() && theta[r] > 0.0);
        if rows.len() < 3 || !complete {
            continue;
        }
        out.push(Profile {
            width: y[rows.start + 1] - y[rows.start],
            j: rows.clone().map(|r| j[r]).collect(),
            theta: rows.map(|r| theta[r]).collect(),
        });
    }
    Ok(out)
}

/// Solves `-d T_{k-1} + (1 + 2 d) T_k - d T_{k+1} = s_k` on periodic bins (`d >= 0`, at
/// least 3 bins): the cyclic tridiagonal system by the Thomas algorithm and a
/// Sherman-Morrison correction for the two corner terms.
pub fn periodic_relaxation(d: f64, source: &[f64]) -> Vec<f64> {
    let n = source.len();
    if d == 0.0 {
        return source.to_vec();
    }
    let (off, diag) = (-d, 1.0 + 2.0 * d);
    // A = T + w w^T-like correction: T has diag' with its first and last entries changed.
    let gamma = -diag;
    let mut main = vec![diag; n];
    main[0] -= gamma;
    main[n - 1] -= off * off / gamma;
    let x = thomas(off, &main, source);
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = off;
    let z = thomas(off, &main, &u);
    let factor = (x[0] + off * x[n - 1] / gamma) / (1.0 + z[0] + off * z[n - 1] / gamma);
    x.iter().zip(&z).map(|(x, z)| x - factor * z).collect()
}

/// The tridiagonal system with constant off-diagonals `off` and diagonal `main`.
fn thomas(off: f64, main: &[f64], rhs: &[f64]) -> Vec<f64> {
    let n = main.len();
    let mut c = vec![0.0; n];
    let mut x = vec![0.0; n];
    c[0] = off / main[0];
    x[0] = rhs[0] / main[0];
    for k in 1..n {
        let m = main[k] - off * c[k - 1];
        c[k] = off / m;
        x[k] = (rhs[k] - off * x[k - 1]) / m;
    }
    for k in (0..n - 1).rev() {
        x[k] -= c[k] * x[k + 1];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_periodic_solve_satisfies_every_row_with_its_corners() {
        let source: Vec<f64> = (0..7).map(|k| 1.0 + (k as f64).sin().powi(2)).collect();
        let d = 2.3;
        let t = periodic_relaxation(d, &source);
        for k in 0..7 {
            let (km, kp) = ((k + 6) % 7, (k + 1) % 7);
            let row = -d * t[km] + (1.0 + 2.0 * d) * t[k] - d * t[kp];
            assert!((row - source[k]).abs() < 1e-12, "row {k}: {row}");
        }
    }

    #[test]
    fn diffusion_conserves_the_mean_and_smooths() {
        // Summed over a period the diffusion terms cancel, so mean(T) = mean(s); a source
        // that is zero in half the bins (a plug) gets a positive T there.
        let source: Vec<f64> = (0..20).map(|k| if k < 10 { 1.0 } else { 0.0 }).collect();
        let t = periodic_relaxation(4.0, &source);
        let mean = t.iter().sum::<f64>() / 20.0;
        assert!((mean - 0.5).abs() < 1e-12);
        assert!(t[10..].iter().all(|&v| v > 0.0));
        assert!(t[..10].iter().all(|&v| v < 1.0));
    }
}
