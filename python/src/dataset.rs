//! Tables in and out: a CSV file or CSV bytes read by `surrogate::Dataset` (the reader of
//! every command), and a dataset's columns handed to Python.
use crate::error::Error;
use pyo3::prelude::*;
use std::path::PathBuf;
use surrogate::{Dataset, TableKind};

/// A table given from Python: a path, or the bytes of a CSV text (a DataFrame's `to_csv`).
#[derive(FromPyObject)]
pub enum Table {
    Bytes(Vec<u8>),
    Path(PathBuf),
}

/// Reads `table`.
pub fn dataset(table: Table) -> Result<Dataset, Error> {
    Ok(match table {
        Table::Bytes(bytes) => Dataset::from_csv_bytes(&bytes, "the DataFrame")?,
        Table::Path(path) => Dataset::read_csv(path)?,
    })
}

/// One column of a dataset: integers for a column of whole numbers
/// ([`schema::columns::INTEGER_COLUMNS`], e.g. `seed`), numbers (NaN for an empty cell)
/// when every cell is one, text otherwise.
#[derive(IntoPyObject)]
pub enum ColumnValues {
    Integers(Vec<i64>),
    Numbers(Vec<f64>),
    Text(Vec<String>),
}

/// `numbers` as integers when every one is a whole number within i64's range.
fn integers(numbers: &[f64]) -> Option<Vec<i64>> {
    let whole = |x: f64| x.fract() == 0.0 && x.abs() < 9.0e15;
    numbers
        .iter()
        .all(|&x| whole(x))
        .then(|| numbers.iter().map(|&x| x as i64).collect())
}

/// The columns of the dataset at `path` (per-run table or ensemble table, `docs/physics.md`
/// section 8 columns) in file order, and the table's kind (`runs`, `ensemble`, or None for a
/// table without scene ids) with its description.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn read_dataset(
    path: PathBuf,
) -> Result<(Vec<(String, ColumnValues)>, Option<(String, String)>), Error> {
    let data = Dataset::read_csv(&path)?;
    let mut columns = Vec::new();
    for name in data.column_names() {
        let integer = schema::columns::INTEGER_COLUMNS.contains(&name.as_str());
        let values = match data.column(name) {
            Ok(numbers) => match integers(numbers).filter(|_| integer) {
                Some(whole) => ColumnValues::Integers(whole),
                None => ColumnValues::Numbers(numbers.to_vec()),
            },
            Err(_) => ColumnValues::Text(data.text(name)?.to_vec()),
        };
        columns.push((name.clone(), values));
    }
    let kind = TableKind::of(&data).ok().map(|k| {
        let name = match k {
            TableKind::Runs { .. } => "runs",
            TableKind::Ensemble { .. } => "ensemble",
        };
        (name.to_owned(), k.describe())
    });
    Ok((columns, kind))
}
