//! A CSV dataset (docs/physics.md section 8): one row per bin per simulation, named columns.
//!
//! Every column keeps its text (used for grouping keys such as `scene_id` or `profile`), and
//! its numbers when every cell parses as one. An empty cell is an undefined value (the
//! simulator leaves `J`, `mu` and `Theta` empty where the bin pressure `P <= 0`): it reads as
//! NaN, [`Dataset::complete_rows`] finds the rows without one, and [`Dataset::matrix`] refuses
//! it. Rows are numbered from 1, counting data rows only (the header is not a data row), in
//! every error message.

use std::collections::HashSet;
use std::path::Path;

use ndarray::Array2;

use crate::data::files;
use crate::error::{Result, SurrogateError};
use schema::excerpt;
use schema::Fingerprint;

/// The column whose value names the simulation a row comes from: the grouping key for
/// cross-validation, so that rows of one simulation never sit on both sides of a split.
pub const GROUP_COLUMN: &str = schema::columns::SCENE_ID;

/// The column whose text names the flow profile of a row: the forcing expression `u_inf(y)`,
/// e.g. `0.2*sin(2*pi*y/L) + 0.1*cos(4*pi*y/L)`, which names both the shape and the
/// amplitude. Rows with the same text form a profile family (the scenes of one forcing at
/// every phi, L_y and seed), the unit that leave-one-family-out cross-validation holds out.
pub const PROFILE_COLUMN: &str = schema::columns::PROFILE;

/// The largest finite f32 (3.4e38), as f64: the models read their inputs as f32, and a
/// value beyond it would become an infinity there.
pub const F32_MAX: f64 = f32::MAX as f64;

/// The UTF-8 byte-order mark some editors put at the start of a CSV file.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// A table read from CSV, with a fingerprint of the bytes it was read from.
#[derive(Debug, Clone)]
pub struct Dataset {
    source_name: String,
    names: Vec<String>,
    columns: Vec<Column>,
    n_rows: usize,
    /// The line of the source on which each data row starts (the header is line 1).
    lines: Vec<u64>,
    fingerprint: Fingerprint,
}

/// One column as read.
#[derive(Debug, Clone)]
struct Column {
    text: Vec<String>,
    /// The parsed values (NaN for an empty cell), or the 0-based index of the first cell that
    /// is neither empty nor a number.
    numbers: std::result::Result<Vec<f64>, usize>,
}

impl Column {
    fn new(text: Vec<String>) -> Self {
        let numbers = text
            .iter()
            .enumerate()
            .map(|(i, cell)| {
                if cell.is_empty() {
                    Ok(f64::NAN)
                } else {
                    cell.parse::<f64>().map_err(|_| i)
                }
            })
            .collect();
        Column { text, numbers }
    }
}

impl Dataset {
    /// Reads a CSV file with a header line.
    pub fn read_csv(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let bytes = files::read(path)?;
        Self::from_csv_bytes(&bytes, &path.display().to_string())
    }

