//! The rows of a dataset as one mapping sees them: features, outputs, simulation groups and
//! profile families.

use ndarray::{Array2, Axis};

use crate::data::dataset::Dataset;
use crate::data::extremum_distance::with_derived_features;
use crate::data::mapping::Mapping;
use crate::data::physical_range::measured_range;
use crate::error::{Result, SurrogateError};

/// Feature and output matrices of one mapping, with the group (simulation) and the profile
/// family of each row and the row's number in the source dataset (from 1), for error messages. Rows with an empty
/// (undefined) cell in one of the mapping's columns are left out and counted.
#[derive(Debug, Clone)]
pub struct Samples {
    /// Where the rows came from.
    pub source_name: String,
    /// FNV-1a 64 hash of the source file's bytes.
    pub source_fingerprint: schema::Fingerprint,
    pub feature_names: Vec<String>,
    pub output_names: Vec<String>,
    /// Rows x features, all finite.
    pub features: Array2<f64>,
    /// Rows x outputs, all finite, in original units.
    pub outputs: Array2<f64>,
    /// Grouping key of each row (see [`crate::data::dataset::GROUP_COLUMN`]).
    pub groups: Vec<String>,
    /// Profile family of each row: the text of [`crate::data::dataset::PROFILE_COLUMN`], the forcing
    /// expression, which names both its shape and its amplitude (texts that differ only in
    /// whitespace are one family, named as its first row spells it); `None` when the source
    /// has no such column.
    pub families: Option<Vec<String>>,
    /// 1-based data row of each row in the source dataset.
    pub data_rows: Vec<usize>,
    /// Rows of the source dataset left out because one of the mapping's cells is empty.
    pub skipped_rows: usize,
}

impl Samples {
    /// Selects `mapping`'s feature and output columns and the group keys of `dataset`, in
    /// the rows where none of those cells is empty. Text, NaN or an infinity in any of those
    /// cells is an error naming its row, and so is a dataset left without rows.
    pub fn from_dataset(dataset: &Dataset, mapping: &Mapping) -> Result<Self> {
        let dataset = &*with_derived_features(dataset, mapping.features)?;
        let columns = mapping.columns();
        let rows = dataset.complete_rows(&columns)?;
        if rows.is_empty() {
            return Err(SurrogateError::EmptyDataset {
                what: format!(
                    "{} (every row has an empty cell in one of {})",
                    dataset.source_name(),
                    columns.join(", ")
                ),
            });
        }
        let keys = dataset.group_keys()?;
        let families = dataset.family_keys()?;
        let features = dataset.matrix_of_rows(mapping.features, &rows)?;
        let outputs = dataset.matrix_of_rows(mapping.outputs, &rows)?;
        for (names, matrix) in [(mapping.features, &features), (mapping.outputs, &outputs)] {
            check_measured_ranges(dataset.source_name(), names, matrix, &rows)?;
        }
        Ok(Samples {
            source_name: dataset.source_name().to_owned(),
            source_fingerprint: dataset.fingerprint(),
            feature_names: mapping.features.iter().map(|&s| s.to_owned()).collect(),
            output_names: mapping.outputs.iter().map(|&s| s.to_owned()).collect(),
            features,
            outputs,
            groups: rows.iter().map(|&row| keys[row].clone()).collect(),
            families: families.map(|f| one_spelling_per_family(rows.iter().map(|&row| &f[row]))),
            data_rows: rows.iter().map(|&row| row + 1).collect(),
            skipped_rows: dataset.n_rows() - rows.len(),
        })
    }

    /// Number of rows.
    pub fn n_rows(&self) -> usize {
        self.groups.len()
    }

    /// The rows `rows` (0-based indices into these samples), in that order; `skipped_rows`
    /// still counts the rows the source lost to empty cells.
    pub fn subset(&self, rows: &[usize]) -> Result<Self> {
        if let Some(&bad) = rows.iter().find(|&&row| row >= self.n_rows()) {
            return Err(SurrogateError::InvalidArgument(format!(
                "row index {bad} is out of range for {} rows of {}",
                self.n_rows(),
                self.source_name
            )));
        }
        Ok(Samples {
            source_name: self.source_name.clone(),
            source_fingerprint: self.source_fingerprint,
            feature_names: self.feature_names.clone(),
            output_names: self.output_names.clone(),
            features: self.features.select(Axis(0), rows),
            outputs: self.outputs.select(Axis(0), rows),
            groups: rows.iter().map(|&row| self.groups[row].clone()).collect(),
            families: self
                .families
                .as_ref()
                .map(|f| rows.iter().map(|&row| f[row].clone()).collect()),
            data_rows: rows.iter().map(|&row| self.data_rows[row]).collect(),
            skipped_rows: self.skipped_rows,
        })
    }
}

/// Fails on the first value of `matrix` (columns `names`, rows from dataset rows `rows`)
/// outside its column's [`measured_range`], naming the data row.
fn check_measured_ranges(
    source_name: &str,
    names: &[&str],
    matrix: &Array2<f64>,
    rows: &[usize],
) -> Result<()> {
    for (&name, column) in names.iter().zip(matrix.axis_iter(Axis(1))) {
        let Some((range, reason)) = measured_range(name) else {
            continue;
        };
        if let Some((i, &value)) = column
            .iter()
            .enumerate()
            .find(|(_, &v)| !(range.min..=range.max).contains(&v))
        {
            return Err(SurrogateError::Unphysical {
                source_name: source_name.to_owned(),
                row: rows[i] + 1,
                column: name.to_owned(),
                value,
                range: reason.to_owned(),
            });
        }
    }
    Ok(())
}

/// The family of each profile text, spelled as its first row spells it: texts that differ
/// only in whitespace (`0.1*sin(y) ` and `0.1*sin(y)`, `a+b` and `a + b`) are one forcing,
/// and two families would put the same flow on both sides of a cross-validation fold.
fn one_spelling_per_family<'a>(profiles: impl Iterator<Item = &'a String>) -> Vec<String> {
    let mut first: std::collections::HashMap<String, &'a String> = Default::default();
    profiles
        .map(|p| {
            let key: String = p.chars().filter(|c| !c.is_whitespace()).collect();
            (*first.entry(key).or_insert(p)).clone()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_differing_only_in_whitespace_are_one_family() {
        let profiles: Vec<String> = ["a + b", "a+b", "c", " a +b ", "c "]
            .iter()
            .map(|p| p.to_string())
            .collect();
        assert_eq!(
            one_spelling_per_family(profiles.iter()),
            ["a + b", "a + b", "c", "a + b", "c"]
        );
    }
}
