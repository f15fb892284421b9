//! `suspflow coverage DATA.csv... --out DIR`: which local states the datasets hold. Draws
//! every row of every dataset in the (J, phi_loc) and (J, Theta) planes, J on a logarithmic
//! axis and each dataset in its own colour on the same axes (`DIR/coverage.svg`), and
//! writes the range `[min, max]` of each numeric column of each dataset as a markdown table
//! (`DIR/coverage.md`, also printed). Empty (undefined) cells are left out of the ranges
//! and the figure, and counted in the table.
use crate::plots::scatter_panels::{scatter_panels, PointSet, ScatterPanel};
use anyhow::Context;
use schema::columns as col;
use std::path::{Path, PathBuf};
use surrogate::Dataset;

/// The planes drawn: (horizontal, vertical, logarithmic vertical axis).
const PLANES: [(&str, &str, bool); 2] = [(col::J, col::PHI_LOC, false), (col::J, col::THETA, true)];

#[derive(clap::Args)]
pub struct Args {
    /// Datasets (per-run or ensemble tables), e.g. the training and the validation set.
    #[arg(required = true)]
    data: Vec<PathBuf>,
    /// Directory for `coverage.svg` and `coverage.md` (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Replace the `coverage.svg` and `coverage.md` of an earlier run in `--out`.
    #[arg(long)]
    force: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let datasets = args
        .data
        .iter()
        .map(Dataset::read_csv)
        .collect::<Result<Vec<_>, _>>()?;
    let _lock = crate::output_guard::claim_dir(&args.out, "`suspflow coverage`")?;
    let (figure, markdown) = (args.out.join("coverage.svg"), args.out.join("coverage.md"));
    crate::output_guard::refuse_any_unless_force(
        &[figure.clone(), markdown.clone()],
        args.force,
        "the output of `suspflow coverage`",
        "choose another --out",
    )?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let names: Vec<String> = args.data.iter().map(|p| file_name(p)).collect();
    let mut panels = Vec::new();
    for (x, y, log_y) in PLANES {
        let mut sets = Vec::new();
        for (data, name) in datasets.iter().zip(&names) {
            let (xs, ys) = (data.defined_column(x)?, data.defined_column(y)?);
            sets.push(PointSet {
                name: format!("{name} ({} rows)", data.n_rows()),
                points: xs.iter().copied().zip(ys.iter().copied()).collect(),
            });
        }
        panels.push(ScatterPanel {
            x_label: x.to_string(),
            y_label: y.to_string(),
            log_y,
            sets,
        });
    }
    scatter_panels(
        &figure,
        "rows of each dataset in the (J, phi_loc) and (J, Theta) planes",
        &panels,
    )?;
    let table = ranges_table(&datasets, &names)?;
    schema::write_atomic(&markdown, table.as_bytes())?;
    print!("{table}");
    println!("\n{}\n{}", figure.display(), markdown.display());
    Ok(())
}

/// The last component of `path`, for labels.
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    )
}

/// The markdown table of column ranges: one row per numeric column (in order of first
/// appearance), one cell per dataset: `[min, max]`, then `, k empty` when k cells are empty;
/// `-` where the dataset lacks the column or holds text in it. A cell spelling NaN or an
/// infinity is an error (only an empty cell is an undefined value).
fn ranges_table(datasets: &[Dataset], names: &[String]) -> anyhow::Result<String> {
    let mut columns: Vec<&str> = Vec::new();
    for data in datasets {
        for name in data.column_names() {
            if !columns.contains(&name.as_str()) && data.column(name).is_ok() {
                columns.push(name);
            }
        }
    }
    let mut text = format!("| column | {} |\n|---|", names.join(" | "));
    text += &"---|".repeat(names.len());
    text.push('\n');
    for name in columns {
        let cells = datasets
            .iter()
            .map(|data| match data.column(name) {
                Err(_) => Ok("-".to_string()),
                Ok(_) => Ok(range_cell(data.defined_column(name)?)),
            })
            .collect::<anyhow::Result<Vec<String>>>()?;
        text += &format!("| `{name}` | {} |\n", cells.join(" | "));
    }
    Ok(text)
}

/// `[min, max]` of the finite values (empty cells read as NaN), with the count of empty ones.
fn range_cell(values: &[f64]) -> String {
    let defined: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let empty = values.len() - defined.len();
    let range = if defined.is_empty() {
        "no value".to_string()
    } else {
        let lo = defined.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = defined.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        format!("[{}, {}]", significant(lo), significant(hi))
    };
    if empty > 0 {
        format!("{range}, {empty} empty")
    } else {
        range
    }
}

/// `v` as written when that is short (at most 6 characters, e.g. `0.54`, `100`), else with
/// four significant digits, in exponent form outside [1e-3, 1e5).
fn significant(v: f64) -> String {
    let plain = v.to_string();
    // Zero is always short: log10 below never sees it.
    if plain.len() <= 6 {
        plain
    } else if (1e-3..1e5).contains(&v.abs()) {
        let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_keep_four_significant_digits_and_count_empty_cells() {
        assert_eq!(significant(0.43217), "0.4322");
        assert_eq!(significant(100.0), "100");
        assert_eq!(significant(0.5600000001), "0.5600");
        assert_eq!(significant(2.5e-5), "2.500e-5");
        assert_eq!(significant(-0.0), "-0");
        assert_eq!(range_cell(&[0.5, f64::NAN, -1.25]), "[-1.25, 0.5], 1 empty");
        assert_eq!(range_cell(&[f64::NAN]), "no value, 1 empty");
    }
}
