//! Accuracy metric of docs/physics.md section 8 (thesis eq 6.6).

use ndarray::{ArrayView2, Axis};

use crate::error::{Result, SurrogateError};

/// Relative L2 error `||y' - yhat'||_2 / ||y'||_2` of each output column, for min-max scaled
/// truth `y'` and prediction `yhat'` (rows x outputs). A column whose truth is all zero gets
/// 0 if the prediction is exact and infinity otherwise.
pub fn relative_l2_error(truth: ArrayView2<f64>, predicted: ArrayView2<f64>) -> Result<Vec<f64>> {
    if truth.dim() != predicted.dim() {
        return Err(SurrogateError::ShapeMismatch {
            what: "relative L2 error (prediction vs truth)".to_owned(),
            expected: truth.dim(),
            found: predicted.dim(),
        });
    }
    if truth.nrows() == 0 {
        return Err(SurrogateError::EmptyDataset {
            what: "the set to measure the error on".to_owned(),
        });
    }
    Ok(truth
        .axis_iter(Axis(1))
        .zip(predicted.axis_iter(Axis(1)))
        .map(|(y, yhat)| {
            let residual = y
                .iter()
                .zip(yhat)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            let norm = y.iter().map(|a| a * a).sum::<f64>().sqrt();
            if residual == 0.0 {
                0.0
            } else {
                residual / norm
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn per_output_error_matches_hand_computation() {
        let truth = array![[3.0, 1.0], [4.0, 0.0]];
        let predicted = array![[3.0, 1.0], [3.0, 0.5]];
        let e = relative_l2_error(truth.view(), predicted.view()).unwrap();
        assert!((e[0] - 1.0 / 5.0).abs() < 1e-15);
        assert!((e[1] - 0.5).abs() < 1e-15);
    }

    #[test]
    fn mismatched_shapes_are_an_error() {
        let e = relative_l2_error(array![[1.0]].view(), array![[1.0, 2.0]].view()).unwrap_err();
        assert!(matches!(e, SurrogateError::ShapeMismatch { .. }));
    }
}
