//! `suspflow generate GRID.toml --out FILE.csv`: runs every scene of a grid, every replica
//! (seed) of a scene as its own run, and writes the dataset (one row per bin per finished
//! run, docs/physics.md section 8), a table of the runs and, when a scene has replicas, the
//! ensemble table and its summary (`crate::ensemble_table`).
//!
//! Runs go in parallel, one thread each by default: below 2048 particles the pair loop
//! is serial (see `sim::forces::force_accumulation`), and the bench shows one scene on two threads
//! no faster than on one at N = 1000, so two runs at a time use both cores fully.
//! Longest runs start first. Every run checkpoints into `<FILE>.work/<id>_seed<seed>/`;
//! re-running the same command skips finished runs and resumes the others from their
//! checkpoints. After each run the dataset is rewritten atomically with the finished runs in
//! grid order, so it is always complete and the same as an uninterrupted run's; the ensemble
//! table holds the scenes none of whose runs is still to do (a failed replica is left out:
//! the `replicas` column says how many were averaged). `--shard` splits the runs (a
//! scene's replicas may land in different parts): the parts write no ensemble table, `merge`
//! writes it from the combined parts.
//!
//! An existing `<FILE>` (or run table, or ensemble table) is replaced only if this grid wrote
//! it (its work directory holds one of the grid's runs) or with `--force`; a lock in the work
//! directory keeps a second run on the same output out.
use crate::ensemble_table;
use crate::file_lock::FileLock;
use crate::output_guard;
use crate::scene_work::{summary_cells, SceneStatus, SceneWork, SUMMARY_COLUMNS};
use anyhow::{bail, Context};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use schema::RunTable;
use sim::input::grid::{Grid, GridRun};
use sim::run::{Phase, RunOptions};
use sim::SimError;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Seconds between status lines of a running scene when no progress bar can be drawn.
const STATUS_EVERY_S: u64 = 60;

#[derive(clap::Args)]
pub struct Args {
    /// Grid file (TOML, see README and `grids/`).
    grid: PathBuf,
    /// Dataset to write; the run table goes to `<stem>.scenes.csv` beside it, and with
    /// replicas the ensemble table to `<stem>.ensemble.csv` (summary `<stem>.ensemble.json`).
    #[arg(long)]
    out: PathBuf,
    /// Run only part `I` of `N` disjoint parts of the grid's runs (0 <= I < N), e.g. a SLURM
    /// array task; combine the parts with `suspflow merge`.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    shard: Option<(usize, usize)>,
    /// Runs at the same time (0 = one per core).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::threads::count)]
    jobs: usize,
    /// Threads per run (0 = cores / jobs).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::threads::count)]
    threads: usize,
    /// Work directory for checkpoints and per-run results (default `<out>.work`).
    #[arg(long)]
    work: Option<PathBuf>,
    /// Run again the runs that failed in an earlier invocation.
    #[arg(long)]
    retry_failed: bool,
    /// Refuse scenes that only warrant a warning (Stokes number >= 0.1).
    #[arg(long)]
    strict: bool,
    /// List the runs with their size, time step and cost, and run nothing.
    #[arg(long)]
    check: bool,
    /// Replace an existing dataset, run table or ensemble table that this grid did not write.
    #[arg(long)]
    force: bool,
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (i, n) = s.split_once('/').ok_or("expected I/N, e.g. 0/4")?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| "I is not a number")?,
        n.trim().parse().map_err(|_| "N is not a number")?,
    );
    if n == 0 || i >= n {
        return Err(format!("need 0 <= I < N, got {i}/{n}"));
    }
    Ok((i, n))
}

/// Estimated particle-steps of a run up to its strain budget plus its averaging.
fn cost(scene: &sim::input::scene::Scene) -> f64 {
    let r = &scene.file.run;
    let strain = r.max_strain.min(10.0) + r.sample_strain * r.snapshots as f64;
    scene.timestep.steps_per_strain(scene) * strain * scene.n_particles() as f64
}

/// Paths of the outputs.
struct Outputs {
    dataset: PathBuf,
    scene_table: PathBuf,
    /// The ensemble table and summary, when this invocation writes them.
    ensemble: Option<[PathBuf; 2]>,
    work: PathBuf,
}

