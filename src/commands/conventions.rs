//! `suspflow conventions DIR...`: the effect of each observable convention (docs/physics.md
//! section 6) on mu, phi_loc, Theta, Delta_v and J, measured on the snapshot sums of
//! finished runs (the `--out` directory of `simulate`, or the scene folders of a `generate`
//! work directory), so that every convention sees the same snapshots. Prints, as Markdown,
//! per option the median and the largest relative difference from the default over all bins
//! of all runs, then per run the independent stress checks.
use anyhow::Context;
use sim::input::scene::Scene;
use sim::output::result_files::{SnapshotSums, SNAPSHOT_SUMS};
use sim::sampling::bin_averages::{BinAverages, BinningContext};
use sim::sampling::convention_effects::{convention_effects, COMPARED};
use sim::sampling::stress_checks::stress_checks;
use std::fmt::Write as _;
use std::path::PathBuf;
use surrogate::median;

#[derive(clap::Args)]
pub struct Args {
    /// Result directories, each holding the `snapshot_sums.json` of a finished run. Of
    /// several (`WORK/*` of a generate work directory), files and folders without that file
    /// (`generate.lock`, a failed run) are skipped with a note; one alone must be a run.
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
}

/// The run folders among `paths`: all of them when there is one (the reader then names what
/// is wrong with it); of several, those holding snapshot sums, the others (files such as
/// `generate.lock`, folders of failed or unfinished runs) skipped with a note. A path that
/// does not exist is an error either way, and so is a list without any run.
fn run_folders(paths: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    if let Some(missing) = paths.iter().find(|p| !p.exists()) {
        anyhow::bail!("{} does not exist", missing.display());
    }
    if let [one] = paths {
        if !one.is_dir() {
            anyhow::bail!(
                "{} is a file, not a run folder (the --out of `suspflow simulate`, or a scene \
                 folder of a `suspflow generate` work directory)",
                one.display()
            );
        }
        return Ok(vec![one.clone()]);
    }
    let (runs, others): (Vec<&PathBuf>, Vec<&PathBuf>) = paths
        .iter()
        .partition(|p| p.is_dir() && p.join(SNAPSHOT_SUMS).is_file());
    for other in &others {
        let what = if other.is_dir() {
            format!("a folder without {SNAPSHOT_SUMS} (a failed or unfinished run?)")
        } else {
            "a file, not a run folder".to_owned()
        };
        eprintln!("note: skipping {}: {what}", other.display());
    }
    if runs.is_empty() {
        anyhow::bail!(
            "none of the {} paths is a finished run (a folder holding {SNAPSHOT_SUMS})",
            paths.len()
        );
    }
    Ok(runs.into_iter().cloned().collect())
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut pooled: Vec<(String, [Vec<f64>; 5])> = Vec::new();
    let mut checks = String::from(
        "| run | bins | sigma_yy chi2 | max abs z of sigma_yy | balance residual, bin stress | balance residual, face forces |\n\
         |---|---|---|---|---|---|\n",
    );
    let dirs = run_folders(&args.dirs)?;
    for dir in &dirs {
        let path = dir.join(SNAPSHOT_SUMS);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "reading {} (is {} a finished run?)",
                path.display(),
                dir.display()
            )
        })?;
        let sums: SnapshotSums = serde_json::from_str(&text)
            .with_context(|| format!("{} is not a snapshot-sums file", path.display()))?;
        let name = sums.scene.name.clone();
        let scene = Scene::from_file(sums.scene, false)
            .with_context(|| format!("the scene of {}", dir.display()))?;
        if !sums.sums.fits(scene.n_bins) {
            anyhow::bail!(
                "{} holds snapshot sums of another layout (an older suspflow, or another bin \
                 count): run the scene again to get sums this version reads",
                path.display()
            );
        }
        let ctx = BinningContext::for_scene(&scene);
        for effect in convention_effects(&ctx, &sums.sums)? {
            match pooled.iter_mut().find(|(o, _)| *o == effect.option) {
                Some((_, all)) => all
                    .iter_mut()
                    .zip(effect.relative)
                    .for_each(|(a, r)| a.extend(r)),
                None => pooled.push((effect.option, effect.relative)),
            }
        }
        let c = stress_checks(&ctx, &sums.sums);
        let face = BinAverages::from_blocks(&ctx, &sums.sums)?.momentum_residual;
        let _ = writeln!(
            checks,
            "| {name} | {} | {:.2} | {:.2} | {} | {} |",
            scene.n_bins,
            c.sigma_yy_chi2,
            c.sigma_yy_max_z,
            c.balance_residual
                .map_or("n/a".into(), |r| format!("{r:.4}")),
            face.map_or("n/a".into(), |r| format!("{r:.4}"))
        );
    }
    let mut table = format!(
        "Relative difference from the default, median / max over {} runs' bins:\n\n| option |",
        dirs.len()
    );
    for name in COMPARED {
        let _ = write!(table, " {name} |");
    }
    table.push_str("\n|---|");
    table.push_str(&"---|".repeat(COMPARED.len()));
    table.push('\n');
    for (option, relative) in &pooled {
        let _ = write!(table, "| `{option}` |");
        for r in relative {
            let cell = if r.is_empty() {
                "n/a".to_string()
            } else if r.iter().all(|&x| x == 0.0) {
                "0".to_string()
            } else {
                let max = r.iter().fold(0.0f64, |m, &x| m.max(x));
                format!(
                    "{} / {}",
                    significant_percent(median(r.clone())),
                    significant_percent(max)
                )
            };
            let _ = write!(table, " {cell} |");
        }
        table.push('\n');
    }
    println!("{table}\n{checks}");
    Ok(())
}

/// A relative difference as a percentage with two significant digits.
fn significant_percent(x: f64) -> String {
    let p = 100.0 * x;
    if p >= 10.0 {
        format!("{p:.0} %")
    } else if p >= 1.0 {
        format!("{p:.1} %")
    } else {
        format!("{p:.2} %")
    }
}
