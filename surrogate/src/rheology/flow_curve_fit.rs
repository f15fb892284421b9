//! Flow curves of homogeneous shear: the relative viscosity of a scene's bins, and the
//! jamming law fitted to all scenes and to each seed's scenes alone, whose spread gives the
//! fit's standard errors.

use std::collections::BTreeMap;

use schema::columns as col;

use crate::data::dataset::Dataset;
use crate::error::Result;
use crate::rheology::jamming_law::JammingLaw;
use crate::rheology::statistics::mean_and_standard_error;

/// One scene's point on the flow curve.
#[derive(Debug, Clone, Copy)]
pub struct FlowCurvePoint {
    /// Seed of the scene's realisation.
    pub seed: u64,
    /// Realised volume fraction.
    pub phi: f64,
    /// Relative viscosity `eta_r`.
    pub eta_r: f64,
}

/// The jamming law fitted to every point, and to each seed's points alone.
#[derive(Debug, Clone)]
pub struct SeededJammingFit {
    pub all: JammingLaw,
    /// One fit per seed, in seed order.
    pub per_seed: Vec<(u64, JammingLaw)>,
    /// Standard error of `phi_J`: the seeds' spread over `sqrt(seeds)` (NaN below 2 seeds).
    pub phi_j_se: f64,
    /// The same for `lambda`.
    pub lambda_se: f64,
}

impl SeededJammingFit {
    /// Fits the jamming law to `points` and to each seed's points.
    pub fn fit(points: &[FlowCurvePoint]) -> Result<Self> {
        let law = |sel: &[&FlowCurvePoint]| {
            let phi: Vec<f64> = sel.iter().map(|p| p.phi).collect();
            let eta: Vec<f64> = sel.iter().map(|p| p.eta_r).collect();
            JammingLaw::fit(&phi, &eta)
        };
        let all = law(&points.iter().collect::<Vec<_>>())?;
        let mut seeds: BTreeMap<u64, Vec<&FlowCurvePoint>> = BTreeMap::new();
        for p in points {
            seeds.entry(p.seed).or_default().push(p);
        }
        let per_seed: Vec<(u64, JammingLaw)> = seeds
            .iter()
            .map(|(&s, sel)| law(sel).map(|l| (s, l)))
            .collect::<Result<_>>()?;
        let spread = |f: fn(&JammingLaw) -> f64| {
            mean_and_standard_error(&per_seed.iter().map(|(_, l)| f(l)).collect::<Vec<_>>()).1
        };
        Ok(SeededJammingFit {
            phi_j_se: spread(|l| l.phi_j),
            lambda_se: spread(|l| l.lambda),
            all,
            per_seed,
        })
    }
}

/// `eta_r` of a scene's binned `sigma_xy` at `eta gdot` (the imposed rate): the mean over
/// bins of `-sigma_xy / (eta gdot)`, standard error from the bins' standard errors,
/// `sqrt(sum se^2) / (n eta gdot)`.
pub fn bin_viscosity(profile: &Dataset, eta_gdot: f64) -> Result<(f64, f64)> {
    let (sigma, se) = (
        profile.column(col::SIGMA_XY)?,
        profile.column(&col::standard_error(col::SIGMA_XY))?,
    );
    let n = sigma.len() as f64;
    let mean = -sigma.iter().sum::<f64>() / n / eta_gdot;
    let se = se.iter().map(|s| s * s).sum::<f64>().sqrt() / n / eta_gdot;
    Ok((mean, se))
}
