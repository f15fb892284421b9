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
//! into `<out>/bands.json`. The work is `solver::TrainingJob`'s; this command parses,
//! calls and prints.
use solver::{BandsOutcome, ParamsSource, SolverError, TrainingEvent, TrainingJob, TrainingResult};
use std::path::PathBuf;
use surrogate::{Dataset, Mapping, TableKind, MIN_TUNING_FAMILIES};

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
    let params = match (&args.params_from, args.no_tune) {
        (Some(dir), _) => ParamsSource::From(dir.clone()),
        (None, true) => ParamsSource::Defaults,
        (None, false) => ParamsSource::Tune,
    };
    let job = TrainingJob {
        data: &dataset,
        data_file: Some(&args.data),
        out: &args.out,
        mappings,
        params,
        bands: !args.no_bands,
        force: args.force,
        code_version: crate::CODE_VERSION,
        interrupt: None,
    };
    let result = job.run(&print_event).map_err(|e| match e {
        SolverError::WouldReplace { path, what } => {
            crate::output_guard::refusal(&path, &what, "give another --out")
        }
        e => e.into(),
    })?;
    print_bands(&result);
    println!(
        "models in {} ({:.3} s in all)",
        args.out.display(),
        result.seconds
    );
    Ok(())
}

/// The training's progress: a line per step on standard output, warnings on standard error.
fn print_event(event: TrainingEvent) {
    match event {
        TrainingEvent::Started { data } => {
            // A table without scene ids has no kind; the samples of the first mapping name
            // that problem.
            if let Ok(kind) = TableKind::of(data) {
                println!("training data {}: {}", data.source_name(), kind.describe());
            }
        }
        TrainingEvent::Samples { mapping, samples } => warn_skipped(mapping, samples),
        TrainingEvent::Tuned { mapping, tuning } => {
            if let Some(why) = &tuning.backbone_excluded {
                eprintln!(
                    "warning: {}: settings with the physics backbone left out of the search: {why}",
                    mapping.name
                );
            }
            println!(
                "{}: {} settings cross-validated over {} {} (leave one out) in {:.1} s; chosen {}: {}; \
                 XGBoost defaults ({}): {}",
                mapping.name,
                tuning.settings,
                tuning.folds,
                tuning.left_out,
                tuning.seconds,
                describe(&tuning.chosen.params),
                errors_by_output(mapping.outputs, &tuning.chosen.per_output),
                describe(&tuning.defaults.params),
                errors_by_output(mapping.outputs, &tuning.defaults.per_output)
            );
        }
        TrainingEvent::Noiseless { mapping } => println!(
            "{}: the table gives no standard error of every output: intervals \
             calibrated as if its targets were noiseless",
            mapping.name
        ),
        TrainingEvent::Intervals { mapping, intervals } => println!(
            "{}: {:.0} % intervals calibrated on {} folds (one of the {} left out each) in {:.1} s: \
             held-out rows covered {}; mean width {}",
            mapping.name,
            100.0 * intervals.level,
            intervals.folds,
            intervals.held_out,
            intervals.seconds,
            errors_by_output(mapping.outputs, &intervals.fold_coverage),
            widths_by_output(mapping.outputs, &intervals.fold_mean_width)
        ),
        TrainingEvent::WithoutIntervals { mapping, why } => eprintln!(
            "warning: {}: saved without intervals, which need held-out rows to calibrate \
             on: {why}",
            mapping.name
        ),
        TrainingEvent::Trained { mapping, trained } => println!(
            "{}: ({}) -> ({}), {} rows, {}, trained in {:.3} s; training-set relative L2 error {}",
            mapping.name,
            mapping.features.join(", "),
            mapping.outputs.join(", "),
            trained.rows,
            describe(&trained.params),
            trained.fit_seconds,
            errors_by_output(mapping.outputs, &trained.training_error)
        ),
        TrainingEvent::BandsFold { done, family } => {
            eprintln!("  bands: [{done}] solved the scenes of `{family}` with its fold's models")
        }
    }
}

/// What became of the bands of `solve`: their calibration, or why there is none.
fn print_bands(result: &TrainingResult) {
    match &result.bands {
        BandsOutcome::Skipped | BandsOutcome::NotTrained { kept: None } => {}
        BandsOutcome::NotTrained { kept: Some(path) } => eprintln!(
            "warning: {} was left as it was: the bands of `solve` are calibrated when \
             `dv` and `theta` are trained together (with `ext` for its closure)",
            path.display()
        ),
        BandsOutcome::TooFewFamilies { mapping, held_out } => eprintln!(
            "note: no bands for solve: they are calibrated leaving one profile family out, and \
             `{mapping}`'s folds left out {held_out} (fewer than {MIN_TUNING_FAMILIES} families)"
        ),
        BandsOutcome::Calibrated(bands) => {
            println!(
                "bands of solve calibrated on {} folds (one of the {} left out each) in {:.1} s:",
                bands.folds, bands.held_out, bands.seconds
            );
            for c in &bands.closures {
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
        }
    }
}
