//! The table `suspflow predict` writes: the input table with each row's predictions, their
//! interval bounds and the training-domain check (docs/commands.md).

use schema::columns as col;

use crate::data::dataset::Dataset;
use crate::data::training_domain::DomainCheck;
use crate::error::{Result, SurrogateError};
use crate::models::predictor::Prediction;

/// A model's predictions for the rows of `dataset`, ready to be written.
pub struct PredictionTable<'a> {
    pub dataset: &'a Dataset,
    /// The model's output names, in the order of the prediction's columns.
    pub outputs: &'a [String],
    pub prediction: &'a Prediction,
    pub domain: &'a [DomainCheck],
}

impl PredictionTable<'_> {
    /// The names of the columns added after the input's: `<output>_pred` per output, then
    /// `<output>_lower` and `<output>_upper` per output when the prediction has intervals, then
    /// `in_domain` and `domain_distance`.
    pub fn added_columns(&self) -> Vec<String> {
        let suffixed = |suffix: &str| -> Vec<String> {
            self.outputs
                .iter()
                .map(|o| format!("{o}{suffix}"))
                .collect()
        };
        let mut added = suffixed(col::PREDICTED_SUFFIX);
        if self.prediction.intervals.is_some() {
            for output in self.outputs {
                added.push(format!("{output}{}", col::LOWER_SUFFIX));
                added.push(format!("{output}{}", col::UPPER_SUFFIX));
            }
        }
        added.extend([col::IN_DOMAIN.to_owned(), col::DOMAIN_DISTANCE.to_owned()]);
        added
    }

    /// The CSV text: every input column as read, then [`PredictionTable::added_columns`]
    /// (numbers in `{:e}`, shortest round trip). Refuses an input that already has one of the
    /// added names (the output of an earlier `predict`), whose columns would repeat.
    pub fn to_csv(&self) -> Result<String> {
        let names = self.dataset.column_names();
        let added = self.added_columns();
        if let Some(taken) = added.iter().find(|a| names.contains(a)) {
            return Err(SurrogateError::InvalidArgument(format!(
                "{} already has a column `{taken}` (the output of an earlier predict?): the \
                 predictions would repeat its name; give the table without it",
                self.dataset.source_name()
            )));
        }
        let columns = names
            .iter()
            .map(|n| self.dataset.text(n))
            .collect::<Result<Vec<_>>>()?;
        let csv_error = |source| SurrogateError::Csv {
            source_name: "the prediction table".to_owned(),
            source,
        };
        let mut writer = csv::Writer::from_writer(Vec::new());
        writer
            .write_record(names.iter().chain(&added))
            .map_err(csv_error)?;
        let p = self.prediction;
        for (row, check) in self.domain.iter().enumerate() {
            let mut cells: Vec<String> = columns.iter().map(|c| c[row].clone()).collect();
            cells.extend(p.values.row(row).iter().map(|x| format!("{x:e}")));
            if let Some(intervals) = &p.intervals {
                for j in 0..self.outputs.len() {
                    cells.push(format!("{:e}", intervals.lower[[row, j]]));
                    cells.push(format!("{:e}", intervals.upper[[row, j]]));
                }
            }
            cells.extend([check.inside().to_string(), format!("{:e}", check.distance)]);
            writer.write_record(&cells).map_err(csv_error)?;
        }
        let bytes = writer.into_inner().map_err(|e| {
            SurrogateError::InvalidArgument(format!("writing the prediction table: {e}"))
        })?;
        String::from_utf8(bytes).map_err(|e| SurrogateError::InvalidArgument(e.to_string()))
    }
}
