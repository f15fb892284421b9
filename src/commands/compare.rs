//! `suspflow compare A.csv B.csv`: do two binned profiles of the same scene geometry agree
//! within their statistical errors? For each observable, the mean over bins of the squared
//! z-score `(a - b)^2 / (se_a^2 + se_b^2)` (about 1 when only noise differs, with the
//! standard errors taken at face value) and the relative L2 difference `||a - b|| / ||b||`.
use anyhow::{bail, Context};
use sim::output::dataset_columns;
use sim::output::dataset_columns::{DELTA_V, F_X, J, MU, P, PHI_LOC, SIGMA_XY, THETA, U};
use std::path::{Path, PathBuf};
use surrogate::{excerpt, GROUP_COLUMN};

/// Observables compared by default.
const DEFAULT_COLUMNS: [&str; 9] = [U, SIGMA_XY, P, PHI_LOC, J, MU, THETA, DELTA_V, F_X];

#[derive(clap::Args)]
pub struct Args {
    /// First profile table (`profile.csv` of `simulate`, or a one-scene dataset; a file of
    /// several scenes is refused).
    a: PathBuf,
    /// Second profile table, same bins.
    b: PathBuf,
    /// Observables to compare (each needs `<name>` and `<name>_se` columns).
    #[arg(long = "column")]
    columns: Vec<String>,
}

/// A profile table's columns by name.
struct Table {
    names: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// Reads `path` (a leading UTF-8 byte-order mark is dropped); refuses a file holding
    /// more than one scene.
    fn read(path: &Path) -> anyhow::Result<Table> {
        let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
        let mut reader =
            csv::Reader::from_reader(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes));
        let names = reader
            .headers()
            .with_context(|| format!("reading {}", path.display()))?
            .iter()
            .map(String::from)
            .collect();
        let rows = reader
            .records()
            .map(|r| r.map(|r| r.iter().map(String::from).collect()))
            .collect::<Result<Vec<Vec<String>>, _>>()
            .with_context(|| format!("reading {}", path.display()))?;
        let table = Table { names, rows };
        table.one_scene(path)?;
        Ok(table)
    }

    /// Fails if the table's `scene_id` column names more than one scene: their bins would
    /// be compared as one long profile.
    fn one_scene(&self, path: &Path) -> anyhow::Result<()> {
        let Some(c) = self.names.iter().position(|n| n == GROUP_COLUMN) else {
            return Ok(());
        };
        let mut ids: Vec<&str> = self
            .rows
            .iter()
            .filter_map(|r| r.get(c))
            .map(String::as_str)
            .collect();
        ids.dedup();
        if ids.len() > 1 {
            bail!(
                "{} holds {} scenes ({}, ...); compare takes one scene per file (its profile.csv)",
                path.display(),
                ids.len(),
                ids[..2].join(", ")
            );
        }
        Ok(())
    }

    /// The column `name` (empty cells are NaN: undefined in that bin); a cell that is not a
    /// finite number, or a negative standard error (`*_se`), is an error naming row and column.
    fn column(&self, name: &str, path: &Path) -> anyhow::Result<Vec<f64>> {
        let c = self
            .names
            .iter()
            .position(|n| n == name)
            .with_context(|| format!("{} has no column `{name}`", path.display()))?;
        self.rows
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let cell = r.get(c).map(String::as_str).unwrap_or("");
                let fail = |what: &str| {
                    anyhow::anyhow!(
                        "{} row {}, column `{name}`: `{}` {what}",
                        path.display(),
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
}

/// Agreement of one observable: mean squared z-score and relative L2 difference over the
/// bins where both are defined, and how many bins that is.
pub struct Agreement {
    pub z2: f64,
    pub rel_l2: f64,
    pub bins: usize,
}

/// Compares `a` against `b` (with standard errors `sa`, `sb`), skipping undefined bins.
pub fn agreement(a: &[f64], sa: &[f64], b: &[f64], sb: &[f64]) -> Agreement {
    let (mut z2, mut diff2, mut norm2, mut bins) = (0.0, 0.0, 0.0, 0);
    for k in 0..a.len() {
        let (d, var) = (a[k] - b[k], sa[k] * sa[k] + sb[k] * sb[k]);
        if d.is_finite() && var.is_finite() {
            if var > 0.0 {
                z2 += d * d / var;
            }
            diff2 += d * d;
            norm2 += b[k] * b[k];
            bins += 1;
        }
    }
    Agreement {
        z2: z2 / bins.max(1) as f64,
        rel_l2: (diff2 / norm2).sqrt(),
        bins,
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let (ta, tb) = (Table::read(&args.a)?, Table::read(&args.b)?);
    if ta.rows.len() != tb.rows.len() {
        bail!(
            "{} has {} bins and {} has {}: not the same geometry",
            args.a.display(),
            ta.rows.len(),
            args.b.display(),
            tb.rows.len()
        );
    }
    let (ya, yb) = (ta.column("y", &args.a)?, tb.column("y", &args.b)?);
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
            &ta.column(c, &args.a)?,
            &ta.column(&se, &args.a)?,
            &tb.column(c, &args.b)?,
            &tb.column(&se, &args.b)?,
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
