//! `suspflow cross-validate`'s report, `report.md`: what was done, then per mapping a
//! summary, one table per output and the learning curve, the mappings side by side and the
//! intervals' coverage on the folds, from the study's record (`surrogate::FamilyCvStudy`).
use std::fmt::Write as _;
use surrogate::{FamilyCv, FamilyCvStudy, LearningCurve, Mapping, MeanErrors, RowErrors, Variant};

use crate::surrogate_text::{describe, percent};

/// The report: what was done, then per mapping a summary and one table per output.
pub fn markdown(record: &FamilyCvStudy) -> String {
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
        record.models,
        record.seconds
    );
    for cv in &record.mappings {
        mapping_section(&mut md, cv);
        if let Some(curve) = record
            .learning_curves
            .iter()
            .find(|c| c.mapping == cv.mapping)
        {
            learning_curve_section(&mut md, curve);
        }
    }
    crate::cv_sections::mappings_side_by_side(&mut md, &record.mappings);
    for coverage in &record.intervals {
        crate::cv_sections::interval_section(&mut md, coverage);
    }
    md
}

/// The error against the number of families trained on, one column per output, and its
/// change from the full count.
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
