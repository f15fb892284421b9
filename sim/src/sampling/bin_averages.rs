//! Bin averages: the binned steady-state observables (docs/physics.md section 6) from
//! snapshot sums, under the conventions chosen: u, gdot, stress, P, phi_loc, J, mu, Theta,
//! Delta_v per bin, their batch-means standard errors, and the momentum-balance residual.
use crate::error::SimError;
use crate::sampling::binning::Bins;
use crate::sampling::block_sums::BlockSums;
use crate::sampling::conventions::{
    Conventions, DeltaVConvention, GdotConvention, StressConvention, ThetaConvention,
};
use crate::sampling::periodic_derivative;
use crate::sampling::snapshot::field::*;
use schema::Observable;
use serde::Serialize;

/// Regulariser of Delta_v (thesis eq 6.2).
pub const DELTA_V_EPS: f64 = 1e-5;

/// Constants that turn snapshot sums into observables.
#[derive(Clone, Debug)]
pub struct BinningContext {
    pub bins: Bins,
    /// `L_x * w * L_z`.
    pub bin_volume: f64,
    /// `L_x * L_z`, the area of a bin face.
    pub face_area: f64,
    pub eta: f64,
    /// Mean radius, the `a` of Theta.
    pub a_mean: f64,
    /// Streaming velocity at the bin centres.
    pub u_inf: Vec<f64>,
    /// Which definition of each observable.
    pub conventions: Conventions,
    /// x velocity of the periodic image above relative to the box: `gdot L_y` in a
    /// sheared (Lees-Edwards) box, 0 otherwise (docs/physics.md section 10). The bin above
    /// the top bin is the bottom bin moving this much faster.
    pub image_velocity: f64,
}

impl BinningContext {
    /// A bin velocity `v` of bin `k` + `step` (`step` = -1, 0, 1), wrapped periodically
    /// and shifted by the image velocity where it wraps across a y face.
    fn neighbour(&self, v: &[f64], k: usize, step: isize) -> f64 {
        let nb = self.bins.count as isize;
        let raw = k as isize + step;
        let image = raw.div_euclid(nb) as f64;
        v[raw.rem_euclid(nb) as usize] + image * self.image_velocity
    }

    /// `du/dy` of the bin velocities `u` under `convention`. In a sheared box `u` jumps by
    /// the image velocity across the y faces: the derivative is taken of `u` minus the
    /// ramp `image_velocity y / L_y`, which is periodic, and the ramp's slope added back.
    fn velocity_gradient(&self, u: &[f64], convention: GdotConvention) -> Vec<f64> {
        let slope = self.image_velocity / (self.bins.width * self.bins.count as f64);
        let periodic: Vec<f64> = u
            .iter()
            .enumerate()
            .map(|(k, u)| u - slope * self.bins.centre(k))
            .collect();
        let derivative = match convention {
            GdotConvention::Spectral => periodic_derivative::spectral(&periodic, self.bins.width),
            GdotConvention::Centred => periodic_derivative::centred(&periodic, self.bins.width),
        };
        derivative.into_iter().map(|g| g + slope).collect()
    }
}

/// Per-bin observables. Stresses use the positive-in-compression convention
/// (`sigma = -Cauchy stress`): `sigma = sum of stresslets / V_b`, `P = tr(sigma)/3`.
/// J, mu and Theta are NaN where P <= 0 (undefined; written as empty fields).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Observables {
    /// Mean x-velocity of the particles centred in the bin.
    pub u: Vec<f64>,
    /// `du/dy` of the time-averaged u ([`GdotConvention`]).
    pub gdot: Vec<f64>,
    /// Shear stress under the [`StressConvention`].
    pub sigma_xy: Vec<f64>,
    #[serde(rename = "P")]
    pub p: Vec<f64>,
    pub phi_loc: Vec<f64>,
    #[serde(rename = "J")]
    pub j: Vec<f64>,
    pub mu: Vec<f64>,
    #[serde(rename = "Theta")]
    pub theta: Vec<f64>,
    #[serde(rename = "Delta_v")]
    pub delta_v: Vec<f64>,
    /// Drag force density on the particles, x component.
    pub f_x: Vec<f64>,
    /// Mean number of particle centres in the bin.
    pub count: Vec<f64>,
}

