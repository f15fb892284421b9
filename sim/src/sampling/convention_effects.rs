//! The effect of each observable convention (docs/physics.md section 6), measured paired:
//! the profile of one run's snapshot sums under every alternative convention against the
//! same sums under the defaults, bin by bin.
use crate::error::SimError;
use crate::sampling::bin_averages::{BinAverages, BinningContext};
use crate::sampling::block_sums::BlockSums;
use crate::sampling::conventions::Conventions;
use schema::Observable;

/// The observables whose change is reported.
pub const COMPARED: [Observable; 5] = [
    Observable::Mu,
    Observable::PhiLoc,
    Observable::Theta,
    Observable::DeltaV,
    Observable::J,
];

/// One alternative convention against the defaults.
#[derive(Clone, Debug)]
pub struct ConventionEffect {
    /// The option that differs, as written in a scene file.
    pub option: String,
    /// For each of [`COMPARED`], `|alternative - default| / |default|` in every bin where
    /// both are defined and the default is not zero.
    pub relative: [Vec<f64>; 5],
}

/// The effect of every alternative of [`Conventions::alternatives`] on the snapshot sums
/// `blocks`; the conventions of `ctx` are ignored.
pub fn convention_effects(
    ctx: &BinningContext,
    blocks: &BlockSums,
) -> Result<Vec<ConventionEffect>, SimError> {
    let under = |conventions: Conventions| {
        let ctx = BinningContext {
            conventions,
            ..ctx.clone()
        };
        BinAverages::from_blocks(&ctx, blocks)
    };
    let default = under(Conventions::default())?;
    Conventions::alternatives()
        .into_iter()
        .map(|(option, conventions)| {
            let other = under(conventions)?;
            let relative = COMPARED.map(|o| {
                let (a, d) = (other.mean.column(o), default.mean.column(o));
                a.iter()
                    .zip(d)
                    .filter(|(a, d)| a.is_finite() && d.is_finite() && **d != 0.0)
                    .map(|(a, d)| ((a - d) / d).abs())
                    .collect()
            });
            Ok(ConventionEffect { option, relative })
        })
        .collect()
}
