//! `cross_validate`: the leave-one-family-out study of `suspflow cross-validate`
//! (`surrogate::FamilyCvStudy`: trees, backbone and both on each profile family left out,
//! the learning curve, the intervals' coverage on the same folds), with the trees' settings
//! of the models in a directory. The record is `cv.json`'s, as JSON text.
use crate::dataset::{dataset, Table};
use crate::error::Error;
use pyo3::prelude::*;
use std::path::PathBuf;
use surrogate::{CvSettings, FamilyCvStudy, Mapping, TrainedModel};

/// The study of `table` for the mappings named (all four when empty), the trees with the
/// hyper-parameters of the models in `dir`; `learning_curve` the numbers of training
/// families of the learning curve (none: no curve), each with `draws` draws seeded by
/// `seed`; the intervals' coverage at `level`. Returns `cv.json`'s record as JSON text. The
/// GIL is released while the folds run.
#[pyfunction]
#[pyo3(signature = (dir, table, mappings = Vec::new(), learning_curve = Vec::new(), draws = 3, seed = 1, level = surrogate::DEFAULT_LEVEL))]
#[allow(clippy::too_many_arguments)]
pub fn cross_validate(
    py: Python<'_>,
    dir: PathBuf,
    table: Table,
    mappings: Vec<String>,
    learning_curve: Vec<usize>,
    draws: usize,
    seed: u64,
    level: f64,
) -> Result<String, Error> {
    let data = dataset(table)?;
    surrogate::profile_names(&data)?;
    let plan = Mapping::select(&mappings)?
        .into_iter()
        .map(|mapping| {
            let model = TrainedModel::load(&dir, mapping.name).map_err(|e| {
                Error::context(
                    format!(
                        "reading the hyper-parameters of `{}` from {}",
                        mapping.name,
                        dir.display()
                    ),
                    e,
                )
            })?;
            Ok((mapping, model.meta().hyper_parameters.clone()))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let settings = CvSettings {
        learning_curve,
        draws,
        seed,
        level,
    };
    let study = py.allow_threads(|| FamilyCvStudy::run(&data, &plan, &dir, &settings, &|_| {}))?;
    serde_json::to_string(&study).map_err(|e| Error::from(e.to_string()))
}
