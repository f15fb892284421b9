//! `suspflow validate`'s tables: per mapping the errors on each unseen profile beside the
//! seeds' figures and the targets' noise, the intervals' coverage, the comparison with
//! XGBoost's defaults and the linear baselines, then theta against dv and the gain
//! importance of every model.
use std::path::Path;
use surrogate::{
    compare_contenders, gain_shares, seeds_validation_error, theta_vs_dv, Baseline, Contender,
    Lower, Mapping, Samples, TrainedModel, Tuning, Validation,
};

use crate::surrogate_text::{describe, errors_by_output, percent};

/// A loaded model and how it did.
pub struct Checked {
    pub mapping: &'static Mapping,
    pub model: TrainedModel,
    pub validation: Validation,
}

/// The table of errors per profile and output, with the seeds' figures.
pub fn print_errors(c: &Checked) {
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
pub fn print_coverage(c: &Checked, level: f64) {
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

/// Errors on all validation rows of models trained on `training`: the chosen and the
/// default XGBoost setting and the linear baselines, with training times; and the tuning
/// record's cross-validated errors.
pub fn print_comparison(c: &Checked, training: &Samples, models: &Path) {
    let meta = c.model.meta();
    let outputs = c.mapping.outputs;
    let rows = compare_contenders(
        c.mapping,
        &meta.hyper_parameters,
        training,
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

/// The errors of mapping theta next to those of mapping dv, profile by profile.
pub fn print_theta_vs_dv(checked: &[Checked]) {
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
pub fn print_importance(checked: &[Checked]) -> anyhow::Result<()> {
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
