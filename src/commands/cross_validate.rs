//! `suspflow cross-validate --data TABLE --out DIR`: leave-one-family-out cross-validation of
//! XGBoost alone, the physics backbone alone and backbone + XGBoost (`surrogate::FamilyCv`).
//!
//! A profile family is every row of one forcing expression (the `profile` column: shape and
//! amplitude) at every phi, L_y and seed. Each fold trains the three variants and the
//! training domain on the other families and measures, per mapping and output, the relative
//! L2 error of eq 6.6 on the held-out family's rows: all of them, those inside the training
//! domain and those outside, with their counts. The trees' settings are those of the models
//! in `--models` (`<mapping>.meta.json`), so train first. With `--learning-curve`, it also
//! measures the error against the number of families trained on (`surrogate::LearningCurve`).
//! Beside every error, the part beyond the held-out targets' own noise; then the mappings
//! side by side family by family, and the coverage of their intervals on the same folds
//! (`surrogate::IntervalStudy`: three ways of making them, and the shipped one per family).
//! Writes `DIR/report.md` (tables) and `DIR/cv.json` (every figure); progress goes to
//! standard error.
use anyhow::Context;
use std::path::PathBuf;
use surrogate::{
    CurveCost, CvProgress, CvSettings, Dataset, FamilyCvStudy, HyperParameters, Mapping, Samples,
    TrainedModel,
};

use crate::report::cross_validation::markdown;
use crate::surrogate_text::{describe, warn_skipped};

#[derive(clap::Args)]
pub struct Args {
    /// Table with a `profile` column naming each row's forcing: the per-run table of
    /// `generate` or its ensemble table (`<stem>.ensemble.csv`); at least two families.
    #[arg(long)]
    data: PathBuf,
    /// Mappings to cross-validate (mu, theta, dv, ext); all four when absent.
    #[arg(long = "mapping")]
    mappings: Vec<String>,
    /// Directory of trained models whose hyper-parameters the trees use (`suspflow train --out`).
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Directory for `report.md` and `cv.json`.
    #[arg(long, default_value = "reports/family_cv")]
    out: PathBuf,
    /// Replace a report already in `--out`.
    #[arg(long)]
    force: bool,
    /// Also the error against the number of families trained on, at these counts
    /// (comma-separated, e.g. 4,8,12; all the other families are always added).
    #[arg(long, value_delimiter = ',')]
    learning_curve: Vec<usize>,
    /// Random draws of the training families per held-out family and count.
    #[arg(long, default_value_t = 3, requires = "learning_curve")]
    draws: usize,
    /// Seed of those draws.
    #[arg(long, default_value_t = 1, requires = "learning_curve")]
    seed: u64,
    /// Level of the intervals whose coverage on the folds is measured (in (0, 1)).
    #[arg(long, default_value_t = surrogate::DEFAULT_LEVEL)]
    level: f64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    // Checked first: the intervals come after every fold's fits.
    surrogate::check_level(args.level)?;
    let dataset = Dataset::read_csv(&args.data)?;
    let mappings = Mapping::select(&args.mappings)?;
    let _lock = crate::output_guard::claim_dir(&args.out, "`suspflow cross-validate`")?;
    let (report, json) = (args.out.join("report.md"), args.out.join("cv.json"));
    for path in [&report, &json] {
        crate::output_guard::refuse_unless_force(
            path,
            args.force,
            "a cross-validation report",
            "give another --out",
        )?;
    }
    // A missing `profile` column is named here, before any model is read.
    surrogate::profile_names(&dataset)?;
    let plan = mappings
        .into_iter()
        .map(|mapping| {
            let model = TrainedModel::load(&args.models, mapping.name).with_context(|| {
                format!(
                    "reading the hyper-parameters of `{}` from {} (train first, or give --models)",
                    mapping.name,
                    args.models.display()
                )
            })?;
            Ok((mapping, model.meta().hyper_parameters.clone()))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    if !args.learning_curve.is_empty() {
        announce_learning_curves(&dataset, &plan, &args)?;
    }
    let settings = CvSettings {
        learning_curve: args.learning_curve.clone(),
        draws: args.draws,
        seed: args.seed,
        level: args.level,
    };
    let study = FamilyCvStudy::run(&dataset, &plan, &args.models, &settings, &print_progress)?;
    study.write_json(&json)?;
    schema::write_atomic(&report, markdown(&study).as_bytes())?;
    eprintln!(
        "cross-validation of {} mapping(s) in {:.1} s: {} and {}",
        study.mappings.len(),
        study.seconds,
        report.display(),
        json.display()
    );
    Ok(())
}

/// The study's progress on standard error.
fn print_progress(event: CvProgress) {
    match event {
        CvProgress::Mapping {
            mapping,
            samples,
            families,
            params,
        } => {
            warn_skipped(mapping, samples);
            eprintln!(
                "cross-validate {}: {} rows, {families} profile families, trees: {}",
                mapping.name,
                samples.n_rows(),
                describe(params)
            );
        }
        CvProgress::LearningCurve {
            mapping,
            counts,
            draws,
        } => eprintln!(
            "  {}: learning curve at {counts:?} families, {draws} draws each",
            mapping.name
        ),
        CvProgress::Fold {
            mapping,
            done,
            families,
            fold,
        } => eprintln!(
            "  {} [{done}/{families}] left out `{}`: {} rows",
            mapping.name, fold.family, fold.variants[0].all.rows
        ),
        CvProgress::Intervals { mapping } => {
            eprintln!("  {}: intervals on the same folds", mapping.name)
        }
    }
}

/// The learning curves' cost, checked (refused past the work limit, warned past a day) and
/// printed before any fit.
fn announce_learning_curves(
    dataset: &Dataset,
    plan: &[(&Mapping, HyperParameters)],
    args: &Args,
) -> anyhow::Result<()> {
    let mut seconds = 0.0;
    for (mapping, params) in plan {
        let samples = Samples::from_dataset(dataset, mapping)?;
        let cost = CurveCost::of(mapping, &samples, params, &args.learning_curve, args.draws)
            .with_context(|| format!("the learning curve of `{}`", mapping.name))?;
        let warning = cost
            .check()
            .with_context(|| format!("the learning curve of `{}`", mapping.name))?;
        eprintln!("  {}: learning curve of {}", mapping.name, cost.describe());
        if let Some(w) = warning {
            eprintln!("warning: {w}");
        }
        seconds += cost.seconds();
    }
    eprintln!(
        "learning curves estimated at most {} here (besides the cross-validation itself)",
        schema::work_cost::describe(seconds)
    );
    Ok(())
}
