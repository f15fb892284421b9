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
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use surrogate::{
    family_names, output_standard_errors, profile_names, CurveCost, Dataset, FamilyCv,
    IntervalCoverage, IntervalStudy, LearningCurve, Mapping, MeanErrors, RowErrors, Samples,
    TableKind, TrainedModel, Variant,
};

use crate::surrogate_text::{describe, percent, warn_skipped};

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

/// Everything `cv.json` holds.
#[derive(Serialize)]
struct Record<'a> {
    data: &'a str,
    /// FNV-1a 64 hash of the data file, 16 hex digits.
    fnv1a_64: schema::Fingerprint,
    table: Option<String>,
    families: Vec<String>,
    models: String,
    seconds: f64,
    mappings: &'a [FamilyCv],
    /// One per mapping with `--learning-curve`.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    learning_curves: &'a [LearningCurve],
    /// The intervals' coverage on the same folds, one per mapping.
    intervals: &'a [IntervalCoverage],
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let started = Instant::now();
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
    let table = TableKind::of(&dataset).ok().map(|kind| kind.describe());
    // A missing `profile` column is named here, before any model is read.
    let families = profile_names(&dataset)?;
    let mut inputs = Vec::new();
    for mapping in mappings {
        let params = TrainedModel::load(&args.models, mapping.name)
            .with_context(|| {
                format!(
                    "reading the hyper-parameters of `{}` from {} (train first, or give --models)",
                    mapping.name,
                    args.models.display()
                )
            })?
            .meta()
            .hyper_parameters
            .clone();
        let samples = Samples::from_dataset(&dataset, mapping)?;
        inputs.push((mapping, params, samples));
    }
    if !args.learning_curve.is_empty() {
        announce_learning_curves(&inputs, &args)?;
    }
    let (mut results, mut curves, mut intervals) = (Vec::new(), Vec::new(), Vec::new());
    for (mapping, params, samples) in &inputs {
        let (mapping, params, samples) = (*mapping, params, samples);
        warn_skipped(mapping, samples);
        let n = family_names(samples)?.len();
        eprintln!(
            "cross-validate {}: {} rows, {n} profile families, trees: {}",
            mapping.name,
            samples.n_rows(),
            describe(params)
        );
        if !args.learning_curve.is_empty() {
            eprintln!(
                "  {}: learning curve at {:?} families, {} draws each",
                mapping.name, args.learning_curve, args.draws
            );
            curves.push(
                LearningCurve::run(
                    mapping,
                    samples,
                    params,
                    &args.learning_curve,
                    args.draws,
                    args.seed,
                )
                .with_context(|| format!("the learning curve of `{}`", mapping.name))?,
            );
        }
        let finished = AtomicUsize::new(0);
        let standard_errors = output_standard_errors(&dataset, samples)?;
        let cv = FamilyCv::run(
            mapping,
            samples,
            standard_errors.as_ref(),
            params,
            &|fold| {
                let k = finished.fetch_add(1, Ordering::Relaxed) + 1;
                eprintln!(
                    "  {} [{k}/{n}] left out `{}`: {} rows",
                    mapping.name, fold.family, fold.variants[0].all.rows
                );
            },
        )
        .with_context(|| format!("cross-validating `{}`", mapping.name))?;
        results.push(cv);
        eprintln!("  {}: intervals on the same folds", mapping.name);
        intervals.push(
            IntervalStudy::run(
                mapping,
                samples,
                standard_errors.as_ref().map(|se| se.view()),
                params,
                args.level,
            )
            .with_context(|| format!("the intervals of `{}`", mapping.name))?
            .coverage,
        );
    }
    let seconds = started.elapsed().as_secs_f64();
    let record = Record {
        data: dataset.source_name(),
        fnv1a_64: dataset.fingerprint(),
        table,
        families,
        models: args.models.display().to_string(),
        seconds,
        mappings: &results,
        learning_curves: &curves,
        intervals: &intervals,
    };
    schema::write_atomic(
        &json,
        (serde_json::to_string_pretty(&record)? + "\n").as_bytes(),
    )?;
    schema::write_atomic(&report, markdown(&record, &args.models).as_bytes())?;
    eprintln!(
        "cross-validation of {} mapping(s) in {seconds:.1} s: {} and {}",
        results.len(),
        report.display(),
        json.display()
    );
    Ok(())
}

