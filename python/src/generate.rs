//! `generate`: the runs of a grid (or one shard of them), each in its folder under the work
//! folder, and the grid's tables beside the dataset, as `suspflow generate` makes them
//! (`sim::run::batch::Batch`, `rheometry::sweep_tables`): finished runs are skipped,
//! interrupted ones resume from their checkpoints, and the tables are rewritten after every
//! run. The batch goes on a worker thread ([`run_watched`]); Ctrl-C stops every run with
//! its checkpoint.
use crate::error::{Error, Kind};
use crate::worker::{run_watched, INTERRUPTED};
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use rheometry::sweep_tables::{run_counts, work_beside, SweepTables};
use sim::input::grid::{Grid, GridRun};
use sim::output::file_lock::FileLock;
use sim::output::run_summary::RunOutcome;
use sim::run::batch::{Batch, BatchWatch};
use sim::run::run_folder::Ended;
use sim::run::Progress;
use std::path::PathBuf;
use std::sync::mpsc::Sender;
use std::sync::Mutex;

/// How a batch's runs stand at its end: done, failed (label and reason), still to do.
type Counts = (usize, Vec<(String, String)>, usize);

/// Sends each run's end (label, how it ended, seconds) to the waiting thread.
struct Ends(Mutex<Sender<(String, String, f64)>>);

impl BatchWatch for Ends {
    fn started(&self, _: usize, _: &GridRun, _: bool) {}
    fn progress(&self, _: usize, _: &GridRun, _: &Progress) {}
    fn ended(&self, run: &GridRun, ended: &Ended<RunOutcome>, seconds: f64) {
        let how = match ended {
            Ended::Finished(_) => "finished".to_owned(),
            Ended::Failed(reason) => format!("failed: {reason}"),
            Ended::Interrupted { .. } | Ended::InterruptedPacking => "interrupted".to_owned(),
        };
        if let Ok(send) = self.0.lock() {
            let _ = send.send((run.label(), how, seconds));
        }
    }
}

/// Runs part `shard = (i, n)` of the runs of the grid file `grid` (all of them without),
/// `jobs` at a time on `threads` threads each (0: the command's choice), in the work folder
/// `work` (`<out>.work` by default), and writes the dataset `out`, its run table and, for
/// a whole grid with replicas, its ensemble table. `force` replaces tables this grid did
/// not write; `progress((label, how, seconds))` is called as each run ends. Returns the
/// runs done, failed and still to do.
#[pyfunction]
#[pyo3(signature = (grid, out, shard = None, jobs = 0, threads = 0, work = None, retry_failed = false, force = false, strict = false, progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn generate(
    py: Python<'_>,
    grid: PathBuf,
    out: PathBuf,
    shard: Option<(usize, usize)>,
    jobs: usize,
    threads: usize,
    work: Option<PathBuf>,
    retry_failed: bool,
    force: bool,
    strict: bool,
    progress: Option<PyObject>,
) -> PyResult<Counts> {
    let grid = Grid::from_path(&grid, strict).map_err(Error::from)?;
    let (i, n) = shard.unwrap_or((0, 1));
    let scenes = grid.shard(i, n).map_err(Error::from)?;
    for run in &scenes {
        run.scene
            .check_fits_here()
            .map_err(|e| Error::context(run.label(), e))?;
    }
    let replicas = grid.runs.len() > grid.scene_count();
    let tables = SweepTables::beside(&out, replicas && n == 1);
    let work = work.unwrap_or_else(|| work_beside(&out));
    if !force && !SweepTables::written_by(&work, &scenes) {
        if let Some(file) = tables.files().into_iter().find(|f| f.exists()) {
            return Err(Error::new(
                Kind::File,
                format!(
                    "{} already exists (not written by this grid: {} holds none of its runs); \
                     force=True replaces it, or choose another out",
                    file.display(),
                    work.display()
                ),
            )
            .into());
        }
    }
    for dir in [out.parent(), Some(work.as_path())].into_iter().flatten() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)
                .map_err(|e| Error::new(Kind::File, format!("{}: {e}", dir.display())))?;
        }
    }
    let _lock = FileLock::acquire(
        &work.join("generate.lock"),
        &out.display().to_string(),
        "`suspflow.generate`",
    )
    .map_err(Error::from)?;
    let mut batch = Batch {
        root: work.clone(),
        runs: scenes,
        jobs: 1,
        threads: 1,
        retry_failed,
        interrupt: Some(&INTERRUPTED),
        code_version: crate::CODE_VERSION,
    };
    let todo = batch.prepare().map_err(Error::from)?;
    batch.share_cores(jobs, threads, todo.len());
    tables.write(&batch).map_err(Error::from)?;
    let run = |send: Sender<(String, String, f64)>| {
        let ends = Ends(Mutex::new(send));
        batch.run(todo, &ends, &|| tables.after_run(&batch))
    };
    let (ran, python_error) = run_watched(py, run, |end| match &progress {
        Some(callback) => callback.call1(py, (end,)).map(drop),
        None => Ok(()),
    })?;
    tables.write(&batch).map_err(Error::from)?;
    let counts = run_counts(&batch);
    match (ran, python_error) {
        (_, Some(e)) if e.is_instance_of::<PyKeyboardInterrupt>(py) => {
            Err(PyKeyboardInterrupt::new_err(format!(
                "interrupted with {} run(s) unfinished (state saved in {}); run generate again to continue",
                counts.pending,
                work.display()
            )))
        }
        (_, Some(e)) => Err(e),
        (ran, None) => {
            ran.map_err(Error::from)?;
            Ok((counts.done, counts.failed, counts.pending))
        }
    }
}
