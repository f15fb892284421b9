//! `suspflow compare A.csv B.csv`: do two binned profiles of the same scene geometry agree
//! within their statistical errors? For each observable, the mean over bins of the squared
//! z-score `(a - b)^2 / (se_a^2 + se_b^2)` (about 1 when only noise differs, with the
//! standard errors taken at face value) and the relative L2 difference `||a - b|| / ||b||`.
use anyhow::bail;
use schema::columns as dataset_columns;
use schema::columns::{DELTA_V, F_X, J, MU, P, PHI_LOC, SIGMA_XY, THETA, U};
use std::path::{Path, PathBuf};
use surrogate::{agreement, excerpt, Dataset, GROUP_COLUMN};

/// Observables compared by default.
const DEFAULT_COLUMNS: [&str; 9] = [U, SIGMA_XY, P, PHI_LOC, J, MU, THETA, DELTA_V, F_X];

#[derive(clap::Args)]
pub struct Args {
    /// First profile table (`profile.csv` of `simulate`, or a one-run dataset; a file of
    /// several scenes or replicas is refused).
    a: PathBuf,
    /// Second profile table, same bins.
    b: PathBuf,
    /// Observables to compare (each needs `<name>` and `<name>_se` columns).
    #[arg(long = "column")]
    columns: Vec<String>,
}

/// Reads a profile table with the surrogate's dataset reader; refuses a file holding more
/// than one scene, or more than one replica (seed) of a scene: their bins would be compared
/// as one long profile.
fn read_one_scene(path: &Path) -> anyhow::Result<Dataset> {
    let data = Dataset::read_csv(path)?;
    let ids = consecutive_values(&data, GROUP_COLUMN)?;
    if ids.len() > 1 {
        bail!(
            "{} holds {} scenes ({}, ...); compare takes one scene per file (its profile.csv)",
            path.display(),
            ids.len(),
            ids[..2].join(", ")
        );
    }
    let seeds = consecutive_values(&data, dataset_columns::SEED)?;
    if seeds.len() > 1 {
        bail!(
            "{} holds {} runs (seeds {}, ...); compare takes one run per file (or the \
             ensemble table's rows of one scene)",
            path.display(),
            seeds.len(),
            seeds[..2].join(", ")
        );
    }
    Ok(data)
}

/// The values of column `name` with consecutive repeats dropped; none without the column.
fn consecutive_values<'a>(data: &'a Dataset, name: &str) -> anyhow::Result<Vec<&'a str>> {
    if !data.column_names().iter().any(|n| n == name) {
        return Ok(Vec::new());
    }
    let mut values: Vec<&str> = data.text(name)?.iter().map(String::as_str).collect();
    values.dedup();
    Ok(values)
}

/// The column `name` of `data` (empty cells are NaN: undefined in that bin); a cell that is
/// not a finite number, or a negative standard error (`*_se`), is an error naming row and
/// column.
fn column(data: &Dataset, name: &str) -> anyhow::Result<Vec<f64>> {
    data.text(name)?
        .iter()
        .enumerate()
        .map(|(k, cell)| {
            let fail = |what: &str| {
                anyhow::anyhow!(
                    "{} row {}, column `{name}`: `{}` {what}",
                    data.source_name(),
                    k + 1,
                    excerpt(cell)
                )
            };
            if cell.is_empty() {
                return Ok(f64::NAN);
            }
            match cell.parse::<f64>() {
                Ok(v) if !v.is_finite() => Err(fail("is not a finite number")),
                Ok(v) if v < 0.0 && dataset_columns::is_standard_error(name) => {
                    Err(fail("is negative; a standard error cannot be"))
                }
                Ok(v) => Ok(v),
                Err(_) => Err(fail("is not a number")),
            }
        })
        .collect()
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let (ta, tb) = (read_one_scene(&args.a)?, read_one_scene(&args.b)?);
    if ta.n_rows() != tb.n_rows() {
        bail!(
            "{} has {} bins and {} has {}: not the same geometry",
            args.a.display(),
            ta.n_rows(),
            args.b.display(),
            tb.n_rows()
        );
    }
    let (ya, yb) = (
        column(&ta, dataset_columns::Y)?,
        column(&tb, dataset_columns::Y)?,
    );
    if ya
        .iter()
        .zip(&yb)
        .any(|(p, q)| (p - q).abs() > 1e-9 * p.abs().max(1.0))
    {
        bail!(
            "the bin centres y differ between {} and {}",
            args.a.display(),
            args.b.display()
        );
    }
    let columns: Vec<String> = if args.columns.is_empty() {
        DEFAULT_COLUMNS.iter().map(|s| s.to_string()).collect()
    } else {
        args.columns.clone()
    };
    println!(
        "{:<10} {:>8} {:>10} {:>6}",
        "observable", "mean z^2", "rel. L2", "bins"
    );
    for c in &columns {
        let se = dataset_columns::standard_error(c);
        let g = agreement(
            &column(&ta, c)?,
            &column(&ta, &se)?,
            &column(&tb, c)?,
            &column(&tb, &se)?,
        );
        println!(
            "{c:<10} {:>8.2} {:>9.2}% {:>6}",
            g.z2,
            100.0 * g.rel_l2,
            g.bins
        );
    }
    println!(
        "mean z^2 is about 1 when the profiles differ only by noise of the stated standard errors"
    );
    Ok(())
}
