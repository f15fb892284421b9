//! The models' inputs as f32, the element type of XGBoost and of [`Forest`]: one conversion
//! for every reader, refusing what f32 cannot hold.
//!
//! [`Forest`]: crate::models::forest::Forest

use ndarray::ArrayView2;

use crate::data::dataset::F32_MAX;
use crate::error::{Result, SurrogateError};

/// `values` (rows x columns) in row-major order as f32. NaN and infinities are refused
/// (XGBoost would take NaN for "missing"), and so are finite values beyond f32's range
/// (they would become infinities); `what` names the matrix and `names` its columns (`#j`,
/// from 1, where a name is missing) in the error.
pub(crate) fn to_f32<S: AsRef<str>>(
    values: ArrayView2<f64>,
    what: &str,
    names: &[S],
) -> Result<Vec<f32>> {
    let ncols = values.ncols().max(1);
    let column = |j: usize| {
        names
            .get(j)
            .map_or_else(|| format!("#{}", j + 1), |n| n.as_ref().to_owned())
    };
    values
        .iter()
        .enumerate()
        .map(|(i, &value)| {
            let (row, j) = (i / ncols + 1, i % ncols);
            if !value.is_finite() {
                Err(SurrogateError::NonFinite {
                    source_name: what.to_owned(),
                    row,
                    column: column(j),
                    value,
                })
            } else if value.abs() > F32_MAX {
                Err(SurrogateError::BeyondF32 {
                    source_name: what.to_owned(),
                    place: format!("row {row}"),
                    column: column(j),
                    value,
                })
            } else {
                Ok(value as f32)
            }
        })
        .collect()
}

/// A model's prediction input (rows x `n_features`) as f32 ([`to_f32`]); a matrix of any
/// other width is a shape error.
pub(crate) fn prediction_input<S: AsRef<str>>(
    features: ArrayView2<f64>,
    n_features: usize,
    feature_names: &[S],
) -> Result<Vec<f32>> {
    if features.ncols() != n_features {
        return Err(SurrogateError::ShapeMismatch {
            what: "prediction input (features per row)".to_owned(),
            expected: (features.nrows(), n_features),
            found: features.dim(),
        });
    }
    to_f32(features, "prediction input", feature_names)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn a_prediction_input_of_another_width_is_a_shape_error() {
        let names = ["J", "phi"];
        let wide = array![[1.0, 2.0, 3.0]];
        assert!(matches!(
            prediction_input(wide.view(), 2, &names),
            Err(SurrogateError::ShapeMismatch {
                expected: (1, 2),
                found: (1, 3),
                ..
            })
        ));
        let fits = prediction_input(array![[1.0, 2.0]].view(), 2, &names).unwrap();
        assert_eq!(fits, vec![1.0_f32, 2.0_f32]);
    }

    #[test]
    fn values_beyond_f32_are_refused_naming_row_and_column() {
        let names = ["J".to_owned(), "phi".to_owned()];
        let ok = to_f32(array![[1.0, 3.0e38]].view(), "m", &names).unwrap();
        assert_eq!(ok, vec![1.0_f32, 3.0e38_f32]);
        let message = to_f32(array![[1.0, 2.0], [-1e39, 0.5]].view(), "m", &names)
            .unwrap_err()
            .to_string();
        assert_eq!(
            message,
            "m: row 2, column `J`: -1e39 exceeds the f32 range of the models' inputs \
             (|x| <= 3.4e38)"
        );
        let message = to_f32::<&str>(array![[1.0, f64::NAN]].view(), "m", &[])
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("row 1, column `#2`: NaN is not a finite number"),
            "{message}"
        );
    }
}
