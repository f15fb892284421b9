//! A batch of steady runs (the runs of a grid, or a shard of them), each in its
//! [`RunFolder`] under one root: the finished ones are skipped, the interrupted ones resume
//! from their checkpoints, the failed ones wait for a retry; the others run `jobs` at a
//! time, the longest first, on `threads` threads each. After every run the batch's tables
//! are rewritten ([`BatchTables`]): the dataset of the finished runs in grid order, always
//! complete and the same as an uninterrupted batch's, and the run table, one
//! [`RunTableRow`] per run.
use crate::error::SimError;
use crate::input::grid::GridRun;
use crate::input::scene::Scene;
use crate::output::result_files::{write_results, RESULTS};
use crate::output::run_summary::{RunOutcome, RunSummary};
use crate::run::run_folder::{Ended, RunFolder, RunStatus};
use crate::run::{Progress, RunOptions, SteadyRun};
use crate::sampling::steady_state::TREND_WINDOWS;
use schema::write_atomic;
use schema::RunTable;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// Estimated particle-steps of a run, `[least, most]`: its averaging after the shortest
/// warm-up (the [`TREND_WINDOWS`] windows of `run.window_strain` before the first steady
/// test; what a run with a loose `run.steady_chi2` takes) or after its strain budget (at
/// most 10), the averaging as [`Scene::cost`] counts it. The most orders a batch's runs,
/// longest first.
pub fn cost(scene: &Scene) -> [f64; 2] {
    let r = &scene.file.run;
    let budget = r.max_strain.min(10.0);
    let shortest = (TREND_WINDOWS as f64 * r.window_strain).min(budget);
    let whole = scene.cost();
    let per_strain = whole.steps_per_strain * scene.n_particles() as f64;
    [shortest, budget].map(|warmup| per_strain * warmup + whole.averaging_particle_steps)
}

/// What a batch tells its front end as it goes (from its worker threads).
pub trait BatchWatch: Sync {
    /// Worker `worker` starts `run` (continuing its checkpoint when `resuming`).
    fn started(&self, worker: usize, run: &GridRun, resuming: bool);
    /// After every sample of the run that worker `worker` runs.
    fn progress(&self, worker: usize, run: &GridRun, p: &Progress);
    /// `run` ended so, after `seconds`.
    fn ended(&self, run: &GridRun, ended: &Ended<RunOutcome>, seconds: f64);
}

/// The runs of a batch and how to run them.
pub struct Batch<'a> {
    /// Folder of the run folders.
    pub root: PathBuf,
    /// The runs, in grid order.
    pub runs: Vec<&'a GridRun>,
    /// Runs at the same time (at least 1).
    pub jobs: usize,
    /// Threads per run (at least 1).
    pub threads: usize,
    /// Run again the runs that failed before.
    pub retry_failed: bool,
    /// Set (e.g. by Ctrl-C) to stop every run with its checkpoint.
    pub interrupt: Option<&'static AtomicBool>,
    /// Version of the code, written into the results.
    pub code_version: &'static str,
}

impl<'a> Batch<'a> {
    /// The folder of `run`.
    pub fn folder(&self, run: &GridRun) -> RunFolder {
        RunFolder::in_batch(&self.root, &run.label())
    }

    /// Where each run is, in grid order.
    pub fn statuses(&self) -> Vec<RunStatus> {
        self.runs
            .iter()
            .map(|r| self.folder(r).status(&RESULTS))
            .collect()
    }