impl Outputs {
    fn new(args: &Args, ensemble: bool) -> Outputs {
        let stem = args.out.with_extension("");
        let mut table = stem.into_os_string();
        table.push(".scenes.csv");
        let work = args.work.clone().unwrap_or_else(|| {
            let mut w = args.out.clone().into_os_string();
            w.push(".work");
            PathBuf::from(w)
        });
        Outputs {
            dataset: args.out.clone(),
            scene_table: PathBuf::from(table),
            ensemble: ensemble.then(|| ensemble_table::paths(&args.out)),
            work,
        }
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let grid = Grid::from_path(&args.grid, args.strict)?;
    let (shard_i, shard_n) = args.shard.unwrap_or((0, 1));
    let scenes = grid.shard(shard_i, shard_n)?;
    for gs in &scenes {
        for w in &gs.scene.warnings {
            eprintln!("warning: {}: {w}", gs.label());
        }
        sim::input::memory_estimate::check_fits_here(&gs.scene).with_context(|| gs.label())?;
    }
    if args.check {
        print_check(&scenes);
        return Ok(());
    }
    let replicas = grid.runs.len() > grid.scene_count();
    if replicas && shard_n > 1 {
        eprintln!("note: the ensemble table of a grid with replicas is written by `suspflow merge` of the parts");
    }
    let outputs = Outputs::new(&args, replicas && shard_n == 1);
    guard_outputs(&outputs, &scenes, args.force)?;
    if let Some(parent) = outputs
        .dataset
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
    {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("creating {}", parent.display()))?;
    }
    std::fs::create_dir_all(&outputs.work)
        .with_context(|| format!("creating {}", outputs.work.display()))?;
    let _lock = FileLock::acquire(
        &outputs.work.join("generate.lock"),
        &outputs.dataset.display().to_string(),
        "generate",
    )?;
    let mut todo = Vec::new();
    for gs in &scenes {
        let work = SceneWork::new(&outputs.work, &gs.label());
        work.prepare(&gs.scene.file)?;
        match work.status()? {
            SceneStatus::Done(_) => {}
            SceneStatus::Failed(_) if !args.retry_failed => {}
            _ => {
                work.clear_failure();
                todo.push(*gs);
            }
        }
    }
    // Cheapest first in the vector: workers pop the most expensive scene first.
    todo.sort_by(|a, b| {
        cost(&a.scene)
            .total_cmp(&cost(&b.scene))
            .then(b.index.cmp(&a.index))
    });
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let jobs = if args.jobs > 0 { args.jobs } else { cores }.clamp(1, todo.len().max(1));
    let threads = if args.threads > 0 {
        args.threads
    } else {
        (cores / jobs).max(1)
    };
    let skipped = scenes.len() - todo.len();
    eprintln!(
        "grid `{}`{}: {} runs of {} scenes, {} already finished or failed; running {} at a time on {} thread(s) each",
        grid.name,
        if shard_n > 1 { format!(" shard {shard_i}/{shard_n}") } else { String::new() },
        scenes.len(), grid.scene_count(), skipped, jobs, threads
    );
    write_outputs(&outputs, &scenes)?;
    ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst))
        .context("installing the Ctrl-C handler")?;

    let multi = MultiProgress::new();
    let overall = multi.add(ProgressBar::new(todo.len() as u64));
    overall.set_style(ProgressStyle::with_template(
        "[{elapsed_precise}] {bar:30} {pos}/{len} runs {msg}",
    )?);
    let log = |line: String| {
        if multi.is_hidden() {
            eprintln!("{line}");
        } else {
            let _ = multi.println(line);
        }
    };
    let queue = Mutex::new(todo);
    let finish = Mutex::new(());
    let worker_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| {
                let bar = multi.add(ProgressBar::new(1000));
                bar.set_style(ProgressStyle::with_template("  {msg}").expect("static template"));
                loop {
                    if INTERRUPTED.load(Ordering::SeqCst)
                        || worker_error.lock().map(|e| e.is_some()).unwrap_or(true)
                    {
                        break;
                    }
                    let Some(gs) = queue.lock().ok().and_then(|mut q| q.pop()) else {
                        break;
                    };
                    let result = run_scene(gs, &outputs.work, threads, &bar, &log).and_then(|()| {
                        let _guard = finish.lock();
                        write_outputs(&outputs, &scenes)
                    });
                    overall.inc(1);
                    if let Err(e) = result {
                        if let Ok(mut slot) = worker_error.lock() {
                            slot.get_or_insert(e);
                        }
                    }
                }
                bar.finish_and_clear();
            });
        }
    });
    overall.finish_and_clear();
    if let Some(e) = worker_error.into_inner().ok().flatten() {
        return Err(e);
    }
    let summary = write_outputs(&outputs, &scenes)?;
    report(&outputs, &scenes, summary)
}

