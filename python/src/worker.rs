//! A run on a worker thread while the calling thread, without the GIL, waits for its
//! reports and polls Python's signals: Ctrl-C (KeyboardInterrupt), or an exception of the
//! caller's progress callable, stops the run at its next check (the simulator checks
//! [`INTERRUPTED`] every 256 steps), its checkpoints saved.
use crate::error::{Error, Kind};
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sim::input::scene_file::SceneFile;
use sim::output::file_lock::FileLock;
use sim::run::progress::ProgressLines;
use sim::run::run_folder::{Ended, RunFolder};
use sim::run::{Phase, Progress, RunOptions};
use sim::SimError;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// Set to stop the runs. One for the process, as the simulator asks: a Ctrl-C stops every
/// run of the process.
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// How often the waiting thread polls for signals.
const POLL: Duration = Duration::from_millis(100);

/// A run's options from Python: stopped by [`INTERRUPTED`], results stamped with the
/// package's code version.
pub fn run_options() -> RunOptions<'static> {
    RunOptions {
        interrupt: Some(&INTERRUPTED),
        code_version: crate::CODE_VERSION,
        ..RunOptions::default()
    }
}

/// A pool of `threads` threads (0 = all cores) for one run.
pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, Error> {
    sim::run::threads::check(threads).map_err(Error::from)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::context("starting the thread pool", e.to_string()))
}

/// The run folder `out`, locked for `holder`: started over (the files `written` of an
/// earlier run removed, `scene` recorded) when `fresh`, else checked to be `scene`'s.
pub fn open_folder(
    out: &Path,
    holder: &str,
    scene: &SceneFile,
    fresh: bool,
    written: &[&str],
) -> Result<(RunFolder, FileLock), Error> {
    let folder = RunFolder::new(out);
    let lock = folder.lock(holder)?;
    if fresh {
        folder.start_over(written)?;
        folder.record_scene(scene)?;
    } else {
        folder.prepare(scene)?;
    }
    Ok((folder, lock))
}

/// Hands each report, as a dict, to `progress` when there is one.
pub fn to_progress<'py>(
    py: Python<'py>,
    progress: &'py Option<PyObject>,
) -> impl FnMut(Report) -> PyResult<()> + 'py {
    move |report| match progress {
        Some(callback) => report
            .to_dict(py)
            .and_then(|d| callback.call1(py, (d,)))
            .map(drop),
        None => Ok(()),
    }
}

/// Runs `work` on a worker thread, handing it the sender of its reports; each report goes
/// to `on_report` (with the GIL) until one raises. Returns the work's result and the first
/// Python exception met (a signal, or one of `on_report`), after which the run was told to
/// stop.
pub fn run_watched<M: Send, R: Send>(
    py: Python<'_>,
    work: impl FnOnce(mpsc::Sender<M>) -> R + Send,
    mut on_report: impl FnMut(M) -> PyResult<()>,
) -> Result<(R, Option<PyErr>), Error> {
    INTERRUPTED.store(false, Ordering::SeqCst);
    let (send, receive) = mpsc::channel::<M>();
    // Shared with the GIL-free wait, which must be `Send`.
    let receive = std::sync::Mutex::new(receive);
    let mut python_error: Option<PyErr> = None;
    let result = std::thread::scope(|s| {
        let worker = s.spawn(|| work(send));
        loop {
            let next = py.allow_threads(|| {
                receive
                    .lock()
                    .expect("only this thread locks it")
                    .recv_timeout(POLL)
            });
            let step = match next {
                Ok(report) if python_error.is_none() => on_report(report),
                Ok(_) | Err(mpsc::RecvTimeoutError::Timeout) => Ok(()),
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            };
            if let Err(e) = step.and_then(|()| py.check_signals()) {
                INTERRUPTED.store(true, Ordering::SeqCst);
                python_error.get_or_insert(e);
            }
        }
        py.allow_threads(|| worker.join())
    })
    .map_err(|_| Error::from("the run's thread panicked".to_owned()))?;
    Ok((result, python_error))
}

/// What a run in a folder returns to Python: its result when it finished; on Ctrl-C a
/// KeyboardInterrupt, on a signal of the process `RunInterrupted`, both naming the
/// `checkpoint` that `resume=True` continues; the exception of a progress callable as it
/// was raised; a failure as [`Error`].
pub fn run_ended<T, E: Into<Error>>(
    py: Python<'_>,
    outcome: Result<Ended<T>, E>,
    python_error: Option<PyErr>,
    checkpoint: &Path,
) -> PyResult<T> {
    let interrupted = |step: u64| {
        format!(
            "interrupted at step {step}; state saved in {}; continue with resume=True",
            checkpoint.display()
        )
    };
    let ended = match (outcome, python_error) {
        (Ok(Ended::Interrupted { step }), Some(e))
            if e.is_instance_of::<PyKeyboardInterrupt>(py) =>
        {
            return Err(PyKeyboardInterrupt::new_err(interrupted(step)));
        }
        (_, Some(e)) => return Err(e),
        (outcome, None) => outcome.map_err(Into::into)?,
    };
    match ended {
        Ended::Finished(result) => Ok(result),
        Ended::Interrupted { step } => Err(Error::new(Kind::Interrupted, interrupted(step)).into()),
        Ended::InterruptedPacking => Err(Error::from(SimError::InterruptedPacking).into()),
        Ended::Failed(reason) => Err(Error::from(reason).into()),
    }
}

/// One progress report of the worker.
pub struct Report {
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
    /// The report of progress `p`, with the lines of `status` (a terminal's) and `log`.
    pub fn of(p: &Progress, (status, log): (&mut ProgressLines, &mut ProgressLines)) -> Self {
        Report {
            equilibrating: p.phase == Phase::Equilibrating,
            strain: p.strain,
            max_strain: p.max_strain,
            snapshots: p.snapshots,
            snapshots_target: p.snapshots_target,
            step: p.step,
            status: status.line(p).unwrap_or_default(),
            line: log.line(p),
        }
    }

    pub fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
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
