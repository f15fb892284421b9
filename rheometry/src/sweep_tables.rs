//! The tables of a grid's runs (`generate`): the dataset (one row per bin per finished run),
//! the run table and, for a grid with replicas, the ensemble table of the scenes with no run
//! left to do (`<stem>.ensemble.csv`, summary `<stem>.ensemble.json`), all rewritten
//! atomically from the batch's run folders after every run. One writer for the command and
//! Python.
use crate::error::Result;
use schema::RunTable;
use sim::input::grid::GridRun;
use sim::run::batch::{Batch, BatchTables};
use sim::run::run_folder::{RunFolder, RunStatus};
use std::path::{Path, PathBuf};
use surrogate::{build_ensemble, Ensemble, EnsembleSummary};

/// Where a grid's tables go, beside the dataset `out`.
#[derive(Clone, Debug)]
pub struct SweepTables {
    pub dataset: PathBuf,
    /// `<stem>.scenes.csv`.
    pub run_table: PathBuf,
    /// The ensemble table and its summary, when this writer writes them.
    pub ensemble: Option<[PathBuf; 2]>,
}

/// How a batch's runs stand.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RunCounts {
    pub done: usize,
    /// Each failed run's label and reason.
    pub failed: Vec<(String, String)>,
    pub pending: usize,
}

impl SweepTables {
    /// The tables beside dataset `out`, with the ensemble table when `ensemble`.
    pub fn beside(out: &Path, ensemble: bool) -> Self {
        let mut table = out.with_extension("").into_os_string();
        table.push(".scenes.csv");
        SweepTables {
            dataset: out.to_path_buf(),
            run_table: PathBuf::from(table),
            ensemble: ensemble.then(|| ensemble_paths(out)),
        }
    }

    /// Whether the tables in place were written for `scenes` (runs of one grid): the work
    /// folder `work` holds a folder of one of them. Others are not replaced unasked.
    pub fn written_by(work: &Path, scenes: &[&GridRun]) -> bool {
        scenes.iter().any(|run| {
            RunFolder::in_batch(work, &run.label())
                .scene_toml()
                .exists()
        })
    }

    /// Every file these tables replace.
    pub fn files(&self) -> Vec<&Path> {
        [&self.dataset, &self.run_table]
            .into_iter()
            .chain(self.ensemble.iter().flatten())
            .map(PathBuf::as_path)
            .collect()
    }

    /// Rewrites the dataset (finished runs in grid order), the run table and, when these
    /// tables have one, the ensemble table of the scenes with no run left to do, all
    /// atomically; returns the ensemble's summary when one was written (none while no
    /// scene is complete: the ensemble files are then removed).
    pub fn write(&self, batch: &Batch) -> Result<Option<EnsembleSummary>> {
        let tables = BatchTables {
            dataset: self.dataset.clone(),
            run_table: self.run_table.clone(),
        };
        let (mut dataset, unfinished) = tables.write(batch)?;
        let Some(ensemble) = &self.ensemble else {
            return Ok(None);
        };
        dataset.runs.retain(|(id, _), _| !unfinished.contains(id));
        if dataset.runs.is_empty() {
            for file in ensemble {
                std::fs::remove_file(file).ok();
            }
            return Ok(None);
        }
        let ensemble = build_ensemble_of(&self.dataset, &dataset)?;
        Ok(Some(write_ensemble_beside(&self.dataset, ensemble)?))
    }

    /// [`SweepTables::write`] as a batch's `after_run` (`Batch::run`): its failure as the
    /// simulator's error on the dataset.
    pub fn after_run(&self, batch: &Batch) -> std::result::Result<(), sim::SimError> {
        self.write(batch)
            .map(drop)
            .map_err(|e| sim::SimError::Output {
                path: self.dataset.display().to_string(),
                message: e.to_string(),
            })
    }
}

/// The default work folder of dataset `out`: `<out>.work`, where each run has its folder.
pub fn work_beside(out: &Path) -> PathBuf {
    let mut work = out.as_os_str().to_owned();
    work.push(".work");
    PathBuf::from(work)
}

/// The runs of `batch` done, failed (with their reasons) and still to do.
pub fn run_counts(batch: &Batch) -> RunCounts {
    let mut counts = RunCounts::default();
    for (run, status) in batch.runs.iter().zip(batch.statuses()) {
        match status {
            RunStatus::Done => counts.done += 1,
            RunStatus::Failed(reason) => counts.failed.push((run.label(), reason)),
            RunStatus::Pending => counts.pending += 1,
        }
    }
    counts
}

/// The ensemble files beside dataset `path`: `<stem>.ensemble.csv` and `<stem>.ensemble.json`.
pub fn ensemble_paths(path: &Path) -> [PathBuf; 2] {
    ["csv", "json"].map(|ext| {
        let mut name = path.with_extension("").into_os_string();
        name.push(format!(".ensemble.{ext}"));
        PathBuf::from(name)
    })
}

/// The ensemble table and summary of the per-run table `table` of `dataset`.
pub fn build_ensemble_of(dataset: &Path, table: &RunTable) -> Result<Ensemble> {
    Ok(build_ensemble(table, &dataset.display().to_string())?)
}

/// Writes `ensemble` beside `dataset` (atomically) and returns its summary.
pub fn write_ensemble_beside(dataset: &Path, ensemble: Ensemble) -> Result<EnsembleSummary> {
    let [table, summary] = ensemble_paths(dataset);
    schema::write_atomic(&table, &ensemble.csv)?;
    let json = serde_json::to_string_pretty(&ensemble.summary).map_err(|e| {
        crate::error::RheometryError::File {
            path: summary.display().to_string(),
            message: e.to_string(),
        }
    })? + "\n";
    schema::write_atomic(&summary, json.as_bytes())?;
    Ok(ensemble.summary)
}
