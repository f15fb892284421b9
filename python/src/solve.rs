//! `solve`: the steady profile of a scene from its forcing alone (the `solver` crate): the
//! binned momentum balance closed by the learned `dv` mapping, by the local rheology fitted
//! on the training data, or nonlocally by the `theta` mapping, as `suspflow solve` computes it.
use crate::error::Error;
use crate::scene::Scene;
use pyo3::prelude::*;
use schema::columns as col;
use solver::{ClosureKind, Closures, ProfileProblem, SolvedProfile};
use std::path::PathBuf;

/// A solved profile: per-bin columns under the dataset's names, and how the solve went.
#[pyclass(module = "suspflow._native", frozen, get_all)]
pub struct Solution {
    /// (name, values) in the column order of `suspflow solve`'s profile.csv (numbers only;
    /// the scene id and profile columns are added by the Python side).
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
}

/// Solves `scene` with the `closure` (`learned`: the `dv` model in `models`; `local`: the
/// local rheology fitted on `train`, by default the `dv` model's training data; `nonlocal`:
/// the `theta` model with the Theta balance fitted on the same data), Newton iterations from
/// the pressure `p_start` (units eta / time), continued from the local law where they stall,
/// as `suspflow solve` does.
#[pyfunction]
#[pyo3(signature = (scene, models, closure = "learned", train = None, p_start = 0.1))]
pub fn solve(
    py: Python<'_>,
    scene: &Scene,
    models: PathBuf,
    closure: &str,
    train: Option<PathBuf>,
    p_start: f64,
) -> Result<Solution, Error> {
    let scene = &scene.inner;
    let kind = ClosureKind::from_name(closure)?;
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
    let solution = py
        .allow_threads(|| problem.solve(closures.get(kind), Some(&closures.local), p_start))
        .map_err(|e| {
            Error::context(
                format!("solving `{}` with the {closure} closure", scene.file.name),
                e,
            )
        })?;
    let s = &solution;
    let checks = closures.domain_checks(kind, scene.file.particles.phi, s)?;
    let n = problem.n_bins();
    let solved = SolvedProfile {
        scene,
        problem: &problem,
        solution: s,
        checks: &checks,
    };
    let mut columns = vec![
        (col::L_Y, vec![scene.file.box_.l_y; n]),
        (col::PHI, vec![scene.file.particles.phi; n]),
    ];
    columns.extend(solved.columns());
    Ok(Solution {
        columns: columns
            .into_iter()
            .map(|(name, values)| (name.to_owned(), values))
            .collect(),
        in_domain: checks.iter().map(|c| c.inside()).collect(),
        domain_distance: checks.iter().map(|c| c.distance).collect(),
        iterations: s.iterations,
        continued: s.continued,
        residual: s.residual,
        pressure: s.pressure,
    })
}