impl Observables {
    /// The values of observable `o`.
    pub fn column(&self, o: Observable) -> &[f64] {
        self.columns()[o.index()]
    }

    /// Columns in the order of [`OBSERVABLES`](schema::columns::OBSERVABLES).
    pub fn columns(&self) -> [&Vec<f64>; 11] {
        [
            &self.u,
            &self.gdot,
            &self.sigma_xy,
            &self.p,
            &self.phi_loc,
            &self.j,
            &self.mu,
            &self.theta,
            &self.delta_v,
            &self.f_x,
            &self.count,
        ]
    }

    fn columns_mut(&mut self) -> [&mut Vec<f64>; 11] {
        [
            &mut self.u,
            &mut self.gdot,
            &mut self.sigma_xy,
            &mut self.p,
            &mut self.phi_loc,
            &mut self.j,
            &mut self.mu,
            &mut self.theta,
            &mut self.delta_v,
            &mut self.f_x,
            &mut self.count,
        ]
    }
}

/// Averaged profile with standard errors.
#[derive(Clone, Debug, Serialize)]
pub struct BinAverages {
    /// Bin centres.
    pub y: Vec<f64>,
    pub u_inf: Vec<f64>,
    pub mean: Observables,
    /// Standard errors: spread of the block values / sqrt(blocks).
    pub se: Observables,
    /// `rms_k[(sigmaC(k+1) - sigmaC(k))/w + f_x(k)] / rms_k f_x(k)` with the Cauchy plane
    /// stresses sigmaC at the bin faces (method of planes): the discrete steady momentum
    /// balance `d sigmaC_xy/dy + f_x = 0` (docs/physics.md section 6). None without drag.
    pub momentum_residual: Option<f64>,
    /// Snapshots averaged.
    pub snapshots: usize,
}

/// Observables of summed snapshots `s` (`n` snapshots) under `ctx.conventions`. The
/// interpolated-r.m.s. Theta uses fluctuations about `u_star`, the linear interpolation
/// between bin centres of the bin means given.
pub fn observables(
    ctx: &BinningContext,
    s: &[f64],
    n: usize,
    u_star: &[f64],
) -> Result<Observables, SimError> {
    let nb = ctx.bins.count;
    let c = &ctx.conventions;
    let per = |f: usize, k: usize| s[f * nb + k];
    let norm = 1.0 / (n as f64 * ctx.bin_volume);
    let mut o = Observables::default();
    let mut du = Vec::with_capacity(nb);
    for k in 0..nb {
        let count = per(COUNT, k);
        if count == 0.0 {
            return Err(SimError::field("run.bin_width", format!(
                "bin {k} (y = {:.2}) received no particle centre in {n} snapshots: bins too thin for the box \
                 (widen box.l_x / box.l_z or run.bin_width)", ctx.bins.centre(k))));
        }
        o.count.push(count / n as f64);
        o.u.push(per(VX, k) / count);
        o.phi_loc.push(per(VOLUME, k) * norm);
        o.p.push((per(SXX, k) + per(SYY, k) + per(SZZ, k)) * norm / 3.0);
        o.f_x.push(per(DRAG_X, k) * norm);
        let pairs = per(SXY, k) * norm;
        o.sigma_xy.push(match c.stress {
            StressConvention::Pairs => pairs,
            _ => pairs + per(SXY_DRAG, k) * norm,
        });
        let u_inf = match c.delta_v {
            DeltaVConvention::ParticleAverage => per(U_INF, k) / count,
            DeltaVConvention::BinCentre => ctx.u_inf[k],
        };
        o.delta_v
            .push((u_inf - o.u[k]).abs() / (u_inf.abs() + DELTA_V_EPS));
        du.push(match c.theta {
            ThetaConvention::LocalWindow => per(LOCAL_DU, k) / count,
            ThetaConvention::InterpolatedRms => {
                // Sum of (v - u*)^2 over the bin from the interpolation sums.
                let (below, here, above) = (
                    ctx.neighbour(u_star, k, -1),
                    u_star[k],
                    ctx.neighbour(u_star, k, 1),
                );
                let half = |base: usize, left: f64, right: f64| {
                    -2.0 * (left * per(base, k) + right * per(base + 1, k))
                        + left * left * per(base + 2, k)
                        + 2.0 * left * right * per(base + 3, k)
                        + right * right * per(base + 4, k)
                };
                ((per(VX2, k) + half(LOWER, below, here) + half(UPPER, here, above)).max(0.0)
                    / count)
                    .sqrt()
            }
        });
    }
    o.gdot = ctx.velocity_gradient(&o.u, c.gdot);
    if c.stress == StressConvention::PairsDragSolvent {
        // The solvent's Cauchy shear stress eta gdot, with the compression-positive sign.
        for (sigma, g) in o.sigma_xy.iter_mut().zip(&o.gdot) {
            *sigma -= ctx.eta * g;
        }
    }
    for (k, du) in du.into_iter().enumerate() {
        let p = o.p[k];
        let defined = |v: f64| if p > 0.0 { v / p } else { f64::NAN };
        o.j.push(defined(ctx.eta * o.gdot[k].abs()));
        o.mu.push(defined(o.sigma_xy[k].abs()));
        o.theta.push(defined(ctx.eta * du / ctx.a_mean));
    }
    Ok(o)
}

