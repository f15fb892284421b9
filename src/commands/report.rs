//! `suspflow report`: writes `reports/<name>/report.md` with its tables and figures:
//! (1) simulation error against run time (validation scenes against a long reference run),
//! (2) surrogate error against training time and trees, prediction time per profile,
//! (3) simulator and surrogate side by side, (4) stability on stiff and extreme cases,
//! (5) Theta against Delta_v.
//!
//! Quick mode (default) shrinks the validation scenes' box to 8 x L_y x 8 and averages less;
//! `--full` runs them as shipped (the README's numbers).
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use sim::studies::convergence::{self, ConvergenceRun};
use sim::studies::stability_sweep::{self, SweepSize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Report name: writes `<out>/<name>/report.md` and its figures.
    #[arg(long, default_value = "quick", value_parser = report_name)]
    name: String,
    /// Parent directory of the reports.
    #[arg(long, default_value = "reports")]
    out: PathBuf,
    /// Full mode: validation scenes as shipped, longer averaging, longer stability runs.
    #[arg(long)]
    full: bool,
    /// Grid of the scenes of sections 1 and 3 (the validation profiles).
    #[arg(long, default_value = "grids/validate.toml")]
    scenes: PathBuf,
    /// Snapshots of the longest partial average (multiple of 4; default 256 quick, 512 full).
    #[arg(long, allow_negative_numbers = true)]
    partial: Option<usize>,
    /// Snapshots of the reference average (multiple of 10; default 500 quick, 1000 full).
    #[arg(long, allow_negative_numbers = true)]
    reference: Option<usize>,
    /// Training set of section 2: the shipped models' own training table, so that their
    /// tuned hyper-parameters apply.
    #[arg(long, default_value = "datasets/wide_plugs.ensemble.csv")]
    train: PathBuf,
    /// Validation set of sections 2 and 5.
    #[arg(long, default_value = "datasets/validate.csv")]
    validate: PathBuf,
    /// Trained models (`suspflow train --out`).
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Sweep only these parameters in section 4 (k_n, xi_min, phi, amplitude, size_ratio).
    #[arg(long)]
    only: Vec<String>,
}

/// Box edge (x and z, units a) of the validation scenes in quick mode.
const QUICK_BOX: f64 = 8.0;

