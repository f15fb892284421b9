//! `suspflow report`: writes `reports/<name>/report.md` with its tables and figures.
//! Built so far: section 4, stability on stiff and extreme cases (issue 5); the other
//! sections (error against run time, surrogate cost, side by side, Theta vs Delta_v) are
//! still to come and are listed as such in the report.
use crate::stability_sweep::{self, SweepSize};
use anyhow::Context;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Report name: writes `<out>/<name>/report.md` and its figures.
    #[arg(long, default_value = "quick")]
    name: String,
    /// Parent directory of the reports.
    #[arg(long, default_value = "reports")]
    out: PathBuf,
    /// Full mode: longer runs in larger boxes (the README's numbers); default is quick.
    #[arg(long)]
    full: bool,
    /// Sweep only these parameters (k_n, xi_min, phi, amplitude, size_ratio).
    #[arg(long)]
    only: Vec<String>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let dir = args.out.join(&args.name);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let size = if args.full {
        SweepSize { window_strain: 0.25, snapshots: 100, box_edge: 10.0 }
    } else {
        SweepSize { window_strain: 0.05, snapshots: 20, box_edge: 8.0 }
    };
    if let Some(bad) = args.only.iter().find(|o| !stability_sweep::PARAMETERS.iter().any(|(p, _)| p == o)) {
        anyhow::bail!("--only {bad}: not a swept parameter (k_n, xi_min, phi, amplitude, size_ratio)");
    }
    let started = Instant::now();
    eprintln!("stability sweep: {} cases ...", stability_sweep::cases(&args.only).len());
    let results = stability_sweep::sweep(size, &args.only);
    let sweep_s = started.elapsed().as_secs_f64();
    crate::stability_map::draw(&dir.join("stability_map.svg"), &results)?;

    let mut md = String::new();
    let _ = writeln!(md, "# suspflow report `{}` ({} mode)\n", args.name, if args.full { "full" } else { "quick" });
    let _ = writeln!(md, "Command: `suspflow report --name {}{}`; code version {}.\n", args.name,
        if args.full { " --full" } else { "" }, sim::CODE_VERSION);
    let _ = writeln!(md, "Sections 1-3 and 5 (simulation and surrogate error against run time, side by side, \
        Theta vs Delta_v) are not built yet.\n");
    let _ = writeln!(md, "## 4. Stability on stiff and extreme cases\n");
    let _ = writeln!(md, "Base scene: phi 0.5, `0.15*sin(2*pi*y/L)`, radii 1 : 1.4, k_n 1e4, xi_min 1e-3, box {e} x {ly} x {e} \
        (larger for large spheres); one parameter changed at a time; each case runs 4 windows of {w} strain and {s} snapshots \
        0.01 strain apart. dt factor = multiple of the automatic step. {} cases in {sweep_s:.0} s.\n",
        results.len(), e = size.box_edge, ly = size.box_edge * 1.5, w = size.window_strain, s = size.snapshots);
    let _ = writeln!(md, "![stability map](stability_map.svg)\n");
    let _ = writeln!(md, "| parameter | value | dt factor | outcome | dt | limit | max overlap / a_min | momentum residual | message names the cause |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    for r in &results {
        let named = match r.status { "stable" | "inaccurate" => "", _ if r.cause_named => "yes", _ => "no" };
        let _ = writeln!(md, "| {} | {} | {} | {} | {:.3e} | {} | {:.2e} | {:.4} | {} |", r.case.parameter, r.case.value,
            r.case.dt_factor, r.status, r.dt, r.dt_limit, r.max_overlap, r.momentum_residual, named);
    }
    let auto_failures: Vec<&stability_sweep::CaseResult> =
        results.iter().filter(|r| r.case.dt_factor <= 1.0 && r.status != "stable").collect();
    let silent = results.iter()
        .filter(|r| matches!(r.status, "stable" | "inaccurate") && !(r.momentum_residual.is_finite() && r.max_overlap.is_finite()))
        .count();
    let inaccurate = results.iter().filter(|r| r.status == "inaccurate").count();
    let _ = writeln!(md, "\nAt the automatic dt and half of it: {} of {} cases unstable. Above it: {} of {} failed, {} of the failures \
        with a message naming step, particle and cause. Finished with a momentum residual above {}: {inaccurate}. \
        Finished runs with a non-finite result: {silent}.\n",
        auto_failures.len(), results.iter().filter(|r| r.case.dt_factor <= 1.0).count(),
        results.iter().filter(|r| r.case.dt_factor > 1.0 && !matches!(r.status, "stable" | "inaccurate")).count(),
        results.iter().filter(|r| r.case.dt_factor > 1.0).count(),
        results.iter().filter(|r| r.status != "stable" && r.cause_named).count(), stability_sweep::INACCURATE_RESIDUAL);
    for r in results.iter().filter(|r| !matches!(r.status, "stable" | "inaccurate")) {
        let _ = writeln!(md, "- {} = {}, dt x {}: {}", r.case.parameter, r.case.value, r.case.dt_factor, r.message);
    }
    let path = dir.join("report.md");
    sim::checkpoint::write_atomic(&path, md.as_bytes())?;
    println!("{}", path.display());
    Ok(())
}
