//! The targets' own noise: the error (eq 6.6) that a model predicting the true means would
//! score against targets as noisy as their standard errors say.

use ndarray::{Array2, ArrayView2};

use crate::data::dataset::Dataset;
use crate::data::samples::Samples;
use crate::data::scaling::MinMaxScaling;
use crate::error::Result;
use crate::models::metrics::relative_l2_error;

/// The standard errors of `samples`' outputs (rows x outputs), from `dataset`'s
/// `<output>_se` columns; `None` when an output has no such column or one of the rows an
/// empty or non-finite one.
pub fn output_standard_errors(dataset: &Dataset, samples: &Samples) -> Result<Option<Array2<f64>>> {
    let names = dataset.column_names();
    let mut se = Array2::zeros(samples.outputs.raw_dim());
    for (j, output) in samples.output_names.iter().enumerate() {
        let se_name = schema::columns::standard_error(output);
        if !names.contains(&se_name) {
            return Ok(None);
        }
        let column = dataset.column(&se_name)?;
        for (i, &row) in samples.data_rows.iter().enumerate() {
            let e = column[row - 1];
            if !e.is_finite() {
                return Ok(None);
            }
            se[[i, j]] = e;
        }
    }
    Ok(Some(se))
}

/// Per output, the relative L2 error (eq 6.6, outputs scaled with `scaling`) of the targets
/// `outputs` shifted by one standard error `se`.
pub fn target_noise(
    scaling: &MinMaxScaling,
    outputs: ArrayView2<f64>,
    se: ArrayView2<f64>,
) -> Result<Vec<f64>> {
    let shifted = &outputs + &se;
    relative_l2_error(
        scaling.scale(outputs)?.view(),
        scaling.scale(shifted.view())?.view(),
    )
}

/// The part of an error beyond the targets' own noise, `sqrt(max(0, error^2 - noise^2))`
/// (issue 52): what a better model could still gain if the model's error and the noise of
/// the targets it is scored against are independent (their squares add). Both in one
/// measure (eq 6.6 fractions, or absolute errors).
pub fn beyond_noise(error: f64, noise: f64) -> f64 {
    (error * error - noise * noise).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    /// Targets 1, 2, 3 with standard errors 0.1, scaled on their range [1, 3]: the shifted
    /// scaled targets are 0.05 above 0, 0.5, 1, so the noise is sqrt(3 0.05^2 / 1.25) = 0.0775.
    /// The offset of the scaling cancels; only its width divides the standard errors.
    #[test]
    fn the_noise_is_the_scaled_standard_error_over_the_scaled_targets() {
        let outputs = array![[1.0], [2.0], [3.0]];
        let se = array![[0.1], [0.1], [0.1]];
        let scaling = MinMaxScaling::fit(outputs.view()).unwrap();
        let noise = target_noise(&scaling, outputs.view(), se.view()).unwrap();
        let expected = (3.0 * 0.05f64.powi(2) / 1.25).sqrt();
        assert!((noise[0] - expected).abs() < 1e-12, "{noise:?} {expected}");
    }

    #[test]
    fn the_error_beyond_noise_subtracts_in_quadrature_and_never_goes_negative() {
        assert!((beyond_noise(0.05, 0.03) - 0.04).abs() < 1e-15);
        assert_eq!(beyond_noise(0.02, 0.03), 0.0);
        assert_eq!(beyond_noise(0.05, 0.0), 0.05);
    }
}
