//! The relative L2 error (eq 6.6) of one profile against another, and of a saved model's
//! predictions on a table: what the report uses to put the simulation's error beside the
//! surrogate's in the same metric.
use ndarray::Array2;

use crate::data::dataset::Dataset;
use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::error::Result;
use crate::models::metrics::relative_l2_error;
use crate::models::predictor::Predictor;

/// `||a - b|| / ||b - offset||` over the bins where both are finite (NaN when none are):
/// the metric of eq 6.6 ([`relative_l2_error`]) on values shifted by `offset`, with `b`
/// the truth; dimensionless.
pub fn relative_l2(a: &[f64], b: &[f64], offset: f64) -> f64 {
    let pairs: Vec<(f64, f64)> = a
        .iter()
        .zip(b)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(&x, &y)| (x - offset, y - offset))
        .collect();
    let shifted = |pick: fn(&(f64, f64)) -> f64| {
        Array2::from_shape_fn((pairs.len(), 1), |(k, _)| pick(&pairs[k]))
    };
    let (predicted, truth) = (shifted(|p| p.0), shifted(|p| p.1));
    relative_l2_error(truth.view(), predicted.view()).map_or(f64::NAN, |e| e[0])
}

/// Relative L2 error (eq 6.6) of each output of `model` on the rows of `data` that
/// `mapping` reads, on outputs min-max scaled with the model's training ranges (eq 6.4).
pub fn model_errors(model: &Predictor, mapping: &Mapping, data: &Dataset) -> Result<Vec<f64>> {
    let samples = Samples::from_dataset(data, mapping)?;
    let predicted = model.predict_features(samples.features.view())?;
    let scaling = &model.meta().scaling;
    let truth = scaling.scale(samples.outputs.view())?;
    relative_l2_error(truth.view(), scaling.scale(predicted.view())?.view())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_l2_skips_undefined_bins_and_uses_the_offset() {
        let e = relative_l2(&[1.0, f64::NAN, 3.0], &[2.0, 5.0, 3.0], 1.0);
        assert!((e - (1.0f64 / 5.0).sqrt()).abs() < 1e-12);
    }
}