    /// Parses CSV text with a header line (a leading UTF-8 byte-order mark is skipped);
    /// `source_name` names it in error messages. Fails on an empty table, a duplicated column name, or a row with a different number of
    /// fields than the header.
    pub fn from_csv_bytes(bytes: &[u8], source_name: &str) -> Result<Self> {
        let csv_error = |source| SurrogateError::Csv {
            source_name: source_name.to_owned(),
            source,
        };
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes));
        let names: Vec<String> = reader
            .headers()
            .map_err(csv_error)?
            .iter()
            .map(str::to_owned)
            .collect();
        let mut seen = HashSet::new();
        if let Some(duplicate) = names.iter().find(|name| !seen.insert(name.as_str())) {
            return Err(SurrogateError::InvalidArgument(format!(
                "{source_name}: column `{duplicate}` appears twice in the header"
            )));
        }
        let mut cells: Vec<Vec<String>> = vec![Vec::new(); names.len()];
        let mut lines = Vec::new();
        for (index, record) in reader.records().enumerate() {
            let record = record.map_err(csv_error)?;
            lines.push(record.position().map_or(index as u64 + 2, |p| p.line()));
            if record.len() != names.len() {
                return Err(SurrogateError::RaggedRow {
                    source_name: source_name.to_owned(),
                    row: index + 1,
                    expected: names.len(),
                    found: record.len(),
                });
            }
            for (column, field) in cells.iter_mut().zip(record.iter()) {
                column.push(field.to_owned());
            }
        }
        let n_rows = cells.first().map_or(0, Vec::len);
        if n_rows == 0 {
            return Err(SurrogateError::EmptyDataset {
                what: source_name.to_owned(),
            });
        }
        Ok(Dataset {
            source_name: source_name.to_owned(),
            names,
            columns: cells.into_iter().map(Column::new).collect(),
            n_rows,
            lines,
            fingerprint: Fingerprint::of(bytes),
        })
    }

    /// Where the data came from (a path, or the name given to [`Dataset::from_csv_bytes`]).
    pub fn source_name(&self) -> &str {
        &self.source_name
    }

    /// Number of data rows (never 0: a dataset without rows is refused when read).
    pub fn n_rows(&self) -> usize {
        self.n_rows
    }

    /// Column names in header order.
    pub fn column_names(&self) -> &[String] {
        &self.names
    }

    /// This dataset with the column `name` added after the others, its cells `values` (an
    /// empty cell for NaN, an undefined value); the source's name and fingerprint are kept,
    /// since the column is derived from it. Refuses a name already present or a count of
    /// values other than the rows'.
    pub fn with_column(&self, name: &str, values: &[f64]) -> Result<Dataset> {
        if self.names.iter().any(|n| n == name) || values.len() != self.n_rows {
            return Err(SurrogateError::InvalidArgument(format!(
                "{}: cannot add column `{name}` of {} values to {} rows with columns [{}]",
                self.source_name,
                values.len(),
                self.n_rows,
                self.names.join(", ")
            )));
        }
        let text = values
            .iter()
            .map(|v| {
                if v.is_nan() {
                    String::new()
                } else {
                    format!("{v:e}")
                }
            })
            .collect();
        let mut with = self.clone();
        with.names.push(name.to_owned());
        with.columns.push(Column::new(text));
        Ok(with)
    }

    /// The rows `rows` (0-based, in that order) of this dataset, every column kept; the
    /// source's name and fingerprint are kept too (the rows came from it). Refuses an index
    /// out of range or no rows.
    pub fn select_rows(&self, rows: &[usize]) -> Result<Dataset> {
        if rows.is_empty() || rows.iter().any(|&r| r >= self.n_rows) {
            return Err(SurrogateError::InvalidArgument(format!(
                "{}: cannot select rows {:?} of {}",
                self.source_name,
                rows.iter().take(5).collect::<Vec<_>>(),
                self.n_rows
            )));
        }
        let mut with = self.clone();
        with.columns = self
            .columns
            .iter()
            .map(|c| Column::new(rows.iter().map(|&r| c.text[r].clone()).collect()))
            .collect();
        with.lines = rows.iter().map(|&r| self.line(r)).collect();
        with.n_rows = rows.len();
        Ok(with)
    }

    /// The line of the source on which data row `row` (0-based) starts; the header is line 1.
    pub fn line(&self, row: usize) -> u64 {
        self.lines.get(row).copied().unwrap_or(row as u64 + 2)
    }

    /// FNV-1a 64 hash of the CSV bytes the dataset was read from.
    pub fn fingerprint(&self) -> Fingerprint {
        self.fingerprint
    }

    /// The numbers of column `name`, one per row, NaN for an empty cell. NaN and infinities
    /// are returned as they are (a standard error can legitimately be NaN);
    /// [`Dataset::matrix`] refuses them.
    pub fn column(&self, name: &str) -> Result<&[f64]> {
        let column = self.find(name)?;
        column
            .numbers
            .as_deref()
            .map_err(|&index| SurrogateError::NotANumber {
                source_name: self.source_name.clone(),
                row: index + 1,
                column: name.to_owned(),
                text: excerpt(&column.text[index]),
            })
    }

    /// [`Dataset::column`] for readers that draw or tabulate the values: NaN for an empty
    /// cell (an undefined value), and an error naming the row for a cell that spells NaN or
    /// an infinity, which no writer of these tables puts there.
    pub fn defined_column(&self, name: &str) -> Result<&[f64]> {
        let values = self.column(name)?;
        let text = self.text(name)?;
        match values
            .iter()
            .zip(text)
            .position(|(v, t)| !v.is_finite() && !t.is_empty())
        {
            None => Ok(values),
            Some(row) => Err(SurrogateError::NonFinite {
                source_name: self.source_name.clone(),
                row: row + 1,
                column: name.to_owned(),
                value: values[row],
            }),
        }
    }

    /// The cells of column `name` as text, one per row.
    pub fn text(&self, name: &str) -> Result<&[String]> {
        Ok(&self.find(name)?.text)
    }

    /// The grouping key of each row: the text of [`GROUP_COLUMN`]; an empty key is an
    /// error naming its row (a row of no simulation cannot be grouped).
    pub fn group_keys(&self) -> Result<&[String]> {
        self.keys(GROUP_COLUMN, "its simulation")
    }

    /// The profile family of each row: the text of [`PROFILE_COLUMN`], or `None` when the
    /// table has no such column; an empty cell is an error naming its row.
    pub fn family_keys(&self) -> Result<Option<&[String]>> {
        if !self.names.iter().any(|n| n == PROFILE_COLUMN) {
            return Ok(None);
        }
        self.keys(PROFILE_COLUMN, "its forcing profile").map(Some)
    }

    /// The text of key column `name`, refusing an empty cell: every row must name `what`.
    fn keys(&self, name: &str, what: &str) -> Result<&[String]> {
        let keys = self.text(name)?;
        match keys.iter().position(String::is_empty) {
            Some(row) => Err(SurrogateError::InvalidArgument(format!(
                "{}: data row {}, column `{name}` is empty; every row must name {what}",
                self.source_name,
                row + 1
            ))),
            None => Ok(keys),
        }
    }

    /// The columns `names`, in that order, as a rows x columns matrix of finite numbers
    /// within f32's range (see [`Dataset::matrix_of_rows`]).
    pub fn matrix(&self, names: &[&str]) -> Result<Array2<f64>> {
        let all: Vec<usize> = (0..self.n_rows).collect();
        self.matrix_of_rows(names, &all)
    }

    /// The rows `rows` (0-based, in that order) of the columns `names` as a rows x columns
    /// matrix of finite numbers for a model to read; an empty, NaN or infinite cell is an
    /// error naming its row, and so is a value beyond f32's range ([`F32_MAX`]): the trees
    /// (XGBoost's and [`crate::models::forest::Forest`]) read their inputs as f32, in which
    /// it is an infinity.
    pub fn matrix_of_rows(&self, names: &[&str], rows: &[usize]) -> Result<Array2<f64>> {
        if let Some(&bad) = rows.iter().find(|&&row| row >= self.n_rows) {
            return Err(SurrogateError::InvalidArgument(format!(
                "row index {bad} is out of range for {} rows of {}",
                self.n_rows, self.source_name
            )));
        }
        let mut matrix = Array2::zeros((rows.len(), names.len()));
        for (j, &name) in names.iter().enumerate() {
            let (values, text) = (self.column(name)?, self.text(name)?);
            for (i, &row) in rows.iter().enumerate() {
                let value = values[row];
                if text[row].is_empty() {
                    return Err(SurrogateError::EmptyCell {
                        source_name: self.source_name.clone(),
                        row: row + 1,
                        column: name.to_owned(),
                    });
                }
                if !value.is_finite() {
                    return Err(SurrogateError::NonFinite {
                        source_name: self.source_name.clone(),
                        row: row + 1,
                        column: name.to_owned(),
                        value,
                    });
                }
                if value.abs() > F32_MAX {
                    return Err(SurrogateError::BeyondF32 {
                        source_name: self.source_name.clone(),
                        place: format!("line {} (data row {})", self.line(row), row + 1),
                        column: name.to_owned(),
                        value,
                    });
                }
                matrix[[i, j]] = value;
            }
        }
        Ok(matrix)
    }

    /// The rows (0-based, ascending) in which no cell of the columns `names` is empty.
    pub fn complete_rows(&self, names: &[&str]) -> Result<Vec<usize>> {
        let columns = names
            .iter()
            .map(|name| self.text(name))
            .collect::<Result<Vec<_>>>()?;
        Ok((0..self.n_rows)
            .filter(|&row| columns.iter().all(|text| !text[row].is_empty()))
            .collect())
    }

    fn find(&self, name: &str) -> Result<&Column> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|index| &self.columns[index])
            .ok_or_else(|| SurrogateError::MissingColumn {
                source_name: self.source_name.clone(),
                name: name.to_owned(),
                available: self.names.clone(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CSV: &str =
        "scene_id,profile,J,mu_se\ns1,sin,0.1,nan\ns1,sin,0.2,0.01\ns2,cos,0.3,0.02\n";

    #[test]
    fn reads_numbers_text_and_groups() {
        let data = Dataset::from_csv_bytes(CSV.as_bytes(), "t").unwrap();
        assert_eq!(data.n_rows(), 3);
        assert_eq!(data.column("J").unwrap(), &[0.1, 0.2, 0.3]);
        assert_eq!(data.group_keys().unwrap(), &["s1", "s1", "s2"]);
        assert_eq!(data.text("profile").unwrap()[2], "cos");
        assert!(data.column("mu_se").unwrap()[0].is_nan());
        assert_eq!(
            data.matrix(&["J"]).unwrap().column(0).to_vec(),
            vec![0.1, 0.2, 0.3]
        );
    }

    #[test]
    fn text_in_a_numeric_column_names_row_and_column() {
        let data = Dataset::from_csv_bytes(CSV.as_bytes(), "t").unwrap();
        let message = data.column("profile").unwrap_err().to_string();
        assert!(
            message.contains("data row 1")
                && message.contains("`profile`")
                && message.contains("`sin`"),
            "{message}"
        );
    }

    #[test]
    fn ragged_row_and_duplicate_header_are_refused() {
        let ragged = Dataset::from_csv_bytes(b"a,b\n1,2\n3\n", "t").unwrap_err();
        assert!(
            matches!(
                ragged,
                SurrogateError::RaggedRow {
                    row: 2,
                    expected: 2,
                    found: 1,
                    ..
                }
            ),
            "{ragged}"
        );
        let duplicate = Dataset::from_csv_bytes(b"a,a\n1,2\n", "t").unwrap_err();
        assert!(
            duplicate.to_string().contains("`a` appears twice"),
            "{duplicate}"
        );
    }

    #[test]
    fn empty_cells_read_as_nan_are_found_and_refused_in_a_matrix() {
        let data =
            Dataset::from_csv_bytes(b"scene_id,J,mu\ns1,0.1,0.5\ns1,,0.6\ns2,0.3,\n", "t").unwrap();
        assert!(data.column("J").unwrap()[1].is_nan());
        assert_eq!(data.complete_rows(&["J"]).unwrap(), vec![0, 2]);
        assert_eq!(data.complete_rows(&["J", "mu"]).unwrap(), vec![0]);
        assert_eq!(
            data.matrix_of_rows(&["mu", "J"], &[2, 0])
                .unwrap_err()
                .to_string(),
            "t: data row 3, column `mu` is empty (an undefined value)"
        );
        assert_eq!(
            data.matrix_of_rows(&["J", "mu"], &[0])
                .unwrap()
                .row(0)
                .to_vec(),
            vec![0.1, 0.5]
        );
        assert!(matches!(
            data.complete_rows(&["P"]),
            Err(SurrogateError::MissingColumn { .. })
        ));
    }

    #[test]
    fn byte_order_mark_is_skipped() {
        let data = Dataset::from_csv_bytes(b"\xEF\xBB\xBFscene_id,J\ns1,0.1\n", "t").unwrap();
        assert_eq!(data.column_names(), &["scene_id", "J"]);
        assert_eq!(data.group_keys().unwrap(), &["s1"]);
    }

    #[test]
    fn empty_group_key_is_refused_naming_the_row() {
        let data = Dataset::from_csv_bytes(b"scene_id,J\ns1,0.1\n,0.2\n", "t").unwrap();
        let message = data.group_keys().unwrap_err().to_string();
        assert!(
            message.contains("data row 2, column `scene_id` is empty"),
            "{message}"
        );
        let data =
            Dataset::from_csv_bytes(b"scene_id,profile,J\ns1,sin,0.1\ns2,,0.2\n", "t").unwrap();
        let message = data.family_keys().unwrap_err().to_string();
        assert!(
            message.contains("data row 2, column `profile` is empty"),
            "{message}"
        );
        let data = Dataset::from_csv_bytes(b"scene_id,J\ns1,0.1\n", "t").unwrap();
        assert_eq!(data.family_keys().unwrap(), None);
    }

    #[test]
    fn a_huge_cell_is_cut_in_the_message() {
        let cell = "x".repeat(500_000);
        let data = Dataset::from_csv_bytes(format!("J\n{cell}\n").as_bytes(), "t").unwrap();
        let message = data.column("J").unwrap_err().to_string();
        assert!(
            message.len() < 200 && message.contains("... (500000 bytes)"),
            "{message}"
        );
    }

    #[test]
    fn fingerprint_follows_the_bytes() {
        let a = Dataset::from_csv_bytes(b"x\n1\n", "t").unwrap();
        let b = Dataset::from_csv_bytes(b"x\n2\n", "t").unwrap();
        assert_ne!(a.fingerprint(), b.fingerprint());
    }
}
