//! The crate's single error type.

use std::path::PathBuf;

/// Everything that can go wrong in this crate, with enough context to act on the message.
#[derive(Debug, thiserror::Error)]
pub enum SurrogateError {
    /// A column the caller asked for is not in the dataset.
    #[error("{source_name}: no column `{name}`; available columns: {}", available.join(", "))]
    MissingColumn {
        source_name: String,
        name: String,
        available: Vec<String>,
    },

    /// A column that must hold numbers holds text that does not parse as one.
    #[error("{source_name}: data row {row}, column `{column}`: `{text}` is not a number")]
    NotANumber {
        source_name: String,
        row: usize,
        column: String,
        text: String,
    },

    /// An empty cell (an undefined value) where a number is needed.
    #[error("{source_name}: data row {row}, column `{column}` is empty (an undefined value)")]
    EmptyCell {
        source_name: String,
        row: usize,
        column: String,
    },

    /// A NaN or infinite value where a finite number is needed (`row` counts data rows from 1).
    #[error("{source_name}: data row {row}, column `{column}`: {value} is not a finite number")]
    NonFinite {
        source_name: String,
        row: usize,
        column: String,
        value: f64,
    },

    /// A finite value too large for f32, the element type the models read their inputs in.
    /// `place` is "line L (data row R)" for a table, "row R" for a matrix.
    #[error("{source_name}: {place}, column `{column}`: {value:e} exceeds the f32 range of the models' inputs (|x| <= 3.4e38)")]
    BeyondF32 {
        source_name: String,
        place: String,
        column: String,
        value: f64,
    },

    /// A value that no flow can have (negative J, phi = 2, ...; see
    /// [`crate::data::physical_range::measured_range`]).
    #[error("{source_name}: data row {row}, column `{column}`: {value} is not physical ({range})")]
    Unphysical {
        source_name: String,
        row: usize,
        column: String,
        value: f64,
        range: String,
    },

    /// The files of a saved model disagree with each other or hold impossible values.
    #[error("model {model}: {detail}")]
    InconsistentModel { model: String, detail: String },

    /// A value that must be positive (e.g. to take its logarithm) is not.
    #[error("{source_name}: data row {row}, column `{column}`: {value} is not positive, so it has no logarithm")]
    NonPositive {
        source_name: String,
        row: usize,
        column: String,
        value: f64,
    },

    /// A dataset, or a part of it that must hold rows, holds none.
    #[error("{what} holds no data rows")]
    EmptyDataset { what: String },

    /// A CSV record has a different number of fields than the header.
    #[error("{source_name}: data row {row} has {found} fields, the header has {expected}")]
    RaggedRow {
        source_name: String,
        row: usize,
        expected: usize,
        found: usize,
    },

    /// The input does not carry the features a model was trained on, or a model's parts
    /// disagree on its columns; `detail` says what differs ([`name_differences`]).
    #[error("{detail}")]
    FeatureMismatch { detail: String },

    /// Two arrays that must have the same shape do not.
    #[error("shape mismatch in {what}: expected {expected:?}, found {found:?}")]
    ShapeMismatch {
        what: String,
        expected: (usize, usize),
        found: (usize, usize),
    },

    /// No mapping has this name.
    #[error("unknown mapping `{name}`; known mappings: {}", known.join(", "))]
    UnknownMapping { name: String, known: Vec<String> },

    /// An argument outside its valid range (e.g. more folds than groups).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),

    /// The XGBoost library reported an error; the message is the library's own.
    #[error("XGBoost: {0}")]
    Xgboost(String),

    /// An XGBoost JSON model file that cannot be read, or holds what this crate does not
    /// read; the message names the file.
    #[error("{0}")]
    ModelFormat(String),

    /// A linear baseline could not be fitted.
    #[error("linear baseline: {0}")]
    Baseline(#[from] linfa_linear::LinearError<f64>),

    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },

    /// A CSV source is malformed.
    #[error("{source_name}: {source}")]
    Csv {
        source_name: String,
        source: csv::Error,
    },

    /// A file that cannot be read as what it should hold (empty, truncated, not JSON, JSON
    /// of another shape); `detail` says which.
    #[error("{}: {detail}", path.display())]
    UnreadableFile { path: PathBuf, detail: String },

    /// A JSON file cannot be written.
    #[error("{}: {source}", path.display())]
    Json {
        path: PathBuf,
        source: serde_json::Error,
    },

    /// A table offered as a model's training data holds other bytes than the ones its
    /// sidecar records.
    #[error("{} is not the file model `{model}` was trained on (its hash differs)", path.display())]
    NotTrainingData { path: PathBuf, model: String },

    /// An error met while doing `what` (e.g. "cross-validating `mu`").
    #[error("{what}: {source}")]
    Within {
        what: String,
        source: Box<SurrogateError>,
    },
}

/// How the list of names `found` differs from `expected`: the names missing from it, those
/// it has besides, or, with the same names, the order of both; empty when they are equal.
pub fn name_differences<A: AsRef<str>, B: AsRef<str>>(expected: &[A], found: &[B]) -> String {
    let expected: Vec<&str> = expected.iter().map(AsRef::as_ref).collect();
    let found: Vec<&str> = found.iter().map(AsRef::as_ref).collect();
    let missing: Vec<&str> = expected
        .iter()
        .filter(|e| !found.contains(e))
        .copied()
        .collect();
    let extra: Vec<&str> = found
        .iter()
        .filter(|f| !expected.contains(f))
        .copied()
        .collect();
    let mut parts = Vec::new();
    if !missing.is_empty() {
        parts.push(format!("missing {}", missing.join(", ")));
    }
    if !extra.is_empty() {
        parts.push(format!("extra {}", extra.join(", ")));
    }
    if parts.is_empty() && expected != found {
        if expected.len() == found.len() {
            parts.push("the same names in another order".to_owned());
        } else {
            parts.push("a name repeated".to_owned());
        }
    }
    parts.join("; ")
}

/// Result type of this crate.
pub type Result<T> = std::result::Result<T, SurrogateError>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn name_differences_say_what_is_missing_extra_or_reordered() {
        assert_eq!(name_differences(&["a", "b"], &["a", "b"]), "");
        assert_eq!(
            name_differences(&["J", "Delta_v", "phi"], &["J", "phi_loc", "phi"]),
            "missing Delta_v; extra phi_loc"
        );
        assert_eq!(name_differences(&["a", "b"], &["a"]), "missing b");
        assert_eq!(
            name_differences(&["phi_loc", "mu"], &["mu", "phi_loc"]),
            "the same names in another order"
        );
        assert_eq!(name_differences(&["a"], &["a", "a"]), "a name repeated");
    }
}
