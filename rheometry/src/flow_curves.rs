//! The flow curves of a grid of homogeneous-shear runs (docs/physics.md sections 10 and
//! 11): the finished runs' points ([`FlowRuns`]) with the Green-Kubo replicas of the grid's
//! volume fractions, the curve fitted (the Green-Kubo estimate kept at each curve's lowest
//! Peclet number) and the jamming law's fits per state `(mu_p, Pe)` (`surrogate::StateFits`).
//! The command and Python render them.
use crate::error::{Result, RheometryError};
use crate::flow_points::{FlowPoint, FlowRuns};
use crate::green_kubo::GreenKuboResult;
use std::path::{Path, PathBuf};
use surrogate::{keep_green_kubo_at_lowest_peclet, states, StateFits, StatePoint};

/// The flow curves of the finished runs of a grid.
pub struct FlowCurves {
    /// Each finished run's point, in grid order.
    pub points: Vec<FlowPoint>,
    /// Labels of the grid's runs not finished.
    pub missing: Vec<String>,
    /// The points fitted.
    pub curve: Vec<StatePoint>,
    /// One per state, in the order of `surrogate::states`.
    pub fits: Vec<StateFits>,
}

impl FlowCurves {
    /// The curves of `runs`, with the Green-Kubo results `green_kubo` (replicas of the grid's
    /// volume fractions). Refuses a result whose volume fraction is that of no finished run.
    pub fn fit(runs: FlowRuns, green_kubo: &[(PathBuf, GreenKuboResult)]) -> Result<Self> {
        let results: Vec<GreenKuboResult> = green_kubo.iter().map(|(_, r)| r.clone()).collect();
        if let Some(&k) = runs.unmatched(&results).first() {
            let mut phis: Vec<String> = runs
                .points
                .iter()
                .map(|p| format!("{:.4}", p.point.phi_actual))
                .collect();
            phis.sort();
            phis.dedup();
            return Err(RheometryError::File {
                path: green_kubo[k].0.display().to_string(),
                message: format!(
                    "its volume fraction {:.4} is that of no finished run (theirs: {}); give \
                     the Green-Kubo runs of the grid's volume fractions",
                    results[k].phi_actual,
                    phis.join(", ")
                ),
            });
        }
        let FlowRuns { points, missing } = runs;
        let mut curve: Vec<StatePoint> = points.iter().map(|p| p.point).collect();
        keep_green_kubo_at_lowest_peclet(&mut curve);
        let fits = states(&curve)
            .into_iter()
            .map(|state| StateFits::fit(&curve, state))
            .collect();
        Ok(FlowCurves {
            points,
            missing,
            curve,
            fits,
        })
    }
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
