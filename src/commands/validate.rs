//! `suspflow validate --models DIR --data FILE.csv`: the trained mappings on flow profiles
//! they were not trained on (thesis section 6.2, figures 6.2-6.4).
//!
//! For each mapping, output and profile (the `profile` column, and all profiles together) it
//! prints the relative L2 error of eq 6.6 on outputs min-max scaled with the training ranges
//! stored in the model's sidecar, next to the seeds' figures and the targets' own noise (the
//! same error of the targets shifted by one standard error: small for an ensemble table). From the training data (the
//! file the sidecar names, or `--train`) it then measures on all validation rows, with
//! training times, the chosen XGBoost setting, XGBoost's defaults (the thesis's untuned
//! setting) and two linfa least-squares baselines; it also shows the cross-validated errors
//! of the tuning record. Then the theta vs dv errors on every profile and each model's gain
//! importance. One SVG per profile shows phi_loc and mu along y: simulated (error bars of
//! one standard error from `<column>_se`) and each mapping's prediction. `--json` prints
//! only the records `{mapping, output, profile, rel_l2}`.
use anyhow::Context;
use std::path::{Path, PathBuf};
use surrogate::{
    overlap_warning, records, Dataset, Mapping, Samples, TableKind, TrainedModel, Validation,
};

use crate::plots::validation_figures::write_figures;
use crate::report::validation::{
    print_comparison, print_coverage, print_errors, print_importance, print_theta_vs_dv, Checked,
};
use crate::surrogate_text::warn_skipped;

#[derive(clap::Args)]
pub struct Args {
    /// Directory of the trained models (`suspflow train --out`).
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Validation table (simulations not used in training, docs/physics.md section 8 columns):
    /// the per-run table or the ensemble table (`<stem>.ensemble.csv`), told apart by the
    /// columns; profiles are told apart by the `profile` column.
    #[arg(long)]
    data: PathBuf,
    /// Mappings to validate (mu, theta, dv, ext); all four when absent.
    #[arg(long = "mapping")]
    mappings: Vec<String>,
    /// Directory for the figures, one SVG per profile; `<models>/validation_plots` when absent.
    #[arg(long)]
    plots: Option<PathBuf>,
    /// Training table for the comparisons with XGBoost's defaults and the linear baselines;
    /// when absent, the file each model's sidecar names, if it still holds the same bytes.
    #[arg(long)]
    train: Option<PathBuf>,
    /// Print only a JSON array of records {"mapping", "output", "profile", "rel_l2",
    /// "beyond_noise", "coverage", "interval_width"}.
    #[arg(long)]
    json: bool,
    /// Level of the intervals whose coverage is measured (a probability in (0, 1)).
    #[arg(long, default_value_t = surrogate::DEFAULT_LEVEL)]
    level: f64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let data = Dataset::read_csv(&args.data)?;
    let mut checked = Vec::new();
    for mapping in Mapping::select(&args.mappings)? {
        let model = TrainedModel::load(&args.models, mapping.name).with_context(|| {
            format!(
                "loading model `{}` from {}",
                mapping.name,
                args.models.display()
            )
        })?;
        let validation = Validation::run_at(&model, &data, args.level)
            .with_context(|| format!("validating model `{}`", mapping.name))?;
        warn_skipped(mapping, &validation.samples);
        if let Some(warning) = overlap_warning(&model, &args.models, &data, &validation.samples) {
            eprintln!("warning: {warning}");
        }
        checked.push(Checked {
            mapping,
            model,
            validation,
        });
    }
    let plots = args
        .plots
        .clone()
        .unwrap_or_else(|| args.models.join("validation_plots"));
    let figures = write_figures(&data, &checked, &plots)?;
    if args.json {
        let records: Vec<_> = checked
            .iter()
            .flat_map(|c| records(c.mapping, &c.validation))
            .collect();
        println!("{}", serde_json::to_string_pretty(&records)?);
        return Ok(());
    }
    println!(
        "validation data {}: {} rows",
        data.source_name(),
        data.n_rows()
    );
    // A table without scene ids has no kind (validation groups by profile, not by scene).
    if let Ok(kind) = TableKind::of(&data) {
        println!("  {}", kind.describe());
    }
    for c in &checked {
        print_errors(c);
        print_coverage(c, args.level);
        if let Some(training) = training_samples(c, args.train.as_deref(), &args.models)? {
            print_comparison(c, &training, &args.models);
        }
    }
    print_theta_vs_dv(&checked);
    print_importance(&checked)?;
    println!("\nfigures: {} in {}", figures.len(), plots.display());
    Ok(())
}

/// The mapping's rows of its training data: `--train`, or the file the sidecar names. `None`
/// (with a note) when the sidecar's file is gone or changed; an error when `--train` is not
/// the data the model was trained on.
fn training_samples(
    c: &Checked,
    train: Option<&Path>,
    models: &Path,
) -> anyhow::Result<Option<Samples>> {
    let path = train.map_or_else(|| c.model.meta().training_file(models), Path::to_path_buf);
    match (
        surrogate::training_samples(&c.model, c.mapping, &path),
        train,
    ) {
        (Ok(samples), _) => Ok(Some(samples)),
        (Err(problem), Some(_)) => anyhow::bail!("--train: {problem}"),
        (Err(problem), None) => {
            println!("  comparisons with XGBoost's defaults and the baselines skipped: {problem}; pass --train FILE");
            Ok(None)
        }
    }
}
