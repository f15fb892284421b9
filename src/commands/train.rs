//! `suspflow train --data FILE.csv --out DIR`: fits the surrogate mappings of docs/physics.md
//! section 8 and saves each as XGBoost JSON plus a sidecar.
//!
//! By default each mapping's hyper-parameters are chosen first, on the training data only:
//! every setting of `surrogate::standard_grid()` is cross-validated leaving one profile
//! family (`profile`) out at a time when the data hold at least three families, else one
//! simulation (`scene_id`), and the lowest mean relative L2 error wins. The search is
//! recorded in `DIR/<mapping>.tuning.json`, next to the error of XGBoost's defaults (the
//! thesis's untuned setting). `--no-tune` trains with those defaults directly.
//!
//! Each model is saved with its intervals (`surrogate::IntervalStudy`: quantile trees and the
//! conformal scores of the rows predicted by folds that held them out). When the `dv` and
//! `theta` mappings are trained together, the bands of `solve` are calibrated too
//! (`solver::calibrate_bands`: every family's scenes solved with the models of its fold),
//! into `<out>/bands.json`.
use anyhow::Context;
use ndarray::Array2;
use solver::{calibrate_bands, BandCalibration, ShippedModel};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use surrogate::{
    output_standard_errors, standard_grid, Dataset, HyperParameters, IntervalCalibration,
    IntervalStudy, LeftOut, Mapping, ModelMeta, Samples, TableKind, TrainedModel, Tuning,
    DEFAULT_LEVEL, MIN_TUNING_FAMILIES,
};