/// The report: what was done, then per mapping a summary and one table per output.
fn markdown(record: &Record, models: &Path) -> String {
    let mut md = String::from("# Leave-one-family-out cross-validation\n\n");
    let _ = writeln!(
        md,
        "Data: `{}`{} (FNV-1a 64 `{}`), {} profile families (the `profile` column: shape \
         and amplitude of the forcing). Each fold holds out one family and fits, on the other \
         families' rows, the training domain and three variants: XGBoost alone, the physics \
         backbone alone (`mu = A J^b`, `phi_loc` from eq 6.7) and backbone + XGBoost (trees on \
         the backbone's residual), the trees with the hyper-parameters of the models in `{}`. \
         Errors: relative L2 error of eq 6.6 on the held-out rows, outputs min-max scaled \
         with the fold's training ranges; \"in\" and \"out\" are the rows inside and outside \
         the fold's training domain; \"abs\": the mean absolute error on all held-out rows, \
         in the output's own units (eq 6.6 on mu is dominated by the near-zero mu of \
         plugs). {:.1} s in all.\n",
        record.data,
        record
            .table
            .as_ref()
            .map_or_else(String::new, |t| format!(", {t}")),
        record.fnv1a_64,
        record.families.len(),
        models.display(),
        record.seconds
    );
    for cv in record.mappings {
        mapping_section(&mut md, cv);
        if let Some(curve) = record
            .learning_curves
            .iter()
            .find(|c| c.mapping == cv.mapping)
        {
            learning_curve_section(&mut md, curve);
        }
    }
    crate::cv_sections::mappings_side_by_side(&mut md, record.mappings);
    for coverage in record.intervals {
        crate::cv_sections::interval_section(&mut md, coverage);
    }
    md
}

