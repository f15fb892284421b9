//! The local relative viscosity `eta_r = mu / J = |sigma_xy| / (eta |gdot|)` of the sheared
//! bins of an inhomogeneous-flow dataset (docs/physics.md sections 6 and 10), gathered in
//! bands of `phi_loc`, for comparison with homogeneous shear at the same volume fraction.
use std::collections::BTreeMap;

use schema::columns as col;

use crate::data::dataset::Dataset;
use crate::error::Result;
use crate::rheology::statistics::median;

/// A bin counts as sheared when its `|gdot|` is at least this fraction of the largest
/// `|gdot|` of its scene: near a velocity extremum `J -> 0` and `mu / J` is noise over noise.
pub const SHEARED_FRACTION: f64 = 0.5;

/// Width of a `phi_loc` band.
pub const BAND_WIDTH: f64 = 0.02;

/// The sheared bins whose `phi_loc` lies within `BAND_WIDTH / 2` of `phi`.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalBand {
    /// Band centre.
    pub phi: f64,
    /// `(phi_loc, mu / J)` of each bin in the band.
    pub bins: Vec<(f64, f64)>,
}

impl LocalBand {
    /// Median over the band of `mu / J`.
    pub fn eta_r(&self) -> f64 {
        median(self.bins.iter().map(|b| b.1).collect())
    }

    /// Median over the band of `(mu / J) / reference(phi_loc)`, each bin against the
    /// reference at its own `phi_loc`.
    pub fn ratio(&self, reference: impl Fn(f64) -> f64) -> f64 {
        median(self.bins.iter().map(|&(p, e)| e / reference(p)).collect())
    }
}

/// The bands centred on `centres` of the sheared bins of `data`; bands without a bin are
/// left out.
pub fn bands(data: &Dataset, centres: &[f64]) -> Result<Vec<LocalBand>> {
    let scene = data.group_keys()?;
    let (gdot, phi_loc) = (data.column(col::GDOT)?, data.column(col::PHI_LOC)?);
    let (j, mu) = (data.column(col::J)?, data.column(col::MU)?);
    let mut largest: BTreeMap<&str, f64> = BTreeMap::new();
    for (s, g) in scene.iter().zip(gdot) {
        let m = largest.entry(s.as_str()).or_insert(0.0);
        *m = m.max(g.abs());
    }
    let sheared: Vec<usize> = (0..data.n_rows())
        .filter(|&r| {
            gdot[r].abs() >= SHEARED_FRACTION * largest[scene[r].as_str()]
                && j[r] > 0.0
                && mu[r] > 0.0
        })
        .collect();
    Ok(centres
        .iter()
        .filter_map(|&phi| {
            let bins: Vec<(f64, f64)> = sheared
                .iter()
                .filter(|&&r| (phi_loc[r] - phi).abs() <= 0.5 * BAND_WIDTH)
                .map(|&r| (phi_loc[r], mu[r] / j[r]))
                .collect();
            (!bins.is_empty()).then_some(LocalBand { phi, bins })
        })
        .collect())
}
