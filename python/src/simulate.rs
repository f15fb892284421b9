//! `simulate`: a scene to its steady-state profile in its run folder, as `suspflow simulate`
//! runs it (`sim::RunFolder`: scene.toml, the lock, checkpoint.json, profile.csv, stress.csv,
//! summary.json, snapshot_sums.json, frames). The run goes on
//! a worker thread while the calling thread, without the GIL, waits for its progress and
//! polls Python's signals: Ctrl-C (KeyboardInterrupt) stops the run within 256 steps, its
//! checkpoint saved, and `resume=True` continues it.
use crate::error::{Error, Kind};
use crate::scene::Scene;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::output::frame_writer::FrameWriter;
use sim::output::result_files::{write_results, WRITTEN};
use sim::output::snapshot_format::SnapshotFormat;
use sim::run::progress::ProgressLines;
use sim::run::run_folder::{Ended, RunFolder};
use sim::run::{Phase, RunOptions, SteadyRun};
use sim::SimError;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// Set to stop the run (the simulator checks it every 256 steps). One for the process, as
/// the simulator asks: a Ctrl-C stops every run of the process.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// How often the waiting thread polls for signals.
const POLL: Duration = Duration::from_millis(100);

/// One progress report of the worker.
struct Report {
    equilibrating: bool,
    strain: f64,
    max_strain: f64,
    snapshots: usize,
    snapshots_target: usize,
    step: u64,
    /// The status with the time in the phase and the time left (a terminal's line).
    status: String,
    /// The same when a log's line is due (every few percent or minutes), else None.
    line: Option<String>,
}

impl Report {
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let phase = if self.equilibrating {
            "equilibrating"
        } else {
            "averaging"
        };
        d.set_item("phase", phase)?;
        d.set_item("strain", self.strain)?;
        d.set_item("max_strain", self.max_strain)?;
        d.set_item("snapshots", self.snapshots)?;
        d.set_item("snapshots_target", self.snapshots_target)?;
        d.set_item("step", self.step)?;
        d.set_item("status", &self.status)?;
        d.set_item("line", &self.line)?;
        Ok(d)
    }
}

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
    sim::run::threads::check(threads).map_err(Error::from)?;
    let folder = RunFolder::new(&out);
    let _lock = folder.lock("`suspflow.simulate`").map_err(Error::from)?;
    if fresh {
        folder.start_over(&WRITTEN).map_err(Error::from)?;
        folder.record_scene(&scene.file).map_err(Error::from)?;
    } else {
        folder.prepare(&scene.file).map_err(Error::from)?;
    }
    let checkpoint = folder.checkpoint();
    let resuming = checkpoint.exists();
    let mut frames = snapshot
        .map(|every| FrameWriter::open(&out, format, every, resuming))
        .transpose()
        .map_err(Error::from)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::context("starting the thread pool", e.to_string()))?;
    INTERRUPTED.store(false, Ordering::SeqCst);
    let opts = RunOptions {
        interrupt: Some(&INTERRUPTED),
        code_version: crate::CODE_VERSION,
        ..RunOptions::default()
    };
    let (send, receive) = mpsc::channel::<Report>();
    // Shared with the GIL-free wait, which must be `Send`.
    let receive = std::sync::Mutex::new(receive);
    let mut python_error: Option<PyErr> = None;
    let outcome = std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let send = send;
            let (mut status, mut log) = (ProgressLines::every_report(), ProgressLines::for_logs());
            pool.install(|| {
                folder.run(
                    scene,
                    &mut SteadyRun::new(scene, crate::CODE_VERSION),
                    opts,
                    &mut |p, sim| {
                        let _ = send.send(Report {
                            equilibrating: p.phase == Phase::Equilibrating,
                            strain: p.strain,
                            max_strain: p.max_strain,
                            snapshots: p.snapshots,
                            snapshots_target: p.snapshots_target,
                            step: p.step,
                            status: status.line(p).unwrap_or_default(),
                            line: log.line(p),
                        });
                        if let Some(frames) = frames.as_mut() {
                            frames.after_sample(p.samples, sim);
                        }
                    },
                    |dir, outcome| write_results(dir, scene, outcome),
                )
            })
        });
        loop {
            let next = py.allow_threads(|| {
                receive
                    .lock()
                    .expect("only this thread locks it")
                    .recv_timeout(POLL)
            });
            let step = match next {
                Ok(report) => match &progress {
                    Some(callback) if python_error.is_none() => report
                        .to_dict(py)
                        .and_then(|d| callback.call1(py, (d,)))
                        .map(drop),
                    _ => Ok(()),
                },
                Err(mpsc::RecvTimeoutError::Timeout) => Ok(()),
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            };
            if let Err(e) = step.and_then(|()| py.check_signals()) {
                // Ctrl-C, or a progress callback that raised: stop the run at its next check.
                INTERRUPTED.store(true, Ordering::SeqCst);
                python_error.get_or_insert(e);
            }
        }
        py.allow_threads(|| worker.join())
    })
    .map_err(|_| Error::from("the simulation thread panicked".to_owned()))?;
    if let Some(frames) = frames {
        frames.finish().map_err(Error::from)?;
    }
    let ended = match (outcome, python_error) {
        (Ok(Ended::Interrupted { step }), Some(e))
            if e.is_instance_of::<PyKeyboardInterrupt>(py) =>
        {
            return Err(PyKeyboardInterrupt::new_err(format!(
                "interrupted at step {step}; state saved in {}; continue with resume=True",
                checkpoint.display()
            )));
        }
        (_, Some(e)) => return Err(e),
        (outcome, None) => outcome.map_err(Error::from)?,
    };
    match ended {
        Ended::Finished(outcome) => {
            Ok(serde_json::to_string(&outcome.summary).expect("a run summary serialises"))
        }
        Ended::Interrupted { step } => Err(Error::new(
            Kind::Interrupted,
            format!(
                "interrupted at step {step}; state saved in {}; continue with resume=True",
                checkpoint.display()
            ),
        )
        .into()),
        Ended::InterruptedPacking => Err(Error::from(SimError::InterruptedPacking).into()),
        Ended::Failed(reason) => Err(Error::from(reason).into()),
    }
}
