//! `solve`: the steady profile of a scene from its forcing alone (the `solver` crate): the
//! binned momentum balance closed by the learned `dv` mapping or by the local rheology fitted
//! on the training data, as `suspflow solve` computes it.
use crate::error::Error;
use crate::scene::Scene;
use pyo3::prelude::*;
use schema::columns as col;
use solver::{fit_local_rheology, LearnedClosure, ProfileProblem};
use std::path::{Path, PathBuf};
use surrogate::{Dataset, Predictor};

/// A solved profile: per-bin columns under the dataset's names, and how the solve went.
#[pyclass(module = "suspflow._native", frozen, get_all)]
pub struct Solution {
    /// (name, values) in the column order of `suspflow solve`'s profile.csv (numbers only;
    /// the scene id and profile columns are added by the Python side).
    pub columns: Vec<(String, Vec<f64>)>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Largest balance residual, in units of the forcing's drag density.
    pub residual: f64,
    /// The uniform pressure (units eta / time).
    pub pressure: f64,
}

/// The `dv` model's training data: the path its sidecar names, taken from the current
/// directory as the command does, or else from the folder holding `models` (a script run
/// outside the repository that names `REPO/models`).
fn training_data(models: &Path, predictor: &Predictor) -> PathBuf {
    let source = PathBuf::from(&predictor.meta().training_data.source);
    match models.parent() {
        Some(repo) if source.is_relative() && !source.exists() => repo.join(source),
        _ => source,
    }
}

/// Solves `scene` with the `closure` (`learned`: the `dv` model in `models`; `local`: the
/// local rheology fitted on `train`, by default the `dv` model's training data, see
/// [`training_data`]), Newton
/// iterations from the pressure `p_start` (units eta / time).
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
    let problem = ProfileProblem::from_scene(scene)
        .map_err(|e| Error::context(format!("scene `{}`: nothing to solve", scene.file.name), e))?;
    let predictor = Predictor::load(&models, "dv")
        .map_err(|e| Error::context(format!("loading model `dv` from {}", models.display()), e))?;
    let solution = match closure {
        "learned" => {
            let learned = LearnedClosure::new(predictor)?;
            py.allow_threads(|| problem.solve(&learned, None, p_start))
        }
        "local" => {
            let train = train.unwrap_or_else(|| training_data(&models, &predictor));
            let data = Dataset::read_csv(&train).map_err(|e| {
                Error::context("reading the training data for the local rheology", e)
            })?;
            let law = fit_local_rheology(&data)?;
            py.allow_threads(|| problem.solve(&law, None, p_start))
        }
        other => {
            return Err(Error(format!(
                "unknown closure `{other}` (learned or local)"
            )))
        }
    }
    .map_err(|e| {
        Error::context(
            format!("solving `{}` with the {closure} closure", scene.file.name),
            e,
        )
    })?;
    let s = &solution;
    let n = problem.n_bins();
    let columns = vec![
        (col::L_Y, vec![scene.file.box_.l_y; n]),
        (col::PHI, vec![scene.file.particles.phi; n]),
        (col::Y, problem.bin_centres()),
        (col::U_INF, problem.u_inf.clone()),
        (col::U, s.u.clone()),
        (col::GDOT, s.gdot.clone()),
        (col::SIGMA_XY, s.sigma_xy.clone()),
        (col::P, vec![s.pressure; n]),
        (col::PHI_LOC, s.phi_loc.clone()),
        (col::J, s.j.clone()),
        (col::MU, s.mu.clone()),
        (col::DELTA_V, s.delta_v.clone()),
        (col::F_X, s.f_x.clone()),
    ];
    Ok(Solution {
        columns: columns
            .into_iter()
            .map(|(name, values)| (name.to_owned(), values))
            .collect(),
        iterations: s.iterations,
        residual: s.residual,
        pressure: s.pressure,
    })
}
