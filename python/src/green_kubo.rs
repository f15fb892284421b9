//! `green_kubo`: the Green-Kubo Brownian viscosity of an unsheared Brownian scene in its run
//! folder, as `suspflow green-kubo` runs it (`rheometry::green_kubo::run_in_folder`:
//! scene.toml, the lock, checkpoint.json, green_kubo.csv, green_kubo.json). The run goes on
//! a worker thread ([`run_watched`]): Ctrl-C stops it within 256 steps, its checkpoint
//! saved, and `fresh = false` continues it.
use crate::error::Error;
use crate::scene::Scene;
use crate::worker::{
    open_folder, run_ended, run_options, run_watched, thread_pool, to_progress, Report,
};
use pyo3::prelude::*;
use rheometry::green_kubo::{run_in_folder, WRITTEN};
use sim::run::green_kubo::{GreenKuboJob, GreenKuboRun};
use sim::run::progress::ProgressLines;
use sim::run::Job;
use std::path::PathBuf;

/// Runs the Green-Kubo run of `scene` into the run folder `out` on `threads` threads (0 =
/// all cores): `warmup` and `span` in Brownian times, a sample every `every` steps, the
/// correlation to the lag `max_lag` (Brownian times), the error from `blocks` parts.
/// Continues `out/checkpoint.json` unless `fresh` starts over. `progress(dict)` is called
/// with each report. Returns `green_kubo.json`'s text.
#[pyfunction]
#[pyo3(signature = (scene, out, warmup = 5.0, span = 100.0, every = 5, max_lag = 5.0, blocks = 10, threads = 0, fresh = true, progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn green_kubo(
    scene: &Bound<'_, Scene>,
    out: PathBuf,
    warmup: f64,
    span: f64,
    every: u64,
    max_lag: f64,
    blocks: usize,
    threads: usize,
    fresh: bool,
    progress: Option<PyObject>,
) -> PyResult<String> {
    let py = scene.py();
    let scene = scene.borrow();
    let scene = &scene.inner;
    let plan = GreenKuboRun {
        warmup_tau_b: warmup,
        span_tau_b: span,
        every,
        max_lag_tau_b: max_lag,
        blocks,
    };
    // Checked before the folder is touched: a run that cannot give a result does not start.
    GreenKuboJob::new(scene, plan)
        .check()
        .map_err(Error::from)?;
    scene.check_fits_here().map_err(Error::from)?;
    let pool = thread_pool(threads)?;
    let (folder, _lock) = open_folder(&out, "`suspflow.green_kubo`", &scene.file, fresh, &WRITTEN)?;
    let opts = run_options();
    let work = |send: std::sync::mpsc::Sender<Report>| {
        let (mut status, mut log) = (ProgressLines::every_report(), ProgressLines::for_logs());
        pool.install(|| {
            run_in_folder(&folder, scene, plan, opts, &mut |p, _| {
                let _ = send.send(Report::of(p, (&mut status, &mut log)));
            })
        })
    };
    let (outcome, python_error) = run_watched(py, work, to_progress(py, &progress))?;
    let result = run_ended(py, outcome, python_error, &folder.checkpoint())?;
    Ok(serde_json::to_string(&result).expect("a Green-Kubo result serialises"))
}