/// The error against the number of families trained on, one column per output, and its
/// change from the full count.
/// Before any fit: each mapping's learning curve checked and timed by one fit
/// (`CurveCost`), their estimated wall time together, and the warning of a day-long one
/// (the rule of `schema::work_cost`, as for every option that sets work).
fn announce_learning_curves(
    inputs: &[(&Mapping, surrogate::HyperParameters, Samples)],
    args: &Args,
) -> anyhow::Result<()> {
    let mut seconds = 0.0;
    for (mapping, params, samples) in inputs {
        let cost = CurveCost::of(mapping, samples, params, &args.learning_curve, args.draws)
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

fn learning_curve_section(md: &mut String, curve: &LearningCurve) {
    let trees = if curve.backbone {
        Variant::BackboneTrees
    } else {
        Variant::Trees
    };
    let _ = writeln!(
        md,
        "### `{}`: error against the number of families trained on\n\n\
         The models' variant ({}) on the rows of n of the other families, drawn at random \
         ({} draws per held-out family below the full count, seed {}), scored on the held-out \
         family with the outputs scaled on all the other families' rows: the mean over the \
         held-out families ± its standard error, and its change from the full count (the \
         variant's error above) ± the standard error of the paired differences.\n\n\
         | families | fits | {} |\n|---|---|{}",
        curve.mapping,
        trees.label(),
        curve.draws,
        curve.seed,
        curve
            .outputs
            .iter()
            .map(|o| format!("{o} | change"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|---|".repeat(curve.outputs.len())
    );
    for p in &curve.points {
        let cells: Vec<String> = (0..curve.outputs.len())
            .map(|j| {
                format!(
                    "{} ± {} | {:+.2} ± {:.2}",
                    percent(p.per_output[j]),
                    percent(p.standard_error[j]),
                    100.0 * p.change_from_full[j],
                    100.0 * p.change_standard_error[j]
                )
            })
            .collect();
        let _ = writeln!(
            md,
            "| {} | {} | {} |",
            p.families,
            p.fits,
            cells.join(" | ")
        );
    }
    md.push('\n');
}

fn mapping_section(md: &mut String, cv: &FamilyCv) {
    let mapping = Mapping::by_name(&cv.mapping).ok();
    let _ = writeln!(
        md,
        "## Mapping `{}`{}\n\n{} rows ({} skipped for an empty cell); trees: {}.\n",
        cv.mapping,
        mapping.map_or_else(String::new, |m| format!(
            ": ({}) -> ({})",
            m.features.join(", "),
            m.outputs.join(", ")
        )),
        cv.rows,
        cv.skipped_rows,
        describe(&cv.hyper_parameters)
    );
    let _ = writeln!(
        md,
        "Mean over the held-out families (in parentheses: families with such rows){}.\n\n\
         | output | variant | all | in domain | out of domain | abs, all | beyond noise, all |\n\
         |---|---|---|---|---|---|---|",
        if cv.target_noise.is_some() {
            "; \"beyond noise\": the mean over the families of each one's error beyond its \
             targets' own noise, `sqrt(max(0, error^2 - noise^2))`"
        } else {
            ""
        }
    );
    for (j, output) in cv.outputs.iter().enumerate() {
        for s in &cv.summary {
            let cell = |m: &MeanErrors| match &m.per_output {
                Some(e) => format!("{} ({})", percent(e[j]), m.families),
                None => "-".to_owned(),
            };
            let _ = writeln!(
                md,
                "| {output} | {} | {} | {} | {} | {} | {} |",
                s.variant.label(),
                cell(&s.all),
                cell(&s.in_domain),
                cell(&s.out_of_domain),
                absolute_cell(s.all.mean_absolute.as_ref(), j),
                s.all
                    .beyond_noise
                    .as_ref()
                    .map_or_else(|| "-".to_owned(), |b| percent(b[j]))
            );
        }
    }
    if let Some(noise) = &cv.target_noise {
        for (j, output) in cv.outputs.iter().enumerate() {
            let _ = writeln!(
                md,
                "| {output} | the targets' own noise | {} | | | | |",
                percent(noise[j])
            );
        }
    }
    md.push('\n');
    if cv.target_noise.is_some() {
        md.push_str(
            "The targets' own noise: eq 6.6 of the held-out targets shifted by their standard \
             errors (`<output>_se`), what a model that predicts the true means would score.\n\n",
        );
    }
    for (j, output) in cv.outputs.iter().enumerate() {
        let labels: Vec<&str> = Variant::ALL.iter().map(|v| v.label()).collect();
        let _ = writeln!(
            md,
            "### `{output}` by held-out family (all / in / out)\n\n\
             | family | rows (in / out) | {} | abs, all ({}) | noise | beyond noise, all ({}) |\n\
             |---|---|{}---|---|---|",
            labels.join(" | "),
            labels.join(" / "),
            labels.join(" / "),
            "---|".repeat(labels.len())
        );
        for fold in &cv.folds {
            let v0 = &fold.variants[0];
            let cells: Vec<String> = fold
                .variants
                .iter()
                .map(|v| match &v.not_applicable {
                    Some(_) => "n/a".to_owned(),
                    None => [&v.all, &v.in_domain, &v.out_of_domain]
                        .map(|e| error_cell(e, j))
                        .join(" / "),
                })
                .collect();
            let absolute: Vec<String> = fold
                .variants
                .iter()
                .map(|v| absolute_cell(v.all.mean_absolute.as_ref(), j))
                .collect();
            let beyond: Vec<String> = fold
                .variants
                .iter()
                .map(|v| {
                    v.all
                        .beyond_noise
                        .as_ref()
                        .map_or_else(|| "-".to_owned(), |b| percent(b[j]))
                })
                .collect();
            let _ = writeln!(
                md,
                "| `{}` | {} ({} / {}) | {} | {} | {} | {} |",
                fold.family.replace('|', "\\|"),
                v0.all.rows,
                v0.in_domain.rows,
                v0.out_of_domain.rows,
                cells.join(" | "),
                absolute.join(" / "),
                fold.target_noise
                    .as_ref()
                    .map_or_else(|| "-".to_owned(), |n| percent(n[j])),
                beyond.join(" / ")
            );
        }
        md.push('\n');
    }
    for fold in &cv.folds {
        for v in &fold.variants {
            if let Some(why) = &v.not_applicable {
                let _ = writeln!(
                    md,
                    "n/a: {} with `{}` held out: {why}\n",
                    v.variant.label(),
                    fold.family
                );
            }
        }
    }
}

/// One output's error as a percentage, `-` for a class without rows.
fn error_cell(errors: &RowErrors, output: usize) -> String {
    errors
        .per_output
        .as_ref()
        .map_or_else(|| "-".to_owned(), |e| percent(e[output]))
}

/// One output's mean absolute error (output units, 3 decimals), `-` when there is none.
fn absolute_cell(errors: Option<&Vec<f64>>, output: usize) -> String {
    errors.map_or_else(|| "-".to_owned(), |e| format!("{:.3}", e[output]))
}