    /// Makes every run's folder (or checks it was made for the same scene) and returns the
    /// runs to do, cheapest first (the workers take the most expensive first).
    pub fn prepare(&self) -> Result<Vec<&'a GridRun>, SimError> {
        let mut todo = Vec::new();
        for &run in &self.runs {
            let folder = self.folder(run);
            folder.prepare(&run.scene.file)?;
            match folder.status(&RESULTS) {
                RunStatus::Done if folder.records_exactly(&run.scene.file)? => {}
                RunStatus::Failed(_) if !self.retry_failed => {}
                _ => todo.push(run),
            }
        }
        todo.sort_by(|a, b| {
            cost(&a.scene)[1]
                .total_cmp(&cost(&b.scene)[1])
                .then(b.index.cmp(&a.index))
        });
        Ok(todo)
    }

    /// Sets how the cores are shared for `todo` runs to do: `jobs` runs at a time (0 = one
    /// per core), at most one per run, on `threads` threads each (0 = the cores over the
    /// runs at a time, at least 1).
    pub fn share_cores(&mut self, jobs: usize, threads: usize, todo: usize) {
        let cores = std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1);
        self.jobs = if jobs > 0 { jobs } else { cores }.clamp(1, todo.max(1));
        self.threads = if threads > 0 {
            threads
        } else {
            (cores / self.jobs).max(1)
        };
    }

    /// Runs `todo` (from [`Batch::prepare`]), calling `after_run` after each (to rewrite
    /// the batch's tables, say); the first error of a folder or of `after_run` stops the
    /// batch and is returned. An interrupt stops every run with its checkpoint.
    pub fn run(
        &self,
        todo: Vec<&GridRun>,
        watch: &dyn BatchWatch,
        after_run: &(dyn Fn() -> Result<(), SimError> + Sync),
    ) -> Result<(), SimError> {
        let jobs = self.jobs.clamp(1, todo.len().max(1));
        let queue = Mutex::new(todo);
        let finish = Mutex::new(());
        let error: Mutex<Option<SimError>> = Mutex::new(None);
        let stopped = || {
            self.interrupt.is_some_and(|f| f.load(Ordering::SeqCst))
                || error.lock().map(|e| e.is_some()).unwrap_or(true)
        };
        std::thread::scope(|s| {
            for worker in 0..jobs {
                let (queue, finish, error, stopped) = (&queue, &finish, &error, &stopped);
                s.spawn(move || {
                    while !stopped() {
                        let Some(run) = queue.lock().ok().and_then(|mut q| q.pop()) else {
                            break;
                        };
                        let result = self.run_one(worker, run, watch).and_then(|()| {
                            let _guard = finish.lock();
                            after_run()
                        });
                        if let Err(e) = result {
                            if let Ok(mut slot) = error.lock() {
                                slot.get_or_insert(e);
                            }
                        }
                    }
                });
            }
        });
        match error.into_inner() {
            Ok(Some(e)) => Err(e),
            _ => Ok(()),
        }
    }

    /// Runs one run into its folder on a pool of [`Batch::threads`] threads.
    fn run_one(
        &self,
        worker: usize,
        run: &GridRun,
        watch: &dyn BatchWatch,
    ) -> Result<(), SimError> {
        let folder = self.folder(run);
        let _lock = folder.lock("batch run")?;
        watch.started(worker, run, folder.checkpoint().exists());
        let started = std::time::Instant::now();
        let opts = RunOptions {
            interrupt: self.interrupt,
            code_version: self.code_version,
            ..RunOptions::default()
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.max(1))
            .build()
            .map_err(|e| SimError::Output {
                path: folder.dir.display().to_string(),
                message: format!("starting the thread pool: {e}"),
            })?;
        let ended = pool.install(|| {
            let mut job = SteadyRun::new(&run.scene, self.code_version);
            folder.run(
                &run.scene,
                &mut job,
                opts,
                &mut |p, _| watch.progress(worker, run, p),
                |dir, outcome| write_results(dir, &run.scene, outcome),
            )
        })?;
        watch.ended(run, &ended, started.elapsed().as_secs_f64());
        Ok(())
    }
}

/// One run's line of a batch's run table (`<stem>.scenes.csv`): the run, where it is, and
/// from a finished run's summary what the table shows of it (numbers as in the JSON file;
/// empty when not finite, or absent: a run without drag has no momentum residual).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunTableRow {
    pub scene_id: String,
    /// `done`, `failed` or `pending`.
    pub status: String,
    /// Why a failed run failed.
    pub reason: String,
    pub n_particles: usize,
    #[serde(rename = "L_x", with = "shortest")]
    pub l_x: f64,
    #[serde(rename = "L_y", with = "shortest")]
    pub l_y: f64,
    #[serde(rename = "L_z", with = "shortest")]
    pub l_z: f64,
    #[serde(with = "shortest")]
    pub phi: f64,
    pub profile: String,
    pub seed: u64,
    #[serde(with = "shortest")]
    pub rho: f64,
    #[serde(with = "shortest")]
    pub stokes: f64,
    pub dt: Option<f64>,
    pub dt_limit: Option<String>,
    pub steps: Option<u64>,
    pub strain_to_steady: Option<f64>,
    pub strain_total: Option<f64>,
    pub momentum_residual: Option<f64>,
    pub mean_overlap: Option<f64>,
    pub max_overlap: Option<f64>,
    pub wall_s: Option<f64>,
    pub code_version: Option<String>,
}

