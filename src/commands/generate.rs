//! `suspflow generate GRID.toml --out FILE.csv`: runs every scene of a grid, every replica
//! (seed) of a scene as its own run, and writes the dataset (one row per bin per finished
//! run, docs/physics.md section 8), a table of the runs and, when a scene has replicas, the
//! ensemble table and its summary (`rheometry::sweep_tables`).
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
use rheometry::sweep_tables::{run_counts, work_beside, SweepTables};
use rheometry::EnsembleSummary;
use sim::input::grid::{Grid, GridRun};
use sim::run::batch::{cost, Batch};
use sim::sampling::steady_state::TREND_WINDOWS;
use std::path::{Path, PathBuf};

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
    let outputs = SweepTables::beside(&args.out, replicas && shard_n == 1);
    let work = args.work.clone().unwrap_or_else(|| work_beside(&args.out));
    guard_outputs(&outputs, &work, &scenes, args.force)?;
    if let Some(parent) = outputs
        .dataset
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
    {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("creating {}", parent.display()))?;
    }
    std::fs::create_dir_all(&work).with_context(|| format!("creating {}", work.display()))?;
    let _lock = sim::output::file_lock::FileLock::acquire(
        &work.join("generate.lock"),
        &format!("the work folder {}", work.display()),
        "`suspflow generate`",
    )?;
    let mut batch = Batch {
        root: work.clone(),
        runs: scenes.clone(),
        jobs: 1,
        threads: 1,
        retry_failed: args.retry_failed,
        interrupt: Some(crate::interrupt::flag()),
        code_version: crate::CODE_VERSION,
    };
    let todo = batch.prepare()?;
    batch.share_cores(args.jobs, args.threads, todo.len());
    eprintln!(
        "grid `{}`{}: {} runs of {} scenes, {} already finished or failed; running {} at a time on {} thread(s) each",
        grid.name,
        if shard_n > 1 { format!(" shard {shard_i}/{shard_n}") } else { String::new() },
        scenes.len(), grid.scene_count(), scenes.len() - todo.len(), batch.jobs, batch.threads
    );
    outputs.write(&batch)?;
    crate::interrupt::install()?;
    let watch = crate::progress::BatchBars::new(todo.len(), batch.jobs)?;
    batch.run(todo, &watch, &|| {
        watch.overall.inc(1);
        outputs.after_run(&batch)
    })?;
    watch.finish();
    let summary = outputs.write(&batch)?;
    report(&outputs, &work, &batch, summary)
}

/// Refuses to replace a dataset, run table or ensemble table that this grid did not write:
/// one counts as the grid's own when the work directory holds a folder of one of its runs.
fn guard_outputs(
    outputs: &SweepTables,
    work: &Path,
    scenes: &[&GridRun],
    force: bool,
) -> anyhow::Result<()> {
    output_guard::out_file(&outputs.dataset)?;
    if !SweepTables::written_by(work, scenes) {
        let what = format!(
            "not written by this grid: {} holds none of its runs",
            work.display()
        );
        for file in outputs.files() {
            output_guard::refuse_unless_force(file, force, &what, "choose another --out")?;
        }
    }
    Ok(())
}

/// Final summary; an error if runs failed or the invocation was interrupted.
fn report(
    outputs: &SweepTables,
    work: &Path,
    batch: &Batch,
    ensemble: Option<EnsembleSummary>,
) -> anyhow::Result<()> {
    let counts = run_counts(batch);
    let (done, pending) = (counts.done, counts.pending);
    let failed: Vec<String> = counts
        .failed
        .iter()
        .map(|(label, reason)| format!("  {label}: {reason}"))
        .collect();
    let rows = schema::RunTable::read(&outputs.dataset)?.rows();
    println!(
        "dataset: {} ({rows} rows from {done} runs)",
        outputs.dataset.display()
    );
    println!("runs:    {}", outputs.run_table.display());
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
            work.display()
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

/// The runs and their estimated cost, without running: each run's particle-steps at
/// most, and the whole grid's between its shortest warm-ups and its strain budgets.
fn print_check(scenes: &[&GridRun]) {
    println!(
        "{:<14} {:>10} {:>6} {:>6} {:>6} {:>7} {:>7} {:>9} {:>12} {:>12}  profile",
        "scene", "seed", "N", "L_y", "phi", "rho", "St", "dt", "least", "most"
    );
    let (mut least, mut most, mut hours) = (0.0, 0.0, [0.0, 0.0]);
    for gs in scenes {
        let s = &gs.scene;
        let [l, m] = cost(s);
        let rate = s.cost().rate;
        (least, most) = (least + l, most + m);
        hours = [hours[0] + l / rate / 3600.0, hours[1] + m / rate / 3600.0];
        println!(
            "{:<14} {:>10} {:>6} {:>6} {:>6.4} {:>7.3} {:>7.4} {:>9.3e} {:>12.3e} {:>12.3e}  {}",
            gs.id,
            gs.seed(),
            s.n_particles(),
            s.box_len[1],
            s.file.particles.phi,
            s.rho,
            s.stokes,
            s.timestep.dt,
            l,
            m,
            s.profile.expr()
        );
    }
    let mut ids: Vec<&str> = scenes.iter().map(|r| r.id.as_str()).collect();
    ids.dedup();
    println!(
        "{} runs of {} scenes, {least:.3e} to {most:.3e} particle-steps (warm-up from {} windows \
         to the strain budget, at most 10, plus averaging): about {:.2} to {:.2} hours here at \
         the estimated rates",
        scenes.len(),
        ids.len(),
        TREND_WINDOWS,
        hours[0],
        hours[1]
    );
}
