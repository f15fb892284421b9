//! The flow curves of a grid of homogeneous-shear runs (docs/physics.md sections 10 and
//! 11): the finished runs' points ([`FlowRuns`]), or the table written of them earlier,
//! with the Green-Kubo replicas of the grid's volume fractions, the curve fitted (the Green-Kubo estimate kept at each curve's lowest
//! Peclet number) and the jamming law's fits per state `(mu_p, Pe)` (`surrogate::StateFits`).
//! The command and Python render them.
use crate::error::{Result, RheometryError};
use crate::flow_points::{replicas, FlowCurveRow, FlowRuns};
use crate::green_kubo::GreenKuboResult;
use sim::input::grid::Grid;
use std::path::{Path, PathBuf};
use surrogate::{
    green_kubo_matches, keep_green_kubo_at_lowest_peclet, states, StateFits, StatePoint,
};

/// Where a grid's flow curves are read from.
#[derive(Clone, Copy)]
pub enum FlowCurveSource<'a> {
    /// The work directories of `generate`: one, or one per shard of the grid, in the
    /// shards' order.
    Runs(&'a [PathBuf]),
    /// A table written earlier from the runs (`flow_curves.csv`).
    Table(&'a Path),
    /// Such a table with the runs finished in the work directories `runs` in place of its
    /// lines of the same scenes (part of a grid run again, after a change of the code, say).
    Updated {
        table: &'a Path,
        runs: &'a [PathBuf],
    },
}

impl<'a> FlowCurveSource<'a> {
    /// The source of an earlier table `table` and the work directories `runs`, either of
    /// which may be absent: the table alone, the runs alone, or the runs in place of the
    /// table's lines.
    pub fn new(table: Option<&'a Path>, runs: &'a [PathBuf]) -> Self {
        match (table, runs.is_empty()) {
            (Some(table), true) => Self::Table(table),
            (Some(table), false) => Self::Updated { table, runs },
            (None, _) => Self::Runs(runs),
        }
    }
}

/// The flow curves of the finished runs of a grid.
pub struct FlowCurves {
    /// Each finished run's line of `flow_curves.csv`, in grid order.
    pub rows: Vec<FlowCurveRow>,
    /// Labels of the grid's runs not finished.
    pub missing: Vec<String>,
    /// The points fitted.
    pub curve: Vec<StatePoint>,
    /// One per state, in the order of `surrogate::states`.
    pub fits: Vec<StateFits>,
}

impl FlowCurves {
    /// The curves of the runs of `grid` read from `source`, with the Green-Kubo results
    /// `green_kubo` (replicas of the grid's volume fractions), as [`Self::fit`],
    /// [`Self::from_table`] and [`Self::updated`] make them.
    pub fn read(
        grid: &Grid,
        source: FlowCurveSource,
        green_kubo: &[(PathBuf, GreenKuboResult)],
    ) -> Result<Self> {
        let runs = |dirs| {
            let results: Vec<_> = green_kubo.iter().map(|(_, r)| r.clone()).collect();
            FlowRuns::read(grid, dirs, &results)
        };
        match source {
            FlowCurveSource::Runs(dirs) => Self::fit(runs(dirs)?, green_kubo),
            FlowCurveSource::Table(table) => Self::from_table(grid, table, green_kubo),
            FlowCurveSource::Updated { table, runs: dirs } => {
                Self::updated(grid, table, runs(dirs)?, green_kubo)
            }
        }
    }

    /// The curves of `runs`, with the Green-Kubo results `green_kubo` (replicas of the grid's
    /// volume fractions). Refuses a result whose volume fraction is that of no finished run.
    fn fit(runs: FlowRuns, green_kubo: &[(PathBuf, GreenKuboResult)]) -> Result<Self> {
        let FlowRuns { points, missing } = runs;
        let rows = points.iter().map(FlowCurveRow::of).collect();
        let curve = points.iter().map(|p| p.point).collect();
        Self::assemble(rows, missing, curve, green_kubo)
    }

    /// The curves of the table `table` written earlier (`flow_curves.csv`) for the runs of
    /// `grid`, with the Green-Kubo results `green_kubo`: the same curves and fits as from
    /// the runs themselves, without them. Refuses a line of a scene that is not the grid's,
    /// and Green-Kubo results as [`Self::fit`] does.
    fn from_table(
        grid: &Grid,
        table: &Path,
        green_kubo: &[(PathBuf, GreenKuboResult)],
    ) -> Result<Self> {
        let lines = table_points(grid, table, green_kubo)?;
        let missing = grid
            .runs
            .iter()
            .filter(|gs| !lines.iter().any(|(row, _)| row.scene_id == gs.id))
            .map(|gs| gs.label())
            .collect();
        let (rows, curve) = lines.into_iter().unzip();
        Self::assemble(rows, missing, curve, green_kubo)
    }

    /// The curves of the table `table` written earlier for the runs of `grid`, with the
    /// finished runs of `runs` in place of the table's lines of the same scenes (part of a
    /// grid run again, after a change of the code, say; each line keeps its run's
    /// `code_version`), in grid order. Refuses the table as [`Self::from_table`] and
    /// Green-Kubo results as [`Self::fit`] do.
    fn updated(
        grid: &Grid,
        table: &Path,
        runs: FlowRuns,
        green_kubo: &[(PathBuf, GreenKuboResult)],
    ) -> Result<Self> {
        let mut earlier = table_points(grid, table, green_kubo)?;
        let mut again = runs.points;
        let (mut rows, mut curve, mut missing) = (Vec::new(), Vec::new(), Vec::new());
        for gs in &grid.runs {
            let line = match again.iter().position(|p| p.id == gs.id) {
                Some(i) => {
                    let p = again.swap_remove(i);
                    Some((FlowCurveRow::of(&p), p.point))
                }
                None => earlier
                    .iter()
                    .position(|(row, _)| row.scene_id == gs.id)
                    .map(|i| earlier.swap_remove(i)),
            };
            match line {
                Some((row, point)) => {
                    rows.push(row);
                    curve.push(point);
                }
                None => missing.push(gs.label()),
            }
        }
        Self::assemble(rows, missing, curve, green_kubo)
    }

    /// The curves of the points `curve` (lines `rows`): the Green-Kubo viscosity kept at each
    /// curve's lowest Peclet number and the jamming law fitted per state. Refuses a
    /// Green-Kubo result whose volume fraction is that of no point.
    fn assemble(
        rows: Vec<FlowCurveRow>,
        missing: Vec<String>,
        mut curve: Vec<StatePoint>,
        green_kubo: &[(PathBuf, GreenKuboResult)],
    ) -> Result<Self> {
        let unmatched = green_kubo.iter().find(|(_, g)| {
            !curve
                .iter()
                .any(|p| green_kubo_matches(g.phi_actual, p.phi_actual))
        });
        if let Some((path, result)) = unmatched {
            let mut phis: Vec<String> = curve
                .iter()
                .map(|p| format!("{:.4}", p.phi_actual))
                .collect();
            phis.sort();
            phis.dedup();
            return Err(RheometryError::File {
                path: path.display().to_string(),
                message: format!(
                    "its volume fraction {:.4} is that of no finished run (theirs: {}); give \
                     the Green-Kubo runs of the grid's volume fractions",
                    result.phi_actual,
                    phis.join(", ")
                ),
            });
        }
        keep_green_kubo_at_lowest_peclet(&mut curve);
        let fits = states(&curve)
            .into_iter()
            .map(|state| StateFits::fit(&curve, state))
            .collect();
        Ok(FlowCurves {
            rows,
            missing,
            curve,
            fits,
        })
    }
}

/// The lines of the table `table` written earlier for the runs of `grid`, each with its
/// point (the Green-Kubo viscosity of `green_kubo` at its volume fraction) and its
/// contacts from the grid. Refuses a line of a scene that is not the grid's, or whose
/// recorded state is not its scene's ([`FlowCurveRow::of_grid`]).
fn table_points(
    grid: &Grid,
    table: &Path,
    green_kubo: &[(PathBuf, GreenKuboResult)],
) -> Result<Vec<(FlowCurveRow, StatePoint)>> {
    let results: Vec<GreenKuboResult> = green_kubo.iter().map(|(_, r)| r.clone()).collect();
    let replicas = replicas(&results);
    let refused = |message| RheometryError::File {
        path: table.display().to_string(),
        message,
    };
    FlowCurveRow::read_all(table)?
        .into_iter()
        .map(|row| {
            let gs = grid
                .runs
                .iter()
                .find(|gs| gs.id == row.scene_id)
                .ok_or_else(|| {
                    refused(format!(
                        "holds scene {}, which grid `{}` does not have: give the grid the table \
                     was made of",
                        row.scene_id, grid.name
                    ))
                })?;
            let row = row.of_grid(gs).map_err(|reason| {
                refused(format!(
                    "{reason} in grid `{}`: give the grid the table was made of",
                    grid.name
                ))
            })?;
            let point = row.point(gs, &replicas);
            Ok((row, point))
        })
        .collect()
}

/// The Green-Kubo results in the folders `dirs`, each with its folder. Refuses a folder
/// given twice, or two with the same result (a copied folder): each would count as a
/// replica, and the spread between replicas, the error, would vanish.
pub fn read_green_kubo_replicas(dirs: &[PathBuf]) -> Result<Vec<(PathBuf, GreenKuboResult)>> {
    let mut replicas: Vec<(PathBuf, GreenKuboResult)> = Vec::with_capacity(dirs.len());
    for dir in dirs {
        let result = GreenKuboResult::read(dir)?;
        let same = |(other, r): &(PathBuf, GreenKuboResult)| {
            *r == result || canonical(other) == canonical(dir)
        };
        if let Some((other, _)) = replicas.iter().find(|r| same(r)) {
            return Err(RheometryError::File {
                path: other.display().to_string(),
                message: format!(
                    "and {} are the same run: each replica counts once (the error is their \
                     spread)",
                    dir.display()
                ),
            });
        }
        replicas.push((dir.clone(), result));
    }
    Ok(replicas)
}

/// `path` made absolute with links resolved, when it exists.
fn canonical(path: &Path) -> Option<PathBuf> {
    std::fs::canonicalize(path).ok()
}
