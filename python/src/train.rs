//! `train`: the surrogate mappings fitted on a table and saved into a folder, as `suspflow
//! train` does (`solver::TrainingJob`: hyper-parameters, fit, intervals, model files, then
//! the bands of `solve`). The job runs on a worker thread ([`run_watched`]) without the GIL;
//! the result is a `solver::TrainingResult` as JSON text. Ctrl-C stops it before the next
//! mapping (or the bands), the models saved until then kept.
use crate::dataset::{dataset, Table};
use crate::error::Error;
use crate::worker::{run_watched, INTERRUPTED};
use pyo3::prelude::*;
use sim::output::file_lock::FileLock;
use solver::{ParamsSource, TrainingEvent, TrainingJob};
use std::path::PathBuf;
use std::sync::mpsc::Sender;
use std::sync::Mutex;
use surrogate::Mapping;

/// Trains the mappings named (all four when empty) on `table` into the folder `out`: with
/// hyper-parameters chosen by cross-validation (`tune`), else those of the models in
/// `params_from`, else XGBoost's defaults; the bands of `solve` when `bands` and `dv` and
/// `theta` are trained. Models already in `out` are replaced only with `force`.
/// `progress((event, name))` is called as each step ends (`tuned`, `intervals`, `trained`
/// with the mapping's name, `bands` with the family whose fold was solved). Returns the
/// result as JSON text.
#[pyfunction]
#[pyo3(signature = (table, out, mappings = Vec::new(), tune = true, params_from = None, bands = true, force = false, progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn train(
    py: Python<'_>,
    table: Table,
    out: PathBuf,
    mappings: Vec<String>,
    tune: bool,
    params_from: Option<PathBuf>,
    bands: bool,
    force: bool,
    progress: Option<PyObject>,
) -> PyResult<String> {
    let data_file = match &table {
        Table::Path(path) => Some(path.clone()),
        Table::Bytes(_) => None,
    };
    let data = dataset(table)?;
    let mappings = Mapping::select(&mappings).map_err(Error::from)?;
    let params = match (params_from, tune) {
        (Some(dir), _) => ParamsSource::From(dir),
        (None, true) => ParamsSource::Tune,
        (None, false) => ParamsSource::Defaults,
    };
    if out.exists() && !out.is_dir() {
        return Err(Error::new(
            crate::error::Kind::File,
            format!(
                "{} is a file; choose a directory for the models",
                out.display()
            ),
        )
        .into());
    }
    let _lock = FileLock::folder(&out, "`suspflow.train`").map_err(Error::from)?;
    let job = TrainingJob {
        data: &data,
        data_file: data_file.as_deref(),
        out: &out,
        mappings,
        params,
        bands,
        force,
        code_version: crate::CODE_VERSION,
        interrupt: Some(&INTERRUPTED),
    };
    let work = |send: Sender<(String, String)>| {
        let send = Mutex::new(send);
        job.run(&|event| {
            let step = match event {
                TrainingEvent::Tuned { mapping, .. } => ("tuned", mapping.name),
                TrainingEvent::Intervals { mapping, .. } => ("intervals", mapping.name),
                TrainingEvent::Trained { mapping, .. } => ("trained", mapping.name),
                TrainingEvent::BandsFold { family, .. } => ("bands", family),
                _ => return,
            };
            if let Ok(send) = send.lock() {
                let _ = send.send((step.0.to_owned(), step.1.to_owned()));
            }
        })
    };
    let (result, python_error) = run_watched(py, work, |step| match &progress {
        Some(callback) => callback.call1(py, (step,)).map(drop),
        None => Ok(()),
    })?;
    if let Some(e) = python_error {
        return Err(e);
    }
    let result = result.map_err(Error::from)?;
    serde_json::to_string(&result).map_err(|e| Error::from(e.to_string()).into())
}
