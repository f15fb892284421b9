//! Sections of the cross-validation report (`suspflow cross-validate`): the mappings side by
//! side family by family, and the coverage of their intervals on the same folds.
use std::fmt::Write as _;
use surrogate::{FamilyCv, IntervalCoverage, IntervalMethod, Variant};

use crate::surrogate_text::percent;

/// For each output two or more mappings predict, one row per held-out family: each mapping's
/// error (eq 6.6) with the variant its models use, and in brackets the part beyond the
/// family's targets' own noise; then the means over the families.
pub fn mappings_side_by_side(md: &mut String, results: &[FamilyCv]) {
    let mut outputs: Vec<&str> = results
        .iter()
        .flat_map(|cv| cv.outputs.iter().map(String::as_str))
        .collect();
    outputs.sort_unstable();
    outputs.dedup();
    for output in outputs {
        let with: Vec<(&FamilyCv, usize, usize)> = results
            .iter()
            .filter_map(|cv| {
                let j = cv.outputs.iter().position(|o| o == output)?;
                let variant = if cv.hyper_parameters.backbone {
                    Variant::BackboneTrees
                } else {
                    Variant::Trees
                };
                let k = Variant::ALL.iter().position(|&v| v == variant)?;
                Some((cv, j, k))
            })
            .collect();
        if with.len() < 2 {
            continue;
        }
        let names: Vec<&str> = with.iter().map(|(cv, _, _)| cv.mapping.as_str()).collect();
        let _ = writeln!(
            md,
            "## `{output}` by held-out family, mapping by mapping\n\n\
             Each mapping with the variant of its models (backbone + XGBoost when they learn \
             the backbone's residual): error on all held-out rows (eq 6.6){}.\n\n\
             | family | {} | noise |\n|---|{}---|",
            if with[0].0.target_noise.is_some() {
                " and, in brackets, its part beyond the family's targets' own noise"
            } else {
                ""
            },
            names.join(" | "),
            "---|".repeat(names.len())
        );
        let families: Vec<&str> = with[0].0.folds.iter().map(|f| f.family.as_str()).collect();
        for (i, family) in families.iter().enumerate() {
            let cells: Vec<String> = with
                .iter()
                .map(
                    |(cv, j, k)| match cv.folds.get(i).filter(|f| f.family == *family) {
                        Some(fold) => {
                            let e = &fold.variants[*k].all;
                            match (&e.per_output, &e.beyond_noise) {
                                (Some(p), Some(b)) => {
                                    format!("{} ({})", percent(p[*j]), percent(b[*j]))
                                }
                                (Some(p), None) => percent(p[*j]),
                                _ => "-".to_owned(),
                            }
                        }
                        None => "-".to_owned(),
                    },
                )
                .collect();
            let noise = with[0].0.folds[i]
                .target_noise
                .as_ref()
                .map_or_else(|| "-".to_owned(), |n| percent(n[with[0].1]));
            let _ = writeln!(
                md,
                "| `{}` | {} | {noise} |",
                family.replace('|', "\\|"),
                cells.join(" | ")
            );
        }
        let means: Vec<String> = with
            .iter()
            .map(|(cv, j, k)| {
                let m = &cv.summary[*k].all;
                match (&m.per_output, &m.beyond_noise) {
                    (Some(p), Some(b)) => format!("**{}** ({})", percent(p[*j]), percent(b[*j])),
                    (Some(p), None) => format!("**{}**", percent(p[*j])),
                    _ => "-".to_owned(),
                }
            })
            .collect();
        let noise = with[0]
            .0
            .target_noise
            .as_ref()
            .map_or_else(|| "-".to_owned(), |n| percent(n[with[0].1]));
        let _ = writeln!(md, "| **mean** | {} | {noise} |\n", means.join(" | "));
    }
}

/// One mapping's intervals on the folds: the methods per output (coverage, mean width,
/// interval score, folds covered below 85 % and above 95 %), then the shipped method's
/// coverage family by family.
pub fn interval_section(md: &mut String, c: &IntervalCoverage) {
    let level = 100.0 * c.level;
    let _ = writeln!(
        md,
        "## Intervals of `{}` on the folds ({level:.0} %)\n\n\
         Every row of a held-out family gets the interval of the models trained without it, \
         widened by the margin of the other folds' conformity scores (cross-conformal: a \
         family's own rows never calibrate its intervals). \"noise apart\": the interval of a \
         target with the row's own standard error (`<output>_se`), the model's error and the \
         target's noise added in quadrature (models/README.md); \"noise-blind\": one margin \
         for targets of any noise. Coverage: the fraction of held-out \
         rows inside; width: the mean of upper - lower (output units); interval score: width \
         plus 2 / (1 - level) times the distance of a miss (lower is better); folds: families \
         covered below 85 % / above 95 %.\n\n\
         | output | method | coverage | mean width | interval score | folds < 85 % / > 95 % |\n\
         |---|---|---|---|---|---|",
        c.mapping
    );
    for (j, output) in c.outputs.iter().enumerate() {
        for m in &c.methods {
            let o = &m.per_output[j];
            let _ = writeln!(
                md,
                "| {output} | {} | {} | {:.4} | {:.4} | {} / {} |",
                m.method.label(),
                percent(o.coverage),
                o.mean_width,
                o.interval_score,
                o.folds_below,
                o.folds_above
            );
        }
    }
    let _ = writeln!(
        md,
        "\n{} by held-out {}: coverage (mean width)\n\n| held out | rows | {} |\n|---|---|{}",
        IntervalMethod::ConformalQuantiles.label(),
        c.left_out.plural(),
        c.outputs.join(" | "),
        "---|".repeat(c.outputs.len())
    );
    for f in &c.folds {
        let cells: Vec<String> = f
            .coverage
            .iter()
            .zip(&f.mean_width)
            .map(|(&k, &w)| format!("{} ({w:.4})", percent(k)))
            .collect();
        let _ = writeln!(
            md,
            "| `{}` | {} | {} |",
            f.held_out.replace('|', "\\|"),
            f.rows,
            cells.join(" | ")
        );
    }
    md.push('\n');
}
