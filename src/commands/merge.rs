//! `suspflow merge PART.csv ... --out ALL.csv`: combines datasets written by `generate
//! --shard` (or any datasets of distinct runs) into one, runs in (scene id, seed) order.
//! When a scene has several replicas (seeds), the ensemble table and its summary go beside
//! the output (`<stem>.ensemble.csv`, `<stem>.ensemble.json`, see `crate::ensemble_table`),
//! replaced as the output is. When every part has its run table beside it (`generate`'s
//! `<stem>.scenes.csv`), their rows go into the output's (status, step, wall time and code
//! version of every run), in the same order. A table beside a replaced output that this
//! merge does not write again (no run table in some part, no replicas) is removed: it
//! described the dataset replaced.
use crate::ensemble_table;
use anyhow::bail;
use rheometry::sweep_tables::{
    build_ensemble_of, ensemble_paths, write_ensemble_beside, SweepTables,
};
use schema::RunTable;
use sim::run::batch::RunTableRow;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// Dataset files to combine (same header, no run (scene and seed) in two files).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The combined dataset.
    #[arg(long)]
    out: PathBuf,
    /// Replace an existing `--out` (and the run and ensemble tables beside it).
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
    let run_table = SweepTables::beside(&args.out, false).run_table;
    crate::output_guard::refuse_any_unless_force(
        &[
            args.out.clone(),
            run_table.clone(),
            table.clone(),
            json.clone(),
        ],
        args.force,
        "an earlier dataset or its run or ensemble table",
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
    let run_rows = merged_run_tables(&args.parts)?;
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
    match run_rows {
        Some(rows) => {
            schema::write_atomic(&run_table, &RunTableRow::to_csv(&rows)?)?;
            println!("runs: {} ({} runs)", run_table.display(), rows.len());
        }
        None => remove_stale(&run_table)?,
    }
    match ensemble {
        Some(ensemble) => {
            let summary = write_ensemble_beside(&args.out, ensemble)?;
            println!(
                "ensemble: {} (summary {})\n{}",
                table.display(),
                json.display(),
                ensemble_table::describe(&summary)
            );
        }
        None => [table, json].iter().try_for_each(|t| remove_stale(t))?,
    }
    Ok(())
}

/// Removes `table`, left beside the output by the dataset `--force` replaced, if there.
fn remove_stale(table: &Path) -> anyhow::Result<()> {
    if table.exists() {
        std::fs::remove_file(table)?;
        println!(
            "removed {}: it described the dataset replaced",
            table.display()
        );
    }
    Ok(())
}

/// The run tables beside `parts` as one, when every part has one; `None` (with a note of the
/// parts without) when some have none, as for datasets not written by `generate`.
fn merged_run_tables(parts: &[PathBuf]) -> anyhow::Result<Option<Vec<RunTableRow>>> {
    let tables: Vec<PathBuf> = parts
        .iter()
        .map(|p| SweepTables::beside(p, false).run_table)
        .collect();
    let absent: Vec<String> = tables
        .iter()
        .filter(|t| !t.exists())
        .map(|t| t.display().to_string())
        .collect();
    if !absent.is_empty() {
        eprintln!(
            "note: no run table written: {} not there",
            absent.join(", ")
        );
        return Ok(None);
    }
    let read = tables
        .iter()
        .map(|t| Ok((t.display().to_string(), RunTableRow::read_all(t)?)))
        .collect::<anyhow::Result<Vec<_>>>()?;
    Ok(Some(RunTableRow::merge(read)?))
}