use crate::surrogate_text::{describe, errors_by_output, percent, warn_skipped, widths_by_output};

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
    /// Mappings to train (mu, theta, dv, ext); all four when absent.
    #[arg(long = "mapping")]
    mappings: Vec<String>,
    /// Skip the cross-validated choice of hyper-parameters and train with XGBoost's defaults.
    #[arg(long, conflicts_with = "params_from")]
    no_tune: bool,
    /// Skip the choice too, and train each mapping with the hyper-parameters of its model in
    /// this directory (e.g. the shipped `models`, to retrain them on more data).
    #[arg(long)]
    params_from: Option<PathBuf>,
    /// Skip the calibration of solve's bands (`bands.json`, a minute of solves) even when
    /// `dv` and `theta` are trained.
    #[arg(long)]
    no_bands: bool,
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
            .chain([IntervalCalibration::path(&args.out, mapping.name)])
            .chain(
                mapping
                    .outputs
                    .iter()
                    .map(|o| IntervalCalibration::trees_path(&args.out, mapping.name, o)),
            )
            .collect();
        crate::output_guard::refuse_any_unless_force(
            &files,
            args.force,
            &format!("a trained `{}` model", mapping.name),
            "give another --out",
        )?;
    }
    let names: Vec<&str> = mappings.iter().map(|m| m.name).collect();
    if names.contains(&"dv") && names.contains(&"theta") && !args.no_bands {
        crate::output_guard::refuse_unless_force(
            &BandCalibration::path(&args.out),
            args.force,
            "the calibration of solve's bands",
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
    let mut studies = Vec::new();
    for mapping in mappings {
        let mut samples = Samples::from_dataset(&dataset, mapping)?;
        warn_skipped(mapping, &samples);
        // The sidecar names the data as the loaders look for it: from the folder holding
        // --out, whatever the directory train ran in (ModelMeta::training_file).
        samples.source_name = ModelMeta::recorded_source(&args.data, &args.out);
        let params = if args.no_tune {
            Tuning::remove_stale(&args.out, mapping.name)?;
            HyperParameters::default()
        } else if let Some(dir) = &args.params_from {
            Tuning::remove_stale(&args.out, mapping.name)?;
            ModelMeta::load_params(dir, mapping.name)
                .with_context(|| format!("--params-from {}", dir.display()))?
        } else {
            tune(mapping, &samples, &args.out)?
        };
        let t = Instant::now();
        let model = TrainedModel::fit(mapping, &samples, &params)?;
        let train_s = t.elapsed().as_secs_f64();
        // The targets' standard errors keep the model's error apart from their noise.
        let noise = output_standard_errors(&dataset, &samples)?;
        if noise.is_none() {
            println!(
                "{}: the table gives no standard error of every output: intervals \
                 calibrated as if its targets were noiseless",
                mapping.name
            );
        }
        let (model, study) = with_intervals(mapping, model, &samples, noise.as_ref(), &params)?;
        studies.extend(study.map(|s| (mapping, params.clone(), s)));
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
    if !args.no_bands {
        bands(&dataset, &studies, &args.out)?;
    }
    println!(
        "models in {} ({:.3} s in all)",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Calibrates the bands of `solve` on the training scenes (`solver::calibrate_bands`) and
/// writes `<out>/bands.json`, when this run trained the `dv` and `theta` mappings with
/// intervals; otherwise says why not.
fn bands(
    dataset: &Dataset,
    studies: &[(&'static Mapping, HyperParameters, IntervalStudy)],
    out: &Path,
) -> anyhow::Result<()> {
    let trained = |name: &str| studies.iter().any(|(m, _, _)| m.name == name);
    if !(trained("dv") && trained("theta")) {
        if BandCalibration::path(out).exists() {
            eprintln!(
                "warning: {} was left as it was: the bands of `solve` are calibrated when \
                 `dv` and `theta` are trained together (with `ext` for its closure)",
                BandCalibration::path(out).display()
            );
        }
        return Ok(());
    }
    if let Some((mapping, _, study)) = studies
        .iter()
        .find(|(_, _, s)| s.calibration.held_out != LeftOut::Family.plural())
    {
        eprintln!(
            "note: no bands for solve: they are calibrated leaving one profile family out, and \
             `{}`'s folds left out {} (fewer than {MIN_TUNING_FAMILIES} families)",
            mapping.name, study.calibration.held_out
        );
        return Ok(());
    }
    let t = Instant::now();
    let models: Vec<ShippedModel> = studies
        .iter()
        .map(|(mapping, params, study)| ShippedModel {
            mapping,
            params,
            study,
        })
        .collect();
    let families = AtomicUsize::new(0);
    let calibration = calibrate_bands(dataset, &models, crate::CODE_VERSION, &|family| {
        let k = families.fetch_add(1, Ordering::Relaxed) + 1;
        eprintln!("  bands: [{k}] solved the scenes of `{family}` with its fold's models");
    })
    .context("calibrating the bands of solve")?;
    calibration.save(out)?;
    println!(
        "bands of solve calibrated on {} folds (one of the {} left out each) in {:.1} s:",
        calibration.folds,
        calibration.held_out,
        t.elapsed().as_secs_f64()
    );
    for c in &calibration.closures {
        println!(
            "  {:<8} {} scenes ({} stalled), held-out bins covered at 90 %: u {}, phi_loc {}, \
             mu {}",
            c.closure,
            c.scenes,
            c.failed,
            percent(c.fold_coverage[0]),
            percent(c.fold_coverage[1]),
            percent(c.fold_coverage[2])
        );
    }
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

/// `model` with its intervals calibrated on the folds of `samples` (those of tuning), and
/// the study that calibrated them; or the model as it is, with a warning, when the data
/// hold too few simulations to leave one out.
fn with_intervals(
    mapping: &Mapping,
    model: TrainedModel,
    samples: &Samples,
    noise: Option<&Array2<f64>>,
    params: &HyperParameters,
) -> anyhow::Result<(TrainedModel, Option<IntervalStudy>)> {
    let t = Instant::now();
    let noise = noise.map(Array2::view);
    let study = match IntervalStudy::run(mapping, samples, noise, params, DEFAULT_LEVEL) {
        Ok(study) => study,
        Err(e) => {
            eprintln!(
                "warning: {}: saved without intervals, which need held-out rows to calibrate \
                 on: {e}",
                mapping.name
            );
            return Ok((model, None));
        }
    };
    let c = &study.calibration;
    println!(
        "{}: {:.0} % intervals calibrated on {} folds (one of the {} left out each) in {:.1} s: \
         held-out rows covered {}; mean width {}",
        mapping.name,
        100.0 * DEFAULT_LEVEL,
        c.folds,
        c.held_out,
        t.elapsed().as_secs_f64(),
        errors_by_output(mapping.outputs, &c.fold_coverage),
        widths_by_output(mapping.outputs, &c.fold_mean_width)
    );
    let trees = model.fit_quantile_trees(samples, params)?;
    let model = model.with_intervals(trees, study.calibration.clone())?;
    Ok((model, Some(study)))
}
