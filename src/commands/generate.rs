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
use crate::exit_status::Stop;
use crate::output_guard;
use anyhow::Context;
use sim::input::grid::{Grid, GridRun};
use sim::run::batch::{cost, Batch, BatchTables};
use sim::run::run_folder::{RunFolder, RunStatus};
use std::path::PathBuf;

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
        gs.scene.check_fits_here().with_context(|| gs.label())?;
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
    let _lock = sim::output::file_lock::FileLock::acquire(
        &outputs.work.join("generate.lock"),
        &outputs.dataset.display().to_string(),
        "`suspflow generate`",
    )?;
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let mut batch = Batch {
        root: outputs.work.clone(),
        runs: scenes.clone(),
        jobs: 1,
        threads: 1,
        retry_failed: args.retry_failed,
        interrupt: Some(crate::interrupt::flag()),
        code_version: crate::CODE_VERSION,
    };
    let todo = batch.prepare()?;
    batch.jobs = if args.jobs > 0 { args.jobs } else { cores }.clamp(1, todo.len().max(1));
    batch.threads = if args.threads > 0 {
        args.threads
    } else {
        (cores / batch.jobs).max(1)
    };
    eprintln!(
        "grid `{}`{}: {} runs of {} scenes, {} already finished or failed; running {} at a time on {} thread(s) each",
        grid.name,
        if shard_n > 1 { format!(" shard {shard_i}/{shard_n}") } else { String::new() },
        scenes.len(), grid.scene_count(), scenes.len() - todo.len(), batch.jobs, batch.threads
    );
    write_outputs(&outputs, &batch)?;
    crate::interrupt::install()?;
    let watch = crate::progress::BatchBars::new(todo.len(), batch.jobs)?;
    batch.run(todo, &watch, &|| {
        watch.overall.inc(1);
        write_outputs(&outputs, &batch)
            .map(drop)
            .map_err(|e| sim::SimError::Output {
                path: outputs.dataset.display().to_string(),
                message: format!("{e:#}"),
            })
    })?;
    watch.finish();
    let summary = write_outputs(&outputs, &batch)?;
    report(&outputs, &batch, summary)
}

/// Refuses to replace a dataset, run table or ensemble table that this grid did not write:
/// one counts as the grid's own when the work directory holds a folder of one of its runs.
fn guard_outputs(outputs: &Outputs, scenes: &[&GridRun], force: bool) -> anyhow::Result<()> {
    output_guard::out_file(&outputs.dataset)?;
    let ours = scenes.iter().any(|gs| {
        RunFolder::in_batch(&outputs.work, &gs.label())
            .scene_toml()
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

/// Rewrites the dataset (finished runs in grid order), the run table and, when this
/// invocation writes one, the ensemble table of the scenes with no run left to do, all
/// atomically; returns the ensemble's summary when one was written.
fn write_outputs(
    outputs: &Outputs,
    batch: &Batch,
) -> anyhow::Result<Option<ensemble_table::EnsembleSummary>> {
    let tables = BatchTables {
        dataset: outputs.dataset.clone(),
        run_table: outputs.scene_table.clone(),
    };
    let (mut dataset, unfinished) = tables.write(batch)?;
    let Some(ensemble) = &outputs.ensemble else {
        return Ok(None);
    };
    dataset.runs.retain(|(id, _), _| !unfinished.contains(id));
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
    batch: &Batch,
    ensemble: Option<ensemble_table::EnsembleSummary>,
) -> anyhow::Result<()> {
    let (mut done, mut failed, mut pending) = (0, Vec::new(), 0);
    for (gs, status) in batch.runs.iter().zip(batch.statuses()) {
        match status {
            RunStatus::Done => done += 1,
            RunStatus::Failed(reason) => failed.push(format!("  {}: {reason}", gs.label())),
            RunStatus::Pending => pending += 1,
        }
    }
    let rows = schema::RunTable::read(&outputs.dataset)?.rows();
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
        return Err(Stop::Interrupted(format!(
            "interrupted with {pending} run(s) unfinished (state saved in {}); run the same \
             command again to continue",
            outputs.work.display()
        ))
        .into());
    }
    if !failed.is_empty() {
        return Err(Stop::Failed(format!(
            "{} run(s) failed and are not in the dataset (--retry-failed runs them again):\n{}",
            failed.len(),
            failed.join("\n")
        ))
        .into());
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