/// Refuses to replace a dataset, run table or ensemble table that this grid did not write:
/// one counts as the grid's own when the work directory holds a folder of one of its runs.
fn guard_outputs(outputs: &Outputs, scenes: &[&GridRun], force: bool) -> anyhow::Result<()> {
    output_guard::out_file(&outputs.dataset)?;
    let ours = scenes.iter().any(|gs| {
        SceneWork::new(&outputs.work, &gs.label())
            .dir
            .join("scene.toml")
            .exists()
    });
    if !ours {
        let what = format!(
            "not written by this grid: {} holds none of its runs",
            outputs.work.display()
        );
        for file in [&outputs.dataset, &outputs.scene_table]
            .into_iter()
            .chain(outputs.ensemble.iter().flatten())
        {
            output_guard::refuse_unless_force(file, force, &what, "choose another --out")?;
        }
    }
    Ok(())
}

/// Runs one replica of a scene into its work folder; a failure of the run itself is
/// recorded there, and only problems of the work directory are returned as errors.
fn run_scene(
    gs: &GridRun,
    root: &Path,
    threads: usize,
    bar: &ProgressBar,
    log: &(dyn Fn(String) + Sync),
) -> anyhow::Result<()> {
    let label = gs.label();
    let work = SceneWork::new(root, &label);
    let resuming = work.checkpoint().exists();
    log(format!(
        "{label} start{}: N = {}, L_y = {}, phi = {}, `{}`",
        if resuming { " (resuming)" } else { "" },
        gs.scene.n_particles(),
        gs.scene.box_len[1],
        gs.scene.file.particles.phi,
        gs.scene.profile.expr()
    ));
    let opts = RunOptions {
        checkpoint: Some(work.checkpoint()),
        resume: true,
        interrupt: Some(&INTERRUPTED),
        code_version: crate::CODE_VERSION,
        packing_progress: None,
    };
    let started = Instant::now();
    let mut last_line = Instant::now();
    let outcome = crate::threads::with_threads(threads, || {
        sim::run::run(&gs.scene, &opts, &mut |p, _| {
            let msg = match p.phase {
                Phase::Equilibrating => format!(
                    "{label}: equilibrating, strain {:.2} (budget {})",
                    p.strain, p.max_strain
                ),
                Phase::Averaging => format!(
                    "{label}: averaging, snapshot {} / {}",
                    p.snapshots, p.snapshots_target
                ),
            };
            // Without a terminal (batch jobs, nohup) the bars are hidden: a status line a minute instead.
            if bar.is_hidden() && last_line.elapsed().as_secs() >= STATUS_EVERY_S {
                log(format!("{msg} ({:.0} s)", started.elapsed().as_secs_f64()));
                last_line = Instant::now();
            }
            bar.set_message(msg);
        })
    })?;
    match outcome {
        Ok(outcome) => {
            sim::output::result_files::write_results(&work.dir, &gs.scene, &outcome)?;
            std::fs::remove_file(work.checkpoint()).ok();
            let s = &outcome.summary;
            log(format!(
                "{label} done in {:.0} s: steady at strain {:.2}, momentum residual {:.4}",
                started.elapsed().as_secs_f64(),
                s.strain_to_steady,
                s.momentum_residual.unwrap_or(f64::NAN)
            ));
        }
        Err(SimError::Interrupted { step }) => log(format!(
            "{label} interrupted at step {step}; checkpoint saved (the same command resumes it)"
        )),
        Err(SimError::InterruptedPacking) => log(format!(
            "{label} interrupted during its initial packing; nothing to save (the same \
             command starts it again from its seed)"
        )),
        Err(e @ SimError::CheckpointUnusable { .. }) => {
            let reason = format!("{e}; remove it to run this scene from the start");
            log(format!("{label} FAILED: {reason}"));
            work.record_failure(&reason)?;
        }
        Err(e) => {
            log(format!("{label} FAILED: {e}"));
            work.record_failure(&e.to_string())?;
        }
    }
    Ok(())
}