impl BinAverages {
    /// Averages of the snapshots in `blocks`: means from all snapshots, standard errors
    /// from the spread of the per-block values.
    pub fn from_blocks(ctx: &BinningContext, blocks: &BlockSums) -> Result<BinAverages, SimError> {
        let nb = ctx.bins.count;
        let total = blocks.total();
        let n = blocks.taken.min(blocks.capacity());
        let u_mean: Vec<f64> = (0..nb)
            .map(|k| total[VX * nb + k] / total[COUNT * nb + k].max(1.0))
            .collect();
        let mean = observables(ctx, &total, n, &u_mean)?;
        let per_block: Vec<Observables> = blocks
            .sums
            .iter()
            .map(|b| observables(ctx, b, blocks.per_block, &mean.u))
            .collect::<Result<_, _>>()?;
        let nblk = per_block.len() as f64;
        let mut se = Observables::default();
        for (c, col) in se.columns_mut().into_iter().enumerate() {
            for k in 0..nb {
                let vals: Vec<f64> = per_block.iter().map(|o| o.columns()[c][k]).collect();
                let m = vals.iter().sum::<f64>() / nblk;
                let var = vals.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (nblk - 1.0);
                col.push((var / nblk).sqrt());
            }
        }
        let face: Vec<f64> = (0..nb)
            .map(|k| total[FACE_FX * nb + k] / (n as f64 * ctx.face_area))
            .collect();
        let (mut r2, mut f2) = (0.0, 0.0);
        for k in 0..nb {
            let r = (face[(k + 1) % nb] - face[k]) / ctx.bins.width + mean.f_x[k];
            r2 += r * r;
            f2 += mean.f_x[k] * mean.f_x[k];
        }
        let momentum_residual = (f2 > 0.0).then(|| (r2 / f2).sqrt());
        Ok(BinAverages {
            y: (0..nb).map(|k| ctx.bins.centre(k)).collect(),
            u_inf: ctx.u_inf.clone(),
            mean,
            se,
            momentum_residual,
            snapshots: n,
        })
    }

    /// Makes the observables of a shear undefined (NaN: empty fields) in every bin, mean and
    /// standard error: J = eta gdot / P, mu = |sigma_xy| / P, Theta and Delta_v, which a
    /// scene without flow has no shear rate or shear stress to scale (at rest they are
    /// ratios of noise, Delta_v in the thousands).
    pub fn undefine_shear_observables(&mut self) {
        for o in [&mut self.mean, &mut self.se] {
            for column in [&mut o.j, &mut o.mu, &mut o.theta, &mut o.delta_v] {
                column.iter_mut().for_each(|v| *v = f64::NAN);
            }
        }
    }

    /// Bins where P <= 0, so that J, mu and Theta are undefined.
    pub fn undefined_bins(&self) -> Vec<usize> {
        (0..self.y.len())
            .filter(|&k| self.mean.p[k].is_nan() || self.mean.p[k] <= 0.0)
            .collect()
    }
}
