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
    compare_contenders, gain_shares, overlap_warning, profile_names, records,
    seeds_validation_error, theta_vs_dv, Baseline, Contender, Dataset, Lower, Mapping, Samples,
    TableKind, TrainedModel, Tuning, Validation, PROFILE_COLUMN,
};

use crate::plots::profile_panels::{profile_panels, Panel, Series};
use crate::surrogate_text::{describe, errors_by_output, percent, warn_skipped};

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

/// A loaded model and how it did.
struct Checked {
    mapping: &'static Mapping,
    model: TrainedModel,
    validation: Validation,
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
        print_comparison(c, args.train.as_deref(), &args.models)?;
    }
    print_theta_vs_dv(&checked);
    print_importance(&checked)?;
    println!("\nfigures: {} in {}", figures.len(), plots.display());
    Ok(())
}

/// The table of errors per profile and output, with the seeds' figures.
fn print_errors(c: &Checked) {
    let meta = c.model.meta();
    println!(
        "\nmapping {}: ({}) -> ({}), trained on {} rows of {}",
        c.mapping.name,
        c.mapping.features.join(", "),
        c.mapping.outputs.join(", "),
        meta.training_data.rows,
        meta.training_data.source
    );
    println!(
        "  relative L2 error (eq 6.6), outputs scaled with the training ranges, and in brackets \
         its part beyond the targets' own noise, sqrt(max(0, error^2 - noise^2)):"
    );
    let width = profile_width(c);
    let header: String = c
        .mapping
        .outputs
        .iter()
        .map(|o| format!("{o:>21}"))
        .collect();
    println!("  {:<width$} {:>5}{header}", "profile", "rows");
    for error in c
        .validation
        .errors
        .iter()
        .chain(&c.validation.domain_errors)
    {
        let beyond = error.beyond_noise();
        let cells: String = (0..error.per_output.len())
            .map(|j| {
                let b = beyond
                    .as_ref()
                    .map_or_else(|| "-".to_owned(), |b| percent(b[j]));
                format!("{:>10} ({b:>8})", percent(error.per_output[j]))
            })
            .collect();
        println!("  {:<width$} {:>5}{cells}", error.profile, error.rows);
    }
    let seeds: String = c
        .mapping
        .outputs
        .iter()
        .map(|o| seeds_validation_error(c.mapping.name, o).map_or_else(|| "-".to_owned(), percent))
        .map(|cell| format!("{cell:>10}{:11}", ""))
        .collect();
    println!("  {:<width$} {:>5}{seeds}", "seeds (thesis, all)", "");
    if let Some(noise) = &c.validation.target_noise {
        let cells: String = noise
            .iter()
            .map(|&e| format!("{:>10}{:11}", percent(e), ""))
            .collect();
        println!(
            "  {:<width$} {:>5}{cells}",
            "target noise (1 s.e., all)",
            c.validation.samples.n_rows()
        );
    }
}

/// The width of the profile column of `c`'s tables: its longest profile, at least 26.
fn profile_width(c: &Checked) -> usize {
    c.validation
        .errors
        .iter()
        .map(|e| e.profile.len())
        .max()
        .unwrap_or(0)
        .max(26)
}

/// The intervals' coverage and mean width per profile and output, beside their coverage on
/// the calibration folds.
fn print_coverage(c: &Checked, level: f64) {
    let Some(intervals) = c.model.intervals() else {
        println!("  no intervals: the model was saved without them");
        return;
    };
    let calibration = &intervals.calibration;
    println!(
        "  {:.0} % intervals: rows inside their interval, and the mean width (output units); \
         on the {} calibration folds (one of the {} left out each) they covered {} at 90 %",
        100.0 * level,
        calibration.folds,
        calibration.held_out,
        errors_by_output(c.mapping.outputs, &calibration.fold_coverage)
    );
    let width = profile_width(c);
    for error in c
        .validation
        .errors
        .iter()
        .chain(&c.validation.domain_errors)
    {
        let (Some(coverage), Some(widths)) = (&error.coverage, &error.mean_width) else {
            continue;
        };
        let cells: String = coverage
            .iter()
            .zip(widths)
            .map(|(&k, &w)| format!("{:>10} ({w:>8.4})", percent(k)))
            .collect();
        println!("  {:<width$} {:>5}{cells}", error.profile, error.rows);
    }
}