/// Rewrites the dataset (finished runs in grid order), the run table and, when this
/// invocation writes one, the ensemble table of the scenes with no run left to do, all
/// atomically; returns the ensemble's summary when one was written.
fn write_outputs(
    outputs: &Outputs,
    scenes: &[&GridRun],
) -> anyhow::Result<Option<ensemble_table::EnsembleSummary>> {
    let mut dataset = RunTable {
        header: schema::columns::header(),
        runs: Default::default(),
    };
    let mut unfinished = std::collections::HashSet::new();
    // Written through the csv crate: a failure reason holds commas, quotes and newlines.
    let mut table = csv::Writer::from_writer(Vec::new());
    let mut header = vec![
        "scene_id",
        "status",
        "reason",
        "n_particles",
        "L_x",
        "L_y",
        "L_z",
        "phi",
        "profile",
        "seed",
        "rho",
        "stokes",
    ];
    header.extend(SUMMARY_COLUMNS);
    table.write_record(&header)?;
    for gs in scenes {
        let work = SceneWork::new(&outputs.work, &gs.label());
        let (status, reason, summary) = match work.status()? {
            SceneStatus::Done(summary) => {
                let part = RunTable::read(&work.profile_csv())?;
                dataset.absorb(part, &work.profile_csv().display().to_string())?;
                ("done", String::new(), Some(summary))
            }
            SceneStatus::Failed(reason) => ("failed", reason, None),
            SceneStatus::Pending => {
                unfinished.insert(gs.id.as_str());
                ("pending", String::new(), None)
            }
        };
        let f = &gs.scene.file;
        let [l_x, l_y, l_z] = gs.scene.box_len;
        let mut row = vec![
            gs.id.clone(),
            status.to_string(),
            reason,
            gs.scene.n_particles().to_string(),
            l_x.to_string(),
            l_y.to_string(),
            l_z.to_string(),
            f.particles.phi.to_string(),
            gs.scene.profile.expr().to_string(),
            f.seed.to_string(),
            gs.scene.rho.to_string(),
            gs.scene.stokes.to_string(),
        ];
        match &summary {
            Some(s) => row.extend(summary_cells(s)),
            None => row.extend(SUMMARY_COLUMNS.map(|_| String::new())),
        }
        table.write_record(&row)?;
    }
    sim::output::atomic_write::write_atomic(&outputs.dataset, dataset.to_text().as_bytes())?;
    sim::output::atomic_write::write_atomic(&outputs.scene_table, &table.into_inner()?)?;
    let Some(ensemble) = &outputs.ensemble else {
        return Ok(None);
    };
    dataset
        .runs
        .retain(|(id, _), _| !unfinished.contains(id.as_str()));
    if dataset.runs.is_empty() {
        for file in ensemble {
            std::fs::remove_file(file).ok();
        }
        return Ok(None);
    }
    let ensemble = ensemble_table::build(&outputs.dataset, &dataset)?;
    Ok(Some(ensemble_table::write_beside(
        &outputs.dataset,
        ensemble,
    )?))
}

/// Final summary; an error if runs failed or the invocation was interrupted.
fn report(
    outputs: &Outputs,
    scenes: &[&GridRun],
    ensemble: Option<ensemble_table::EnsembleSummary>,
) -> anyhow::Result<()> {
    let (mut done, mut failed, mut pending) = (0, Vec::new(), 0);
    for gs in scenes {
        match SceneWork::new(&outputs.work, &gs.label()).status()? {
            SceneStatus::Done(_) => done += 1,
            SceneStatus::Failed(reason) => failed.push(format!("  {}: {reason}", gs.label())),
            SceneStatus::Pending => pending += 1,
        }
    }
    let rows = RunTable::read(&outputs.dataset)?.rows();
    println!(
        "dataset: {} ({rows} rows from {done} runs)",
        outputs.dataset.display()
    );
    println!("runs:    {}", outputs.scene_table.display());
    if let (Some([table, json]), Some(summary)) = (&outputs.ensemble, &ensemble) {
        println!(
            "ensemble: {} (summary {}): per observable, the between-replica standard error \
             over the batch-means one, and the relative ensemble error\n{}",
            table.display(),
            json.display(),
            ensemble_table::describe(summary)
        );
    }
    if pending > 0 {
        bail!("interrupted with {pending} run(s) unfinished (state saved in {}); run the same command again to continue",
            outputs.work.display());
    }
    if !failed.is_empty() {
        bail!(
            "{} run(s) failed and are not in the dataset (--retry-failed runs them again):\n{}",
            failed.len(),
            failed.join("\n")
        );
    }
    Ok(())
}

/// The runs and their estimated cost, without running.
fn print_check(scenes: &[&GridRun]) {
    println!(
        "{:<14} {:>10} {:>6} {:>6} {:>6} {:>7} {:>7} {:>9} {:>12}  profile",
        "scene", "seed", "N", "L_y", "phi", "rho", "St", "dt", "part-steps"
    );
    let mut total = 0.0;
    for gs in scenes {
        let s = &gs.scene;
        let c = cost(s);
        total += c;
        println!(
            "{:<14} {:>10} {:>6} {:>6} {:>6.4} {:>7.3} {:>7.4} {:>9.3e} {:>12.3e}  {}",
            gs.id,
            gs.seed(),
            s.n_particles(),
            s.box_len[1],
            s.file.particles.phi,
            s.rho,
            s.stokes,
            s.timestep.dt,
            c,
            s.profile.expr()
        );
    }
    let mut ids: Vec<&str> = scenes.iter().map(|r| r.id.as_str()).collect();
    ids.dedup();
    println!(
        "{} runs of {} scenes, about {total:.3e} particle-steps (equilibration capped at 10 strain, plus averaging)",
        scenes.len(),
        ids.len()
    );
}
