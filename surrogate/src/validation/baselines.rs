//! Baselines that a surrogate must beat, scored with the same metric: linear least squares
//! (linfa) and the physics backbone alone ([`crate::rheology::local_rheology`]).

use std::time::{Duration, Instant};

use linfa::traits::{Fit, Predict};
use linfa_linear::LinearRegression;
use ndarray::{Array2, Axis};
use serde::Serialize;

use crate::data::samples::Samples;
use crate::data::scaling::MinMaxScaling;
use crate::error::{name_differences, Result, SurrogateError};
use crate::models::metrics::relative_l2_error;
use crate::rheology::backbone::Backbone;

/// Which features a least-squares fit sees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Baseline {
    /// `y' = a + sum_i b_i x_i`.
    Linear,
    /// `y' = a + sum_i b_i ln x_i` (a power law in the features); every feature must be positive.
    LogLinear,
    /// The local rheology alone: `mu = A J^b` and `phi_loc` from eq 6.7, fitted on the
    /// training rows; the other features are not used.
    LocalRheology,
}

/// How a baseline did on a test set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BaselineScore {
    pub baseline: Baseline,
    /// Relative L2 error of each output (eq 6.6), outputs min-max scaled on the training set.
    pub per_output: Vec<f64>,
    /// Time to scale the outputs and fit one regression per output.
    pub training_time: Duration,
}

/// Fits `baseline` on `train`, one least-squares regression per min-max scaled output, and
/// scores it on `test`.
pub fn evaluate_baseline(
    baseline: Baseline,
    train: &Samples,
    test: &Samples,
) -> Result<BaselineScore> {
    if train.feature_names != test.feature_names || train.output_names != test.output_names {
        let differences = [
            ("features", &train.feature_names, &test.feature_names),
            ("outputs", &train.output_names, &test.output_names),
        ]
        .into_iter()
        .filter(|(_, a, b)| a != b)
        .map(|(what, a, b)| format!("{what}: {}", name_differences(a, b)))
        .collect::<Vec<_>>();
        return Err(SurrogateError::FeatureMismatch {
            detail: format!(
                "test set {} differs from training set {} in its {}",
                test.source_name,
                train.source_name,
                differences.join("; ")
            ),
        });
    }
    if baseline == Baseline::LocalRheology {
        return evaluate_local_rheology(train, test);
    }
    let train_features = baseline_features(baseline, train)?;
    let test_features = baseline_features(baseline, test)?;
    let started = Instant::now();
    let scaling = MinMaxScaling::fit(train.outputs.view())?;
    let scaled = scaling.scale(train.outputs.view())?;
    let fits = scaled
        .axis_iter(Axis(1))
        .map(|output| {
            LinearRegression::default().fit(&linfa::Dataset::new(
                train_features.clone(),
                output.to_owned(),
            ))
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let training_time = started.elapsed();
    let mut predicted = Array2::zeros((test.n_rows(), fits.len()));
    for (mut column, fit) in predicted.axis_iter_mut(Axis(1)).zip(&fits) {
        column.assign(&fit.predict(&test_features));
    }
    let truth = scaling.scale(test.outputs.view())?;
    Ok(BaselineScore {
        baseline,
        per_output: relative_l2_error(truth.view(), predicted.view())?,
        training_time,
    })
}

/// The backbone fitted on `train`, scored on `test`.
fn evaluate_local_rheology(train: &Samples, test: &Samples) -> Result<BaselineScore> {
    let started = Instant::now();
    let scaling = MinMaxScaling::fit(train.outputs.view())?;
    let (backbone, _) = Backbone::fit(train)?;
    let training_time = started.elapsed();
    let predicted = backbone.law_prediction(
        &test.feature_names,
        &test.output_names,
        test.features.view(),
    )?;
    Ok(BaselineScore {
        baseline: Baseline::LocalRheology,
        per_output: relative_l2_error(
            scaling.scale(test.outputs.view())?.view(),
            scaling.scale(predicted.view())?.view(),
        )?,
        training_time,
    })
}

/// The features `baseline` regresses on: as they are, or their natural logarithms.
fn baseline_features(baseline: Baseline, samples: &Samples) -> Result<Array2<f64>> {
    match baseline {
        Baseline::Linear | Baseline::LocalRheology => Ok(samples.features.clone()),
        Baseline::LogLinear => {
            if let Some(((i, j), &value)) = samples.features.indexed_iter().find(|(_, &v)| v <= 0.0)
            {
                return Err(SurrogateError::NonPositive {
                    source_name: samples.source_name.clone(),
                    row: samples.data_rows[i],
                    column: samples.feature_names[j].clone(),
                    value,
                });
            }
            Ok(samples.features.mapv(f64::ln))
        }
    }
}
