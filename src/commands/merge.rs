//! `suspflow merge PART.csv ... --out ALL.csv`: combines datasets written by `generate
//! --shard` (or any datasets of distinct runs) into one, runs in (scene id, seed) order.
//! When a scene has several replicas (seeds), the ensemble table and its summary go beside
//! the output (`<stem>.ensemble.csv`, `<stem>.ensemble.json`, see `crate::ensemble_table`),
//! replaced as the output is.
use crate::ensemble_table;
use anyhow::bail;
use rheometry::sweep_tables::{build_ensemble_of, ensemble_paths, write_ensemble_beside};
use schema::RunTable;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Dataset files to combine (same header, no run (scene and seed) in two files).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The combined dataset.
    #[arg(long)]
    out: PathBuf,
    /// Replace an existing `--out` (and the ensemble table beside it).
    #[arg(long)]
    force: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.parts.iter().any(|p| p == &args.out) {
        bail!(
            "--out {} is also an input; write the merge to a new file",
            args.out.display()
        );
    }
    let [table, json] = ensemble_paths(&args.out);
    crate::output_guard::refuse_any_unless_force(
        &[args.out.clone(), table, json],
        args.force,
        "an earlier dataset or its ensemble table",
        "choose another --out",
    )?;
    let mut merged: Option<RunTable> = None;
    for path in &args.parts {
        let part = RunTable::read(path)?;
        match merged.as_mut() {
            None => merged = Some(part),
            Some(m) => m.absorb(part, &path.display().to_string())?,
        }
    }
    let merged = merged.expect("clap requires at least one part");
    let text = merged.to_text();
    // Everything is checked before anything is written: a failed merge leaves no output.
    let ensemble = merged
        .has_replicas()
        .then(|| build_ensemble_of(&args.out, &merged))
        .transpose()?;
    schema::write_atomic(&args.out, text.as_bytes())?;
    println!(
        "{}: {} rows from {} runs of {} scenes in {} files",
        args.out.display(),
        merged.rows(),
        merged.runs.len(),
        merged.scene_count(),
        args.parts.len()
    );
    if let Some(ensemble) = ensemble {
        let summary = write_ensemble_beside(&args.out, ensemble)?;
        let [table, json] = ensemble_paths(&args.out);
        println!(
            "ensemble: {} (summary {})\n{}",
            table.display(),
            json.display(),
            ensemble_table::describe(&summary)
        );
    }
    Ok(())
}
