//! Box totals of a homogeneous-shear run (docs/physics.md section 10): the pair stress over
//! the whole box and the rheology it gives, the relative viscosity `eta_r`, the
//! macroscopic friction `mu` and the viscous number `J`, each with a batch-means standard
//! error.
use crate::sampling::bin_averages::BinningContext;
use crate::sampling::block_sums::{BlockSums, Estimate};
use crate::sampling::snapshot::field::{SXX, SXY, SYY, SZZ};
use serde::{Deserialize, Serialize};

/// Rheology of the whole box under the imposed shear rate. Stresses are the pair
/// stresslets (contact and lubrication) over the box volume, positive in compression
/// (`sigma = -Cauchy stress`, so `sigma_xy < 0` for `gdot > 0`); the drag stresslet and
/// the solvent's own `eta gdot` are not included.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct ShearRheology {
    /// Imposed shear rate (1/time).
    pub shear_rate: f64,
    /// `sigma_xy` (units eta / time).
    pub sigma_xy: Estimate,
    /// Particle pressure `P = tr(sigma)/3`.
    #[serde(rename = "P")]
    pub p: Estimate,
    /// Relative viscosity `eta_r = -sigma_xy / (eta gdot)` (thesis section 4.2).
    pub eta_r: Estimate,
    /// Macroscopic friction `mu = -sigma_xy / P`.
    pub mu: Estimate,
    /// Viscous number `J = eta gdot / P`.
    #[serde(rename = "J")]
    pub j: Estimate,
}

/// `[sigma_xy, P, eta_r, mu, J]` of summed snapshots `s` (`n` snapshots).
fn values(ctx: &BinningContext, s: &[f64], n: usize, gdot: f64) -> [f64; 5] {
    let nb = ctx.bins.count;
    let field = |f: usize| s[f * nb..(f + 1) * nb].iter().sum::<f64>();
    let norm = 1.0 / (n as f64 * ctx.bin_volume * nb as f64);
    let sigma_xy = field(SXY) * norm;
    let p = (field(SXX) + field(SYY) + field(SZZ)) * norm / 3.0;
    [
        sigma_xy,
        p,
        -sigma_xy / (ctx.eta * gdot),
        -sigma_xy / p,
        ctx.eta * gdot / p,
    ]
}

impl ShearRheology {
    /// Box totals of the averaged snapshots in `blocks` at shear rate `gdot`: means from
    /// all snapshots, standard errors from the per-block values.
    pub fn from_blocks(ctx: &BinningContext, blocks: &BlockSums, gdot: f64) -> ShearRheology {
        let e = blocks.estimates(|s, n| values(ctx, s, n, gdot).to_vec());
        ShearRheology {
            shear_rate: gdot,
            sigma_xy: e[0],
            p: e[1],
            eta_r: e[2],
            mu: e[3],
            j: e[4],
        }
    }
}
