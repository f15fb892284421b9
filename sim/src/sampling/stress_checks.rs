//! Checks of the reported (bin-averaged) stress that do not hold by construction
//! (docs/physics.md section 6): in a steady state `sigma_yy` is uniform along y (the y
//! momentum balance with no mean drag along y), and the pair shear stress balances the drag,
//! `d sigma_xy/dy = f_x`, computed here from the method-of-planes stresslet sums of the
//! bins rather than from the forces across the bin faces.
use crate::sampling::bin_averages::BinningContext;
use crate::sampling::block_sums::BlockSums;
use crate::sampling::periodic_derivative;
use crate::sampling::snapshot::field::{DRAG_X, SXY, SYY};
use serde::{Deserialize, Serialize};

/// The two checks of one averaged run.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct StressChecks {
    /// `sum_k ((sigma_yy,k - mean) / se_k)^2 / (n_bins - 1)`, the pair `sigma_yy` about its
    /// mean over bins in units of its batch-means standard errors: about 1 when uniform
    /// within noise.
    pub sigma_yy_chi2: f64,
    /// Largest `|sigma_yy,k - mean| / se_k`.
    pub sigma_yy_max_z: f64,
    /// `rms_k (D sigma_xy)_k - f_x,k) / rms_k f_x,k`, with `D` the spectral derivative of the
    /// bin-averaged pair shear stress: the derivative of a bin average is the bin average of
    /// the derivative, so this is the momentum balance bin by bin up to noise and
    /// aliasing. None without drag.
    pub balance_residual: Option<f64>,
}

/// The checks on the snapshot sums of `blocks` (at least 2 blocks).
pub fn stress_checks(ctx: &BinningContext, blocks: &BlockSums) -> StressChecks {
    let nb = ctx.bins.count;
    let field = |sums: &[f64], f: usize, snapshots: usize| -> Vec<f64> {
        let norm = 1.0 / (snapshots as f64 * ctx.bin_volume);
        sums[f * nb..(f + 1) * nb]
            .iter()
            .map(|v| v * norm)
            .collect()
    };
    let total = blocks.total();
    let n = blocks.capacity().min(blocks.taken);
    let syy = field(&total, SYY, n);
    let per_block: Vec<Vec<f64>> = blocks
        .sums
        .iter()
        .map(|b| field(b, SYY, blocks.per_block))
        .collect();
    let m = per_block.len() as f64;
    let se: Vec<f64> = (0..nb)
        .map(|k| {
            let mean = per_block.iter().map(|b| b[k]).sum::<f64>() / m;
            let var = per_block.iter().map(|b| (b[k] - mean).powi(2)).sum::<f64>() / (m - 1.0);
            (var / m).sqrt()
        })
        .collect();
    let mean = syy.iter().sum::<f64>() / nb as f64;
    let z: Vec<f64> = syy.iter().zip(&se).map(|(s, e)| (s - mean) / e).collect();
    let sigma_yy_chi2 = z.iter().map(|z| z * z).sum::<f64>() / (nb as f64 - 1.0);
    let sigma_yy_max_z = z.iter().fold(0.0f64, |a, z| a.max(z.abs()));

    let slope = periodic_derivative::spectral(&field(&total, SXY, n), ctx.bins.width);
    let f_x = field(&total, DRAG_X, n);
    let rms = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    let drag = rms(&mut f_x.iter().copied());
    let residual = rms(&mut slope.iter().zip(&f_x).map(|(d, f)| d - f));
    StressChecks {
        sigma_yy_chi2,
        sigma_yy_max_z,
        balance_residual: (drag > 0.0).then(|| residual / drag),
    }
}
