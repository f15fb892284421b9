//! `suspflow train --data FILE.csv --out DIR`: fits the surrogate mappings of docs/physics.md
//! section 8 and saves each as XGBoost JSON plus a sidecar.
//!
//! By default each mapping's hyper-parameters are chosen first, on the training data only:
//! every setting of `surrogate::standard_grid()` is cross-validated leaving one profile
//! family (`profile`) out at a time when the data hold at least three families, else one
//! simulation (`scene_id`), and the lowest mean relative L2 error wins. The search is
//! recorded in `DIR/<mapping>.tuning.json`, next to the error of XGBoost's defaults (the
//! thesis's untuned setting). `--no-tune` trains with those defaults directly.
use anyhow::Context;
use std::path::PathBuf;
use std::time::Instant;
use surrogate::{
    standard_grid, Dataset, HyperParameters, Mapping, ModelMeta, Samples, TableKind, TrainedModel,
    Tuning,
};

use crate::surrogate_text::{describe, errors_by_output, warn_skipped};

#[derive(clap::Args)]
pub struct Args {
    /// Training table: the per-run table of `generate` (one row per bin per run) or its
    /// ensemble table (`<stem>.ensemble.csv`, one row per bin per scene), told apart by the
    /// columns (docs/physics.md section 8).
    #[arg(long)]
    data: PathBuf,
    /// Directory for `<mapping>.json`, `<mapping>.meta.json` and `<mapping>.tuning.json`.
    #[arg(long, default_value = "models")]
    out: PathBuf,
    /// Replace models already in `--out` (the shipped `models/` among them).
    #[arg(long)]
    force: bool,
    /// Mappings to train (mu, theta, dv); all three when absent.
    #[arg(long = "mapping")]
    mappings: Vec<String>,
    /// Skip the cross-validated choice of hyper-parameters and train with XGBoost's defaults.
    #[arg(long)]
    no_tune: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let dataset = Dataset::read_csv(&args.data)?;
    let mappings = Mapping::select(&args.mappings)?;
    let _lock = crate::output_guard::claim_dir(&args.out, "`suspflow train`")?;
    for mapping in &mappings {
        // The trees and their sidecars (surrogate's model and tuning files): any one of
        // them alone is a user's file too.
        let files: Vec<PathBuf> = ["json", "meta.json", "domain.json", "tuning.json"]
            .iter()
            .map(|suffix| args.out.join(format!("{}.{suffix}", mapping.name)))
            .collect();
        crate::output_guard::refuse_any_unless_force(
            &files,
            args.force,
            &format!("a trained `{}` model", mapping.name),
            "give another --out",
        )?;
    }
    // A table without scene ids has no kind; Samples::from_dataset names that problem below.
    if let Ok(kind) = TableKind::of(&dataset) {
        println!(
            "training data {}: {}",
            dataset.source_name(),
            kind.describe()
        );
    }
    let started = Instant::now();
    for mapping in mappings {
        let mut samples = Samples::from_dataset(&dataset, mapping)?;
        warn_skipped(mapping, &samples);
        // The sidecar names the data as the loaders look for it: from the folder holding
        // --out, whatever the directory train ran in (ModelMeta::training_file).
        samples.source_name = ModelMeta::recorded_source(&args.data, &args.out);
        let params = if args.no_tune {
            remove_stale_tuning(&args.out, mapping)?;
            HyperParameters::default()
        } else {
            tune(mapping, &samples, &args.out)?
        };
        let t = Instant::now();
        let model = TrainedModel::fit(mapping, &samples, &params)?;
        let train_s = t.elapsed().as_secs_f64();
        model
            .save(&args.out)
            .with_context(|| format!("saving the {} model", mapping.name))?;
        println!(
            "{}: ({}) -> ({}), {} rows, {}, trained in {:.3} s; training-set relative L2 error {}",
            mapping.name,
            mapping.features.join(", "),
            mapping.outputs.join(", "),
            samples.n_rows(),
            describe(&params),
            train_s,
            errors_by_output(mapping.outputs, &model.evaluate(&samples)?)
        );
    }
    println!(
        "models in {} ({:.3} s in all)",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Chooses `mapping`'s hyper-parameters by cross-validation, saves and summarises the record.
fn tune(
    mapping: &Mapping,
    samples: &Samples,
    out: &std::path::Path,
) -> anyhow::Result<HyperParameters> {
    let tuning = Tuning::run(mapping, samples, &standard_grid())?;
    if let Some(why) = &tuning.backbone_excluded {
        eprintln!(
            "warning: {}: settings with the physics backbone left out of the search: {why}",
            mapping.name
        );
    }
    tuning
        .save(out)
        .with_context(|| format!("saving the {} tuning record", mapping.name))?;
    println!(
        "{}: {} settings cross-validated over {} {} (leave one out) in {:.1} s; chosen {}: {}; \
         XGBoost defaults ({}): {}",
        mapping.name,
        tuning.scores.len(),
        tuning.folds,
        tuning.left_out.plural(),
        tuning.seconds,
        describe(&tuning.chosen.params),
        errors_by_output(mapping.outputs, &tuning.chosen.per_output),
        describe(&tuning.untuned.params),
        errors_by_output(mapping.outputs, &tuning.untuned.per_output)
    );
    Ok(tuning.chosen.params)
}

/// Removes `<out>/<mapping>.tuning.json` left by an earlier tuned run: it would describe a
/// choice the new model does not use.
fn remove_stale_tuning(out: &std::path::Path, mapping: &Mapping) -> anyhow::Result<()> {
    let path = Tuning::path(out, mapping.name);
    match std::fs::remove_file(&path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("removing the stale {}", path.display()))
        }
        _ => Ok(()),
    }
}
