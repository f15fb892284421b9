//! Section 2 of the report: surrogate error against training time and number of trees,
//! and prediction time per profile. Each mapping is retrained on the training set with its
//! tuned hyper-parameters (read from the models' sidecars) and only the number of boosting
//! rounds changed, and validated on the unseen profiles (relative L2, eq 6.6, all profiles
//! together); the shipped models are timed predicting one validation profile end to end.
use crate::plots::loglog::{self, Line};
use crate::surrogate_text::percent;
use anyhow::Context;
use std::fmt::Write as _;
use std::path::Path;
use surrogate::{
    time_mapping, timed_fit, Dataset, Predictor, Validation, ALL_PROFILES, FITS, MAPPINGS,
};

/// Numbers of trees (boosting rounds) trained.
pub const TREES: [u32; 6] = [3, 10, 30, 100, 300, 1000];

/// Writes `surrogate_error_vs_training_time.svg` into `dir` and returns the section.
pub fn section(train: &Path, validate: &Path, models: &Path, dir: &Path) -> anyhow::Result<String> {
    let train_data = Dataset::read_csv(train)?;
    let validate_data = Dataset::read_csv(validate)?;
    let mut md = String::from("## 2. Surrogate error against training time\n\n");
    let _ = writeln!(md, "Training set `{}` ({} rows), validation set `{}` ({} rows). Each mapping is retrained with its \
        tuned hyper-parameters (from `{}`), changing only the number of trees; training time is the median of \
        {FITS} identical fits on one thread (the first fit in a process also pays XGBoost's start-up).\n",
        train.display(), train_data.n_rows(), validate.display(), validate_data.n_rows(), models.display(), FITS = FITS);
    md.push_str(
        "Validation error: eq 6.6 on all rows and, in brackets, its part beyond the targets' own \
         noise, `sqrt(max(0, error^2 - noise^2))` (the noise: the same error of the targets \
         shifted by their standard errors).\n\n",
    );
    md.push_str("| mapping | trees | training time (ms) | validation error |\n|---|---|---|---|\n");
    let mut lines = Vec::new();
    for mapping in &MAPPINGS {
        let tuned = Predictor::load(models, mapping.name)
            .with_context(|| {
                format!(
                    "loading the {} model from {}",
                    mapping.name,
                    models.display()
                )
            })?
            .meta()
            .hyper_parameters
            .clone();
        let mut curves: Vec<Line> = mapping
            .outputs
            .iter()
            .map(|o| Line {
                name: format!("{}: {o}", mapping.name),
                points: Vec::new(),
            })
            .collect();
        for trees in TREES {
            let params = surrogate::HyperParameters {
                n_estimators: trees,
                ..tuned.clone()
            };
            let (model, ms) = timed_fit(mapping, &train_data, &params)?;
            let validation = Validation::run(&model, &validate_data)?;
            let all = validation
                .errors
                .iter()
                .find(|e| e.profile == ALL_PROFILES)
                .context("validation without an all-profiles entry")?;
            let errors = match all.beyond_noise() {
                Some(beyond) => mapping
                    .outputs
                    .iter()
                    .zip(&all.per_output)
                    .zip(&beyond)
                    .map(|((o, &e), &b)| format!("{o} {} ({})", percent(e), percent(b)))
                    .collect::<Vec<_>>()
                    .join(", "),
                None => crate::surrogate_text::errors_by_output(mapping.outputs, &all.per_output),
            };
            let tuned_mark = if trees == tuned.n_estimators {
                " (tuned)"
            } else {
                ""
            };
            let _ = writeln!(
                md,
                "| {} | {trees}{tuned_mark} | {ms:.1} | {errors} |",
                mapping.name
            );
            for (curve, e) in curves.iter_mut().zip(&all.per_output) {
                curve.points.push((ms, *e));
            }
        }
        lines.extend(curves);
    }
    loglog::draw(
        &dir.join("surrogate_error_vs_training_time.svg"),
        "surrogate validation error against training time",
        (
            "training time (ms); points: 3, 10, 30, 100, 300, 1000 trees",
            "relative L2 validation error",
        ),
        &lines,
        None,
    )?;
    md.push_str(
        "\n![surrogate error against training time](surrogate_error_vs_training_time.svg)\n\n",
    );
    md.push_str(&prediction_times(validate, &validate_data, models, dir)?);
    Ok(md)
}

/// Median end-to-end prediction time (load + read + predict, 20 runs) of each shipped model
/// on each validation profile, written alone to `dir/validation_<scene>.csv`.
fn prediction_times(
    validate: &Path,
    data: &Dataset,
    models: &Path,
    dir: &Path,
) -> anyhow::Result<String> {
    let text = std::fs::read_to_string(validate)
        .with_context(|| format!("reading {}", validate.display()))?;
    let (header, body) = text
        .split_once('\n')
        .with_context(|| format!("{} has no rows", validate.display()))?;
    let mut ids: Vec<&String> = Vec::new();
    for id in data.group_keys()? {
        if !ids.contains(&id) {
            ids.push(id);
        }
    }
    let mut md = String::from("Prediction time per profile with the shipped models (load model + read CSV + predict, median of 20 runs):\n\n\
        | profile | rows | mu | theta | dv |\n|---|---|---|---|---|\n");
    for id in ids {
        let rows: Vec<&str> = body
            .lines()
            .filter(|l| l.split(',').next() == Some(id.as_str()))
            .collect();
        let path = dir.join(format!("validation_{id}.csv"));
        schema::write_atomic(&path, format!("{header}\n{}\n", rows.join("\n")).as_bytes())?;
        let times: Vec<String> = MAPPINGS
            .iter()
            .map(|m| time_mapping(m, models, &path, 20).map(|t| format!("{:.2} ms", t.median_ms)))
            .collect::<surrogate::Result<_>>()?;
        let _ = writeln!(md, "| {id} | {} | {} |", rows.len(), times.join(" | "));
    }
    md.push('\n');
    Ok(md)
}
