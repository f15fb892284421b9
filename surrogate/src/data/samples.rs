//! The rows of a dataset as one mapping sees them: features, outputs, simulation groups and
//! profile families.

use ndarray::{Array2, Axis};

use crate::data::dataset::Dataset;
use crate::data::mapping::Mapping;
use crate::error::{Result, SurrogateError};

/// Feature and output matrices of one mapping, with the group (simulation) and the profile
/// family of each row and the row's number in the source dataset (from 1), for error messages. Rows with an empty
/// (undefined) cell in one of the mapping's columns are left out and counted.
#[derive(Debug, Clone)]
pub struct Samples {
    /// Where the rows came from.
    pub source_name: String,
    /// FNV-1a 64 hash of the source file's bytes.
    pub source_fingerprint: u64,
    pub feature_names: Vec<String>,
    pub output_names: Vec<String>,
    /// Rows x features, all finite.
    pub features: Array2<f64>,
    /// Rows x outputs, all finite, in original units.
    pub outputs: Array2<f64>,
    /// Grouping key of each row (see [`crate::data::dataset::GROUP_COLUMN`]).
    pub groups: Vec<String>,
    /// Profile family of each row: the text of [`crate::data::dataset::PROFILE_COLUMN`], the forcing
    /// expression, which names both its shape and its amplitude; `None` when the source has
    /// no such column.
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
        let columns: Vec<&str> = mapping
            .features
            .iter()
            .chain(mapping.outputs)
            .copied()
            .collect();
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
        Ok(Samples {
            source_name: dataset.source_name().to_owned(),
            source_fingerprint: dataset.fingerprint(),
            feature_names: mapping.features.iter().map(|&s| s.to_owned()).collect(),
            output_names: mapping.outputs.iter().map(|&s| s.to_owned()).collect(),
            features: dataset.matrix_of_rows(mapping.features, &rows)?,
            outputs: dataset.matrix_of_rows(mapping.outputs, &rows)?,
            groups: rows.iter().map(|&row| keys[row].clone()).collect(),
            families: families.map(|f| rows.iter().map(|&row| f[row].clone()).collect()),
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