/// `f64` cells written as Rust's `Display` writes them (`12`, `0.55`), as the run table
/// always was.
mod shortest {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(v)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let text = String::deserialize(d)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

impl RunTableRow {
    /// The row of `run` in `status`, with its `summary` when finished.
    pub fn new(run: &GridRun, status: &RunStatus, summary: Option<&RunSummary>) -> Self {
        let finite = |v: f64| v.is_finite().then_some(v);
        let s = &run.scene;
        let [l_x, l_y, l_z] = s.box_len;
        let (status, reason) = match status {
            RunStatus::Done => ("done", String::new()),
            RunStatus::Failed(reason) => ("failed", reason.clone()),
            RunStatus::Pending => ("pending", String::new()),
        };
        RunTableRow {
            scene_id: run.id.clone(),
            status: status.into(),
            reason,
            n_particles: s.n_particles(),
            l_x,
            l_y,
            l_z,
            phi: s.file.particles.phi,
            profile: s.profile.expr().to_string(),
            seed: s.file.seed,
            rho: s.rho,
            stokes: s.stokes,
            dt: summary.and_then(|m| finite(m.dt)),
            dt_limit: summary.map(|m| m.dt_limit.clone()),
            steps: summary.map(|m| m.steps),
            strain_to_steady: summary.and_then(|m| finite(m.strain_to_steady)),
            strain_total: summary.and_then(|m| finite(m.strain_total)),
            momentum_residual: summary.and_then(|m| m.momentum_residual.and_then(finite)),
            mean_overlap: summary.and_then(|m| finite(m.mean_overlap)),
            max_overlap: summary.and_then(|m| finite(m.max_overlap)),
            wall_s: summary.and_then(|m| finite(m.wall_s)),
            code_version: summary.map(|m| m.code_version.clone()),
        }
    }

    /// The rows of the run table at `path`.
    pub fn read_all(path: &Path) -> Result<Vec<RunTableRow>, SimError> {
        let err = |e: csv::Error| SimError::Output {
            path: path.display().to_string(),
            message: format!("reading the run table: {e}"),
        };
        csv::Reader::from_path(path)
            .map_err(err)?
            .deserialize()
            .collect::<Result<_, _>>()
            .map_err(err)
    }

    /// The run tables `parts` (each with the file it came from, for errors) as one, in
    /// (scene id, seed) order like the merged dataset; refuses a run in two of them.
    pub fn merge(parts: Vec<(String, Vec<RunTableRow>)>) -> Result<Vec<RunTableRow>, SimError> {
        let mut rows: Vec<(String, RunTableRow)> = parts
            .into_iter()
            .flat_map(|(file, rows)| rows.into_iter().map(move |r| (file.clone(), r)))
            .collect();
        rows.sort_by(|(_, a), (_, b)| (&a.scene_id, a.seed).cmp(&(&b.scene_id, b.seed)));
        if let Some(pair) = rows
            .windows(2)
            .find(|w| (&w[0].1.scene_id, w[0].1.seed) == (&w[1].1.scene_id, w[1].1.seed))
        {
            return Err(SimError::Output {
                path: pair[1].0.clone(),
                message: format!(
                    "run {} seed {} is also in the run table {}",
                    pair[1].1.scene_id, pair[1].1.seed, pair[0].0
                ),
            });
        }
        Ok(rows.into_iter().map(|(_, r)| r).collect())
    }

    /// The run table of `rows`, as CSV (the reasons of failures hold commas, quotes and
    /// line ends).
    pub fn to_csv(rows: &[RunTableRow]) -> Result<Vec<u8>, SimError> {
        let err = |e: String| SimError::Output {
            path: "run table".into(),
            message: e,
        };
        let mut table = csv::Writer::from_writer(Vec::new());
        for row in rows {
            table.serialize(row).map_err(|e| err(e.to_string()))?;
        }
        table.into_inner().map_err(|e| err(e.to_string()))
    }
}

/// The two tables of a batch: the dataset (one row per bin per finished run, grid order)
/// and the run table (one [`RunTableRow`] per run).
pub struct BatchTables {
    pub dataset: PathBuf,
    pub run_table: PathBuf,
}

impl BatchTables {
    /// Rewrites both tables atomically from the folders of `batch`; returns the dataset
    /// and the scenes with a run still to do.
    pub fn write(&self, batch: &Batch) -> Result<(RunTable, HashSet<String>), SimError> {
        let mut dataset = RunTable {
            header: schema::columns::header(),
            runs: Default::default(),
        };
        let mut unfinished = HashSet::new();
        let mut rows = Vec::with_capacity(batch.runs.len());
        for (run, status) in batch.runs.iter().zip(batch.statuses()) {
            let folder = batch.folder(run);
            let summary = match status {
                RunStatus::Done => {
                    let part = RunTable::read(&folder.profile_csv())?;
                    dataset.absorb(part, &folder.profile_csv().display().to_string())?;
                    Some(folder.summary()?)
                }
                RunStatus::Pending => {
                    unfinished.insert(run.id.clone());
                    None
                }
                RunStatus::Failed(_) => None,
            };
            rows.push(RunTableRow::new(run, &status, summary.as_ref()));
        }
        write_atomic(&self.dataset, dataset.to_text().as_bytes())?;
        write_atomic(&self.run_table, &RunTableRow::to_csv(&rows)?)?;
        Ok((dataset, unfinished))
    }
}