/// A report name names a folder inside `--out`: the scene-name rule (no path separator, no
/// leading '.') keeps it there.
fn report_name(name: &str) -> Result<String, String> {
    schema::scene_name::check(name).map(|()| name.to_string())
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let (partial, reference) = (
        args.partial.unwrap_or(if args.full { 512 } else { 256 }),
        args.reference.unwrap_or(if args.full { 1000 } else { 500 }),
    );
    anyhow::ensure!(
        partial >= 8 && partial % 4 == 0,
        "--partial {partial}: must be a multiple of 4, at least 8"
    );
    anyhow::ensure!(
        reference >= 10 && reference % 10 == 0,
        "--reference {reference}: must be a multiple of 10, at least 10"
    );
    if let Some(bad) = args
        .only
        .iter()
        .find(|o| !stability_sweep::PARAMETERS.iter().any(|(p, _)| p == o))
    {
        anyhow::bail!(
            "--only {bad}: not a swept parameter (k_n, xi_min, phi, amplitude, size_ratio)"
        );
    }
    for input in [&args.train, &args.validate] {
        anyhow::ensure!(
            input.is_file(),
            "{}: no such file (see datasets/README.md to generate it)",
            input.display()
        );
    }
    let scenes = validation_scenes(&args.scenes, args.full)?;
    let dir = args.out.join(&args.name);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let started = Instant::now();
    let mode = if args.full { "full" } else { "quick" };
    let mut md = String::new();
    let _ = writeln!(md, "# suspflow report `{}` ({mode} mode)\n", args.name);
    let _ = writeln!(
        md,
        "Command: `suspflow {}`; code version {}; {} threads.\n",
        std::env::args().skip(1).collect::<Vec<_>>().join(" "),
        crate::CODE_VERSION,
        rayon::current_num_threads()
    );

    eprintln!("1/5 convergence runs of {} scenes ({partial} + {reference} snapshots after the steady state) ...", scenes.len());
    let bar = progress_bar(scenes.len() as u64, "scenes");
    let runs: Vec<ConvergenceRun> = scenes
        .par_iter()
        .with_max_len(1)
        .map(|s| {
            let r = convergence::run(s, partial, reference, |a, b| {
                surrogate::relative_l2(a, b, 0.0)
            })
            .with_context(|| format!("scene {}", s.file.name));
            bar.inc(1);
            r
        })
        .collect::<anyhow::Result<_>>()?;
    bar.finish_and_clear();
    let section1 = crate::report::convergence_report::section(&runs, &dir)?;
    eprintln!("2/5 surrogate error against training time ...");
    let section2 =
        crate::report::surrogate_cost::section(&args.train, &args.validate, &args.models, &dir)?;
    eprintln!("3/5 side by side ...");
    let section3 = crate::report::side_by_side::markdown(&crate::report::side_by_side::compare(
        &runs,
        &args.models,
        &dir,
    )?);
    let size = if args.full {
        SweepSize {
            window_strain: 0.1,
            snapshots: 50,
            box_edge: 10.0,
        }
    } else {
        SweepSize {
            window_strain: 0.05,
            snapshots: 20,
            box_edge: 8.0,
        }
    };
    let cases = stability_sweep::cases(&args.only);
    eprintln!("4/5 stability sweep: {} cases ...", cases.len());
    let sweep_started = Instant::now();
    let bar = progress_bar(cases.len() as u64, "cases");
    let results = stability_sweep::sweep(cases, size, &|| bar.inc(1));
    bar.finish_and_clear();
    let section4 = crate::plots::stability_map::section(
        &results,
        size,
        sweep_started.elapsed().as_secs_f64(),
        &dir,
    )?;
    eprintln!("5/5 Theta against Delta_v ...");
    let section5 = crate::report::descriptor_noise::section(&args.validate, &args.models, &dir)?;
    for s in [section1, section2, section3, section4, section5] {
        md.push_str(&s);
    }
    let _ = writeln!(
        md,
        "Report written in {:.0} s.",
        started.elapsed().as_secs_f64()
    );
    let path = dir.join("report.md");
    schema::write_atomic(&path, md.as_bytes())?;
    println!("{}", path.display());
    Ok(())
}

/// The scenes of `grid`; in quick mode with the box shrunk to [`QUICK_BOX`] across.
/// Refuses, before any run, a Brownian scene: the report sets the runs beside the
/// surrogates and the solver, whose closures are of non-Brownian runs.
fn validation_scenes(grid: &Path, full: bool) -> anyhow::Result<Vec<sim::input::scene::Scene>> {
    let path = grid;
    let grid = sim::input::grid::Grid::from_path(grid, false)?;
    if let Some(brownian) = grid.runs.iter().find(|g| g.scene.thermal.is_some()) {
        anyhow::bail!(
            "--scenes {}: scene {} is Brownian (fluid.kT = {}), but the report compares the \
             runs with the surrogates and the solver, which are of non-Brownian runs; give a \
             grid of non-Brownian profile scenes (e.g. grids/validate.toml)",
            path.display(),
            brownian.id,
            brownian.scene.file.fluid.kt
        );
    }
    grid.runs
        .into_iter()
        .map(|g| {
            let mut file = g.scene.file.clone();
            file.name = g.id.clone();
            if !full {
                file.box_.l_x = file.box_.l_x.min(QUICK_BOX);
                file.box_.l_z = file.box_.l_z.min(QUICK_BOX);
            }
            Ok(sim::input::scene::Scene::from_file(file, false)?)
        })
        .collect()
}

/// A progress bar over `n` items, drawn only on a terminal.
fn progress_bar(n: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::new(n);
    if let Ok(style) =
        ProgressStyle::with_template(&format!("{{bar:30}} {{pos}}/{{len}} {what} {{elapsed}}"))
    {
        bar.set_style(style);
    }
    bar
}