/// Errors on all validation rows of models trained on the training data: the chosen and the
/// default XGBoost setting and the linear baselines, with training times; and the tuning
/// record's cross-validated errors.
fn print_comparison(c: &Checked, train: Option<&Path>, models: &Path) -> anyhow::Result<()> {
    let meta = c.model.meta();
    let Some(training) = training_samples(c, train, models)? else {
        return Ok(());
    };
    let outputs = c.mapping.outputs;
    let rows = compare_contenders(
        c.mapping,
        &meta.hyper_parameters,
        &training,
        &c.validation.samples,
    );
    let labels: Vec<String> = rows.iter().map(|r| contender_label(&r.contender)).collect();
    println!(
        "  on all validation rows, each model trained on {} ({} rows):",
        training.source_name,
        training.n_rows()
    );
    let width = labels.iter().map(String::len).max().unwrap_or(0);
    let header: String = outputs.iter().map(|o| format!("{o:>10}")).collect();
    println!("  {:<width$}{header}  {:>10}", "model", "training");
    for (label, row) in labels.iter().zip(rows) {
        let seconds = row.training_seconds;
        match row.errors {
            Ok(errors) => {
                let cells: String = errors
                    .iter()
                    .map(|&e| format!("{:>10}", percent(e)))
                    .collect();
                println!("  {label:<width$}{cells}  {:>7.3} ms", 1e3 * seconds);
            }
            Err(why) => println!("  {label:<width$}  {why}"),
        }
    }
    match Tuning::load(models, c.mapping.name) {
        Ok(tuning) => println!(
            "  cross-validation on the training data ({} folds, one of the {} left out each): chosen {}; defaults {}",
            tuning.folds,
            tuning.left_out.plural(),
            errors_by_output(outputs, &tuning.chosen.per_output),
            errors_by_output(outputs, &tuning.untuned.per_output)
        ),
        Err(_) => println!(
            "  no tuning record {} (trained with --no-tune)",
            Tuning::path(models, c.mapping.name).display()
        ),
    }
    Ok(())
}

