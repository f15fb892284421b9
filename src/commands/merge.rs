//! `suspflow merge PART.csv ... --out ALL.csv`: combines datasets written by `generate
//! --shard` (or any datasets of distinct scenes) into one, scenes in id (grid) order.
use crate::dataset_file::DatasetFile;
use anyhow::bail;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Dataset files to combine (same header, no scene in two files).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The combined dataset.
    #[arg(long)]
    out: PathBuf,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.parts.iter().any(|p| p == &args.out) {
        bail!(
            "--out {} is also an input; write the merge to a new file",
            args.out.display()
        );
    }
    let mut merged: Option<DatasetFile> = None;
    for path in &args.parts {
        let part = DatasetFile::read(path)?;
        match merged.as_mut() {
            None => merged = Some(part),
            Some(m) => m.absorb(part, &path.display().to_string())?,
        }
    }
    let merged = merged.expect("clap requires at least one part");
    sim::output::atomic_write::write_atomic(&args.out, merged.to_text().as_bytes())?;
    println!(
        "{}: {} rows from {} scenes in {} files",
        args.out.display(),
        merged.rows(),
        merged.scenes.len(),
        args.parts.len()
    );
    Ok(())
}
