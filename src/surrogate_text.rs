//! Text shared by the surrogate commands' reports: percentages, hyper-parameters, and the
//! warning about rows left out for empty cells.
use surrogate::{HyperParameters, Mapping, Samples};

/// A fraction as a percentage with two decimals, e.g. `5.10 %`.
pub fn percent(fraction: f64) -> String {
    format!("{:.2} %", 100.0 * fraction)
}

/// `name error` pairs, e.g. `phi_loc 0.52 %, mu 5.10 %`.
pub fn errors_by_output<S: AsRef<str>>(outputs: &[S], errors: &[f64]) -> String {
    let pairs: Vec<String> = outputs
        .iter()
        .zip(errors)
        .map(|(o, &e)| format!("{} {}", o.as_ref(), percent(e)))
        .collect();
    pairs.join(", ")
}

/// `name width` pairs in the outputs' units, e.g. `phi_loc 0.0301, mu 0.205`.
pub fn widths_by_output<S: AsRef<str>>(outputs: &[S], widths: &[f64]) -> String {
    let pairs: Vec<String> = outputs
        .iter()
        .zip(widths)
        .map(|(o, &w)| format!("{} {w:.3}", o.as_ref()))
        .collect();
    pairs.join(", ")
}

/// The settings a grid search varies, e.g. `300 rounds, depth 3, eta 0.1, min_child_weight 1`,
/// prefixed by `backbone + ` when the trees learn the backbone's residual.
pub fn describe(params: &HyperParameters) -> String {
    format!(
        "{}{} rounds, depth {}, eta {}, min_child_weight {}",
        if params.backbone { "backbone + " } else { "" },
        params.n_estimators,
        params.max_depth,
        params.learning_rate,
        params.min_child_weight
    )
}

/// Says on standard error how many rows `mapping` could not use, if any.
pub fn warn_skipped(mapping: &Mapping, samples: &Samples) {
    if samples.skipped_rows > 0 {
        let columns = mapping.columns();
        eprintln!(
            "warning: {}: {} of {} rows of {} skipped: an empty (undefined) cell in one of {}",
            mapping.name,
            samples.skipped_rows,
            samples.skipped_rows + samples.n_rows(),
            samples.source_name,
            columns.join(", ")
        );
    }
}
