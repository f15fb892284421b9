//! `suspflow propose CANDIDATES.toml --models DIR --top N --out GRID.toml`: which of the
//! candidate scenes of a grid to simulate next. Each candidate is solved from its forcing
//! with `--closure` and banded at `--level` with the models' calibration (`bands.json`); the
//! candidates are ranked by the mean relative width of their u, phi_loc and mu bands, widest
//! first (a candidate the closure does not solve first of all). A batch of `--top` is
//! picked to cover the widest bands of all candidates (`solver::Proposal::batch`: a
//! candidate whose states the picked ones already cover adds little) and written as a grid
//! `generate` runs. The ranking is printed, the batch marked.
use anyhow::Context;
use sim::Grid;
use solver::{proposal::describe, ClosureKind, Closures, Proposal};
use std::path::PathBuf;

/// `--closure NAME`: one of the solver's closures.
fn parse_closure(name: &str) -> Result<ClosureKind, String> {
    ClosureKind::from_name(name).map_err(|e| e.to_string())
}

#[derive(clap::Args)]
pub struct Args {
    /// Grid file (TOML) of the candidate scenes (`generate`'s format); replicas of one scene
    /// are one candidate.
    candidates: PathBuf,
    /// Directory of the trained models, with their bands' calibration (`bands.json`).
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Training table of the local law and the Theta balance; by default the file the `dv`
    /// model's sidecar names.
    #[arg(long)]
    train: Option<PathBuf>,
    /// The closure whose bands rank the candidates (learned, local, nonlocal, extremum).
    #[arg(long, default_value = "learned", value_parser = parse_closure)]
    closure: ClosureKind,
    /// Level of the bands (a probability in (0, 1)).
    #[arg(long, default_value_t = surrogate::DEFAULT_LEVEL)]
    level: f64,
    /// How many candidates the proposed grid holds.
    #[arg(long, default_value_t = 4)]
    top: usize,
    /// The proposed grid (TOML).
    #[arg(long)]
    out: PathBuf,
    /// Name of the proposed grid (its scenes are `<name>_<k>`).
    #[arg(long, default_value = "proposed")]
    name: String,
    /// Replace an existing `--out`.
    #[arg(long)]
    force: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.top >= 1,
        "--top {}: propose at least one scene",
        args.top
    );
    crate::output_guard::refuse_unless_force(
        &args.out,
        args.force,
        "an earlier proposal",
        "choose another --out",
    )?;
    surrogate::check_level(args.level)?;
    let grid = Grid::from_path(&args.candidates, false)?;
    let closures = Closures::load(&args.models, args.train.as_deref()).with_context(|| {
        format!(
            "loading the closures from {} and their training data",
            args.models.display()
        )
    })?;
    let proposal = Proposal::rank(&closures, args.closure, &grid, args.level)
        .with_context(|| format!("ranking the candidates of {}", args.candidates.display()))?;
    println!(
        "{} candidates of {}, ranked by the {:.0} % bands of the {} closure (mean relative \
         width of u, phi_loc and mu), widest first:",
        proposal.candidates.len(),
        args.candidates.display(),
        100.0 * args.level,
        args.closure.name()
    );
    let batch = proposal.batch(args.top);
    for (k, c) in proposal.candidates.iter().enumerate() {
        println!(
            "{:>4} {}{} {} (L_y {}, phi {}): {}",
            k + 1,
            if batch.contains(&k) { "*" } else { " " },
            c.id,
            c.profile,
            c.l_y,
            c.phi,
            describe(&c.outcome)
        );
    }
    let text = proposal.grid_toml(&args.name, &batch)?;
    // The proposal must be a grid `generate` runs: read it back before writing.
    Grid::from_toml(&text, false).context("the proposed grid does not read back")?;
    std::fs::write(&args.out, text).with_context(|| format!("writing {}", args.out.display()))?;
    let order: Vec<&str> = batch
        .iter()
        .map(|&k| proposal.candidates[k].id.as_str())
        .collect();
    println!(
        "proposed grid ({} scenes, marked *; picked to cover the widest bands of all \
         candidates, in the order {}): {}",
        batch.len(),
        order.join(", "),
        args.out.display()
    );
    Ok(())
}
