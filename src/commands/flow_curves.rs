//! `suspflow flow-curves GRID.toml --runs WORK --out DIR`: the flow curves of a grid of
//! homogeneous-shear scenes (docs/physics.md section 10) that `suspflow generate` has run
//! (resumably, with progress) into the work directory `WORK` (or into several, one per
//! `generate --shard`, all given to `--runs`): per scene the box totals,
//! the fit of `phi_J` and `lambda` of the jamming law with uncertainties from the scatter
//! between seeds, SVG figures of `eta_r(phi)` and `mu(J)` beside the seeds' law, and a
//! markdown summary; with `--local DATA.csv`, the local `mu / J` of the sheared bins of an
//! inhomogeneous-flow dataset against the homogeneous curve at the same volume fraction.
//!
//! Grids over the Peclet number (`fluid.peclet`, Brownian scenes, docs/physics.md section
//! 11) and the friction coefficient are fitted per state `(mu_p, Pe)`, and each volume
//! fraction gets a figure of `eta_r(Pe)` with the parts of the stress (contact,
//! lubrication, and the structural Brownian stress beside them).
//!
//! With `--table DIR/flow_curves.csv` instead of `--runs`, the figures (and the data beside
//! them) and the README are made again from that table, written earlier, without the runs
//! (with `--green-kubo`, the seeds' Pe -> 0 estimate among the fits), and the table is
//! written into `--out` as this version writes it: the same lines, with the columns added
//! since that the grid gives (the contacts) filled in. With both `--table` and `--runs`,
//! the runs finished there take the place of the table's lines of the same scenes (part of
//! a grid run again) and the table is written anew into `--out`.
//!
//! Two stress conventions are fitted: the box's pair stresslets (contact and lubrication,
//! as the thesis' LAMMPS runs report), and the bins' `sigma_xy` under the scene's
//! `[observables] stress` convention (the same pair stresslets by default; with the
//! one-body drag stresslet under `pairs+drag`, as the shipped datasets were made).
use crate::plots::flow_curves::{draw_figures, draw_peclet_figure, peclet_figure};
use crate::report::flow_curves::{folder_list, summary_text, Command};
use anyhow::Context;
use rheometry::{read_green_kubo_replicas, FlowCurveRow, FlowCurveSource, FlowCurves};
use schema::write_atomic;
use sim::input::grid::Grid;
use std::path::PathBuf;
use surrogate::rheology::local_viscosity::{self, LocalBand};
use surrogate::{volume_fractions, Dataset};

/// Centres of the `phi_loc` bands of the local-versus-homogeneous table.
const LOCAL_BANDS: [f64; 7] = [0.44, 0.46, 0.48, 0.50, 0.52, 0.54, 0.56];