/// A contender's label in the comparison table.
fn contender_label(contender: &Contender) -> String {
    match contender {
        Contender::Xgboost { setting, params } => {
            format!("xgboost, {setting}: {}", describe(params))
        }
        Contender::Baseline(Baseline::Linear) => "linear (linfa)".to_owned(),
        Contender::Baseline(Baseline::LogLinear) => "log-linear (linfa, ln of features)".to_owned(),
        Contender::Baseline(Baseline::LocalRheology) => {
            "backbone alone: mu = A J^b, phi_loc by eq 6.7".to_owned()
        }
    }
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

/// The errors of mapping theta next to those of mapping dv, profile by profile.
fn print_theta_vs_dv(checked: &[Checked]) {
    let find = |name: &str| checked.iter().find(|c| c.mapping.name == name);
    let (Some(theta), Some(dv)) = (find("theta"), find("dv")) else {
        return;
    };
    println!("\ntheta vs dv: relative L2 error on each validation profile");
    let width = theta
        .validation
        .errors
        .iter()
        .map(|e| e.profile.len())
        .max()
        .unwrap_or(0)
        .max(24);
    println!(
        "  {:<width$} {:<8}{:>10}{:>10}  lower",
        "profile", "output", "theta", "dv"
    );
    for row in theta_vs_dv(&theta.validation, &dv.validation, theta.mapping.outputs) {
        let lower = match row.lower() {
            Lower::Theta => "theta",
            Lower::Dv => "dv",
            Lower::Tie => "tie",
        };
        println!(
            "  {:<width$} {:<8}{:>10}{:>10}  {lower}",
            row.profile,
            row.output,
            percent(row.theta),
            percent(row.dv)
        );
    }
}

/// Each model's gain importance, as shares of the total.
fn print_importance(checked: &[Checked]) -> anyhow::Result<()> {
    println!("\nfeature importance (gain: mean loss reduction of the splits on a feature, as a share of the sum):");
    for c in checked {
        let gains = c.model.feature_importance()?;
        let shares: Vec<String> = gain_shares(&gains)
            .iter()
            .map(|(name, share)| format!("{name} {:.1} %", 100.0 * share))
            .collect();
        println!("  {:<6} {}", c.mapping.name, shares.join(", "));
    }
    Ok(())
}

/// One figure per profile in `dir`: each output of the checked mappings along y, simulated
/// and predicted. Returns the files written.
fn write_figures(data: &Dataset, checked: &[Checked], dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut outputs: Vec<&str> = checked
        .iter()
        .flat_map(|c| c.mapping.outputs.iter().copied())
        .collect();
    let columns = data.column_names();
    outputs.sort_by_key(|o| columns.iter().position(|c| c == o));
    outputs.dedup();
    let y = data.column("y")?;
    let profiles = data.text(PROFILE_COLUMN)?;
    let mut files = Vec::new();
    for (k, profile) in profile_names(data)?.iter().enumerate() {
        let rows: Vec<usize> = (0..data.n_rows())
            .filter(|&r| &profiles[r] == profile)
            .collect();
        let mut panels = Vec::new();
        for &output in &outputs {
            let values = data.column(output)?;
            let se_name = schema::columns::standard_error(output);
            let errors = if columns.contains(&se_name) {
                Some(data.column(&se_name)?)
            } else {
                None
            };
            let mut series = vec![Series {
                name: "simulated".to_owned(),
                points: rows.iter().map(|&r| (y[r], values[r])).collect(),
                errors: errors.map(|se| rows.iter().map(|&r| se[r]).collect()),
            }];
            for c in checked {
                let Some(j) = c.mapping.outputs.iter().position(|o| *o == output) else {
                    continue;
                };
                let v = &c.validation;
                series.push(Series {
                    name: format!("mapping {}", c.mapping.name),
                    points: (0..v.samples.n_rows())
                        .filter(|&i| &v.profiles[i] == profile)
                        .map(|i| (y[v.samples.data_rows[i] - 1], v.predicted[[i, j]]))
                        .collect(),
                    errors: None,
                });
            }
            panels.push(Panel {
                quantity: output.to_owned(),
                series,
            });
        }
        let path = dir.join(format!("profile_{}_{}.svg", k + 1, file_stem(profile)));
        profile_panels(&path, &figure_title(data, profile, rows[0])?, &panels)?;
        files.push(path);
    }
    Ok(files)
}

/// `u_inf = <profile>`, with L_y and phi of the profile's first row when the data has them.
fn figure_title(data: &Dataset, profile: &str, row: usize) -> anyhow::Result<String> {
    let mut title = format!("u_inf = {profile}");
    for column in ["L_y", "phi"] {
        if data.column_names().iter().any(|c| c == column) {
            title += &format!(", {column} = {}", data.text(column)?[row]);
        }
    }
    Ok(title + "; simulated vs predicted")
}

/// A file-name-safe form of a profile expression: runs of other characters become `_`.
fn file_stem(profile: &str) -> String {
    let mut stem = String::new();
    for ch in profile.chars() {
        if ch.is_ascii_alphanumeric() {
            stem.push(ch);
        } else if !stem.ends_with('_') {
            stem.push('_');
        }
    }
    stem.trim_matches('_').chars().take(60).collect()
}

#[cfg(test)]
mod tests {
    use super::file_stem;

    #[test]
    fn file_stems_keep_letters_and_digits_only() {
        assert_eq!(file_stem("0.1*sin(2*pi*y/L)^3"), "0_1_sin_2_pi_y_L_3");
        assert_eq!(file_stem("  "), "");
    }
}
