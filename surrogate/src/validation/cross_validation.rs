//! Cross-validation grouped by simulation, and a small grid search over hyper-parameters.
//!
//! Bins of one simulation are strongly correlated, so a fold always holds whole simulations:
//! the rows of one group never sit on both sides of a split. Everything here is
//! deterministic: folds depend only on the group keys, and boosters are seeded.

use std::collections::BTreeMap;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::error::{Result, SurrogateError};
use crate::models::booster::HyperParameters;
use crate::models::model::TrainedModel;

/// One split: row indices to train on and row indices to test on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fold {
    pub train: Vec<usize>,
    pub test: Vec<usize>,
}

/// `k` folds over whole groups, balanced by row count: groups are taken largest first (ties
/// by key) and each goes to the fold with the fewest rows so far (ties to the lowest fold).
/// Needs `2 <= k <=` the number of groups.
pub fn grouped_k_fold(groups: &[String], k: usize) -> Result<Vec<Fold>> {
    let mut rows_of_group: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for (row, group) in groups.iter().enumerate() {
        rows_of_group.entry(group).or_default().push(row);
    }
    if k < 2 || k > rows_of_group.len() {
        return Err(SurrogateError::InvalidArgument(format!(
            "grouped cross-validation needs between 2 and {} folds (one per group at most), not {k}",
            rows_of_group.len()
        )));
    }
    let mut by_size: Vec<&Vec<usize>> = rows_of_group.values().collect();
    // Stable sort: equal sizes keep key order.
    by_size.sort_by_key(|rows| std::cmp::Reverse(rows.len()));
    let mut test_rows: Vec<Vec<usize>> = vec![Vec::new(); k];
    for rows in by_size {
        let smallest = (0..k)
            .min_by_key(|&fold| test_rows[fold].len())
            .unwrap_or(0);
        test_rows[smallest].extend(rows);
    }
    Ok(test_rows
        .into_iter()
        .map(|mut test| {
            test.sort_unstable();
            let train = (0..groups.len())
                .filter(|row| test.binary_search(row).is_err())
                .collect();
            Fold { train, test }
        })
        .collect())
}

/// One fold per group, each testing on that group alone.
pub fn leave_one_group_out(groups: &[String]) -> Result<Vec<Fold>> {
    let n_groups = groups
        .iter()
        .collect::<std::collections::BTreeSet<_>>()
        .len();
    grouped_k_fold(groups, n_groups)
}

/// Cross-validated error of one set of hyper-parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CvScore {
    pub params: HyperParameters,
    /// Relative L2 error of each output (eq 6.6), averaged over the folds.
    pub per_output: Vec<f64>,
    /// Mean of `per_output`: the figure candidates are ranked by.
    pub mean: f64,
}

/// Trains `mapping` on each fold's training rows and measures it on the fold's test rows.
pub fn cross_validate(
    mapping: &Mapping,
    samples: &Samples,
    folds: &[Fold],
    params: &HyperParameters,
) -> Result<CvScore> {
    if folds.is_empty() {
        return Err(SurrogateError::InvalidArgument(
            "cross-validation needs at least one fold".to_owned(),
        ));
    }
    let mut per_output = vec![0.0; mapping.outputs.len()];
    for fold in folds {
        let model = TrainedModel::fit(mapping, &samples.subset(&fold.train)?, params)?;
        let errors = model.evaluate(&samples.subset(&fold.test)?)?;
        for (sum, error) in per_output.iter_mut().zip(errors) {
            *sum += error / folds.len() as f64;
        }
    }
    let mean = per_output.iter().sum::<f64>() / per_output.len() as f64;
    Ok(CvScore {
        params: params.clone(),
        per_output,
        mean,
    })
}

/// Values to try for the hyper-parameters that matter most; the others come from `base`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HyperParameterGrid {
    pub base: HyperParameters,
    pub n_estimators: Vec<u32>,
    pub max_depth: Vec<u32>,
    pub learning_rate: Vec<f64>,
    pub min_child_weight: Vec<f64>,
    /// With and/or without the physics backbone ([`HyperParameters::backbone`]).
    #[serde(default)]
    pub backbone: Vec<bool>,
}

impl HyperParameterGrid {
    /// Every combination, in a fixed order (`backbone` varies slowest, then `n_estimators`).
    /// An empty list of values stands for `base`'s value.
    pub fn candidates(&self) -> Vec<HyperParameters> {
        let mut candidates = Vec::new();
        for backbone in values_or(&self.backbone, self.base.backbone) {
            for n_estimators in values_or(&self.n_estimators, self.base.n_estimators) {
                for max_depth in values_or(&self.max_depth, self.base.max_depth) {
                    for learning_rate in values_or(&self.learning_rate, self.base.learning_rate) {
                        for min_child_weight in
                            values_or(&self.min_child_weight, self.base.min_child_weight)
                        {
                            candidates.push(HyperParameters {
                                n_estimators,
                                max_depth,
                                learning_rate,
                                min_child_weight,
                                backbone,
                                ..self.base.clone()
                            });
                        }
                    }
                }
            }
        }
        candidates
    }
}

/// `values`, or `base` alone when `values` is empty.
fn values_or<T: Copy>(values: &[T], base: T) -> Vec<T> {
    if values.is_empty() {
        vec![base]
    } else {
        values.to_vec()
    }
}

/// Scores of all candidates, and the best one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridSearch {
    /// Lowest mean cross-validated error; the first such candidate on a tie.
    pub best: CvScore,
    /// Every candidate, in grid order.
    pub scores: Vec<CvScore>,
}

/// Cross-validates every candidate of `grid` on `folds` and picks the best by mean error.
/// Candidates run in parallel on rayon's pool; each booster is seeded and trained on its own
/// thread(s) (`nthread`), so the result does not depend on the number of threads.
pub fn grid_search(
    mapping: &Mapping,
    samples: &Samples,
    folds: &[Fold],
    grid: &HyperParameterGrid,
) -> Result<GridSearch> {
    let scores = grid
        .candidates()
        .par_iter()
        .map(|params| cross_validate(mapping, samples, folds, params))
        .collect::<Result<Vec<_>>>()?;
    let best = scores
        .iter()
        .reduce(|best, score| {
            if score.mean.total_cmp(&best.mean).is_lt() {
                score
            } else {
                best
            }
        })
        .cloned()
        .ok_or_else(|| {
            SurrogateError::InvalidArgument("the hyper-parameter grid is empty".to_owned())
        })?;
    Ok(GridSearch { best, scores })
}