#[derive(clap::Args)]
pub struct Args {
    /// Grid of homogeneous-shear scenes (e.g. grids/flow_curves.toml).
    grid: PathBuf,
    /// Work directory in which `suspflow generate` ran the grid (its `--work`, by default
    /// `<out>.work`); one per shard of a grid run in parts (`generate --shard`).
    #[arg(long, num_args = 1.., required_unless_present = "table")]
    runs: Vec<PathBuf>,
    /// A table this command wrote earlier for the grid (`flow_curves.csv`). Alone, the
    /// figures and the README are made again from it (the table is not rewritten); with
    /// `--runs`, the runs finished there replace its lines of the same scenes (part of the
    /// grid run again) in the table written to `--out`.
    #[arg(long, conflicts_with = "local")]
    table: Option<PathBuf>,
    /// Inhomogeneous-flow dataset whose sheared bins are compared with the flow curve
    /// (e.g. datasets/train.csv).
    #[arg(long)]
    local: Option<PathBuf>,
    /// Output directories of `suspflow green-kubo` (one or more replicas per volume
    /// fraction): adds the fit of the seeds' Pe -> 0 estimate, the hydrodynamic viscosity
    /// (lubrication and drag) at each curve's lowest Peclet number plus the Green-Kubo
    /// Brownian viscosity at the same volume fraction (the mean over its replicas, with the
    /// standard error from their spread; one run's block error when it is alone).
    #[arg(long, num_args = 1..)]
    green_kubo: Vec<PathBuf>,
    /// Output directory: flow_curves.csv, eta_r.svg, mu_J.svg, README.md.
    #[arg(long)]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    force: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let grid = Grid::from_path(&args.grid, false)?;
    let _lock = crate::output_guard::claim_dir(&args.out, "`suspflow flow-curves`")?;
    let green_kubo = read_green_kubo_replicas(&args.green_kubo).context("--green-kubo")?;
    let source = FlowCurveSource::new(args.table.as_deref(), &args.runs);
    let curves = FlowCurves::read(&grid, source, &green_kubo).with_context(|| match source {
        FlowCurveSource::Runs(_) => "--runs".to_owned(),
        FlowCurveSource::Table(table) => format!("--table {}", table.display()),
        FlowCurveSource::Updated { table, .. } => format!("--table {} --runs", table.display()),
    })?;
    let from = match source {
        FlowCurveSource::Table(table) => table.display().to_string(),
        _ => format!(
            "{} (run `suspflow generate {} --out ... --work FOLDER`)",
            folder_list(&args.runs),
            args.grid.display(),
        ),
    };
    warn_missing(&curves.missing, grid.runs.len(), &from);
    let local = match &args.local {
        Some(path) => Some(local_viscosity::bands(
            &Dataset::read_csv(path).with_context(|| format!("reading {}", path.display()))?,
            &LOCAL_BANDS,
        )?),
        None => None,
    };
    refuse_earlier(&args, &["README.md", "flow_curves.csv"])?;
    draw(&args, &curves)?;
    FlowCurveRow::write_all(&args.out.join("flow_curves.csv"), &curves.rows)?;
    write_readme(&args, source, &curves, local.as_deref())?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// Refuses to replace the earlier files `names` in `--out` without `--force`.
fn refuse_earlier(args: &Args, names: &[&str]) -> anyhow::Result<()> {
    crate::output_guard::refuse_any_unless_force(
        &names
            .iter()
            .map(|name| args.out.join(name))
            .collect::<Vec<_>>(),
        args.force,
        "an earlier flow-curve result",
        "choose another --out",
    )
}

/// Writes the markdown summary of `curves`, read from `source`, as `--out`/README.md and
/// prints it.
fn write_readme(
    args: &Args,
    source: FlowCurveSource,
    curves: &FlowCurves,
    local: Option<&[LocalBand]>,
) -> anyhow::Result<()> {
    let command = Command {
        grid: &args.grid,
        source,
        local: args.local.as_deref(),
        green_kubo: &args.green_kubo,
        out: &args.out,
    };
    let text = summary_text(&command, &curves.curve, &curves.fits, local);
    write_atomic(&args.out.join("README.md"), text.as_bytes())?;
    print!("{text}");
    Ok(())
}

/// Warns of the `missing` runs of a grid of `total` not in `source`.
fn warn_missing(missing: &[String], total: usize, source: &str) {
    if !missing.is_empty() {
        eprintln!(
            "warning: {} of {total} runs not finished in {source}: {}",
            missing.len(),
            missing.join(", ")
        );
    }
}

/// Draws the figures of `curves` into `--out` (each with its data beside it): `eta_r(phi)`,
/// `mu(J)`, and `eta_r(Pe)` per volume fraction of a Brownian grid; refuses to replace
/// earlier ones without `--force`.
fn draw(args: &Args, curves: &FlowCurves) -> anyhow::Result<()> {
    let phis = volume_fractions(&curves.curve);
    let brownian = curves.curve.iter().any(|p| p.state.peclet.is_finite());
    let mut figures: Vec<PathBuf> = ["eta_r.svg", "mu_J.svg"]
        .iter()
        .map(|f| args.out.join(f))
        .collect();
    if brownian {
        figures.extend(phis.iter().map(|&phi| args.out.join(peclet_figure(phi))));
    }
    crate::output_guard::refuse_any_unless_force(
        &figures,
        args.force,
        "an earlier flow-curve result",
        "choose another --out",
    )?;
    let first_fit = curves
        .fits
        .iter()
        .find_map(|f| f.fits[0].as_ref().ok())
        .map(|f| f.all);
    draw_figures(&args.out, &curves.curve, first_fit.as_ref())?;
    if brownian {
        for &phi in &phis {
            draw_peclet_figure(&args.out.join(peclet_figure(phi)), phi, &curves.curve)?;
        }
    }
    Ok(())
}
