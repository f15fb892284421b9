//! `solve`: the steady profile of a scene from its forcing alone (the `solver` crate): the
//! binned momentum balance closed by the learned `dv` mapping, by the local rheology fitted
//! on the training data, or nonlocally by the `theta` mapping, as `suspflow solve` computes it.
use crate::error::Error;
use crate::scene::Scene;
use pyo3::prelude::*;
use solver::{Bands, ClosureKind, Closures, ProfileProblem, SolvedProfile};
use std::path::PathBuf;

/// A solved profile: per-bin columns under the dataset's names, and how the solve went.
#[pyclass(module = "suspflow._native", frozen, get_all)]
pub struct Solution {
    /// (name, values) in the column order of `suspflow solve`'s profile.csv (numbers only,
    /// `solver::SolvedProfile::columns`; the scene id and profile columns are added
    /// by the Python side), the bands' `_lower` and `_upper` columns included.
    pub columns: Vec<(String, Vec<f64>)>,
    /// Whether each bin lies within the closure's training domain (`in_domain`).
    pub in_domain: Vec<bool>,
    /// Each bin's distance from the training rows (`domain_distance`; <= 1 is near).
    pub domain_distance: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Whether Newton's method stalled from u = u_inf and the solve was continued from the
    /// local law.
    pub continued: bool,
    /// Largest balance residual, in units of the forcing's drag density.
    pub residual: f64,
    /// The uniform pressure (units eta / time).
    pub pressure: f64,
    /// The bands' level, margins, relative widths and held-out coverage as JSON (`suspflow
    /// solve`'s summary.json `bands`), when the models carry their calibration.
    pub bands: Option<String>,
    /// Why the profile has no bands, when it has none.
    pub bands_missing: Option<String>,
}

/// Solves `scene` with the `closure` (`learned`: the `dv` model in `models`; `local`: the
/// local rheology fitted on `train`, by default the `dv` model's training data; `nonlocal`:
/// the `theta` model with the Theta balance fitted on the same data; `extremum`: the `ext`
/// model, whose input is the distance to the nearest velocity extremum), Newton iterations
/// from the pressure `p_start` (units eta / time), continued from the local law where they
/// stall, with the bands at `level` when the models carry their calibration, as `suspflow
/// solve` does.
#[pyfunction]
#[pyo3(signature = (scene, models, closure = "learned", train = None, p_start = 0.1, level = 0.9))]
pub fn solve(
    py: Python<'_>,
    scene: &Scene,
    models: PathBuf,
    closure: &str,
    train: Option<PathBuf>,
    p_start: f64,
    level: f64,
) -> Result<Solution, Error> {
    let scene = &scene.inner;
    let kind = ClosureKind::from_name(closure)?;
    surrogate::check_level(level)?;
    let problem = ProfileProblem::from_scene(scene)
        .map_err(|e| Error::context(format!("scene `{}`: nothing to solve", scene.file.name), e))?;
    let closures = Closures::load(&models, train.as_deref()).map_err(|e| {
        Error::context(
            format!(
                "loading the closures from {} and their training data",
                models.display()
            ),
            e,
        )
    })?;
    let (solution, bands) = py
        .allow_threads(|| {
            let s = closures
                .get(kind)
                .and_then(|c| problem.solve(c, Some(&closures.local), p_start))?;
            let bands = closures.bands(kind, &problem, &s, level)?;
            Ok::<_, solver::SolverError>((s, bands))
        })
        .map_err(|e| {
            Error::context(
                format!("solving `{}` with the {closure} closure", scene.file.name),
                e,
            )
        })?;
    let s = &solution;
    let checks = closures.domain_checks(kind, scene.file.particles.phi, s)?;
    let (profile_bands, summary, missing) = match bands {
        Bands::Calibrated(calibrated) => {
            let (b, summary) = *calibrated;
            (Some(b), Some(summary), None)
        }
        Bands::Missing(why) => (None, None, Some(why)),
    };
    let solved = SolvedProfile {
        scene,
        problem: &problem,
        solution: s,
        checks: &checks,
        bands: profile_bands.as_ref(),
    };
    Ok(Solution {
        columns: solved.columns(),
        in_domain: checks.iter().map(|c| c.inside()).collect(),
        domain_distance: checks.iter().map(|c| c.distance).collect(),
        iterations: s.iterations,
        continued: s.continued,
        residual: s.residual,
        pressure: s.pressure,
        bands: summary
            .map(|b| serde_json::to_string(&b))
            .transpose()
            .map_err(|e| Error::context("the bands' summary", e.to_string()))?,
        bands_missing: missing,
    })
}
