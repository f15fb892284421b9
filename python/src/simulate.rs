//! `simulate`: a scene to its steady-state profile in its run folder, as `suspflow simulate`
//! runs it (`sim::RunFolder`: scene.toml, the lock, checkpoint.json, profile.csv, stress.csv,
//! summary.json, snapshot_sums.json, frames). The run goes on a worker thread
//! ([`run_watched`]): Ctrl-C (KeyboardInterrupt) stops the run within 256 steps, its
//! checkpoint saved, and `resume=True` continues it.
use crate::error::Error;
use crate::scene::Scene;
use crate::worker::{
    open_folder, run_ended, run_options, run_watched, thread_pool, to_progress, Report,
};
use pyo3::prelude::*;
use sim::output::frame_writer::FrameWriter;
use sim::output::result_files::{write_results, WRITTEN};
use sim::output::snapshot_format::SnapshotFormat;
use sim::run::progress::ProgressLines;
use sim::run::SteadyRun;
use sim::SimError;
use std::path::PathBuf;

/// Runs `scene` into the run folder `out` on `threads` threads (0 = all cores), continuing
/// `out/checkpoint.json` (an interrupted run, or a finished one that the scene lengthens)
/// unless `fresh` starts over; with `snapshot = N` a frame every N samples in
/// `snapshot_format` (`xyz`, `lammps` or `gsd`). `progress(dict)` is called with each report.
/// Returns the run summary (summary.json) as JSON text.
#[pyfunction]
#[pyo3(signature = (scene, out, threads = 0, fresh = true, snapshot = None, snapshot_format = "xyz", progress = None))]
pub fn simulate(
    scene: &Bound<'_, Scene>,
    out: PathBuf,
    threads: usize,
    fresh: bool,
    snapshot: Option<u64>,
    snapshot_format: &str,
    progress: Option<PyObject>,
) -> PyResult<String> {
    let py = scene.py();
    let scene = scene.borrow();
    let scene = &scene.inner;
    // A bad argument, not a file's failure: the base class.
    let format: SnapshotFormat = snapshot_format
        .parse()
        .map_err(|e: SimError| Error::from(e.to_string()))?;
    if snapshot == Some(0) {
        return Err(Error::from(
            "snapshot must be at least 1 (a frame every N samples)".to_owned(),
        )
        .into());
    }
    let pool = thread_pool(threads)?;
    let (folder, _lock) = open_folder(&out, "`suspflow.simulate`", &scene.file, fresh, &WRITTEN)?;
    let checkpoint = folder.checkpoint();
    let resuming = checkpoint.exists();
    let mut frames = snapshot
        .map(|every| FrameWriter::open(&out, format, every, resuming))
        .transpose()
        .map_err(Error::from)?;
    let opts = run_options();
    let work = |send: std::sync::mpsc::Sender<Report>| {
        let (mut status, mut log) = (ProgressLines::every_report(), ProgressLines::for_logs());
        pool.install(|| {
            folder.run(
                scene,
                &mut SteadyRun::new(scene, crate::CODE_VERSION),
                opts,
                &mut |p, sim| {
                    let _ = send.send(Report::of(p, (&mut status, &mut log)));
                    if let Some(frames) = frames.as_mut() {
                        frames.after_sample(p.samples, sim);
                    }
                },
                |dir, outcome| write_results(dir, scene, outcome),
            )
        })
    };
    let (outcome, python_error) = run_watched(py, work, to_progress(py, &progress))?;
    if let Some(frames) = frames {
        frames.finish().map_err(Error::from)?;
    }
    let outcome = run_ended(py, outcome, python_error, &checkpoint)?;
    Ok(serde_json::to_string(&outcome.summary).expect("a run summary serialises"))
}
