//! Min-max scaling of outputs to [0, 1] (thesis eq 6.4), fitted on a training set.

use ndarray::{Array2, ArrayView2, Axis};
use serde::{Deserialize, Serialize};

use crate::error::{Result, SurrogateError};

/// The smallest and largest value of one column in the training set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Range {
    pub min: f64,
    pub max: f64,
}

impl Range {
    /// `max - min`, or 1 for a constant column, which then scales to 0 instead of dividing by 0.
    fn span(&self) -> f64 {
        if self.max > self.min {
            self.max - self.min
        } else {
            1.0
        }
    }
}

/// Per-column ranges: `y' = (y - y_min) / (y_max - y_min)` maps the training set onto [0, 1].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MinMaxScaling {
    pub ranges: Vec<Range>,
}

impl MinMaxScaling {
    /// The range of each column of `values` (rows x columns).
    pub fn fit(values: ArrayView2<f64>) -> Result<Self> {
        if values.nrows() == 0 {
            return Err(SurrogateError::EmptyDataset {
                what: "the set to fit the scaling on".to_owned(),
            });
        }
        let ranges = values
            .axis_iter(Axis(1))
            .map(|column| Range {
                min: column.fold(f64::INFINITY, |a, &b| a.min(b)),
                max: column.fold(f64::NEG_INFINITY, |a, &b| a.max(b)),
            })
            .collect();
        Ok(MinMaxScaling { ranges })
    }

    /// `Err(what is wrong)` unless every range is finite with `min <= max`, and, when
    /// `nonzero` (the outputs' ranges, which eq 6.6's error divides by), `min < max`. Column
    /// `k` is named `names[k]`.
    pub fn check<S: AsRef<str>>(
        &self,
        names: &[S],
        nonzero: bool,
    ) -> std::result::Result<(), String> {
        for (range, name) in self.ranges.iter().zip(names) {
            let name = name.as_ref();
            let Range { min, max } = *range;
            if !(min.is_finite() && max.is_finite()) || min > max {
                return Err(format!(
                    "the range of `{name}` is [{min}, {max}], not a range"
                ));
            }
            if nonzero && min == max {
                return Err(format!(
                    "the range of `{name}` is [{min}, {max}], of zero width: the outputs were \
                     the same in every training row, and scaled errors (eq 6.4, 6.6) are 0 / 0"
                ));
            }
        }
        Ok(())
    }

    /// `values` scaled column by column (eq 6.4).
    pub fn scale(&self, values: ArrayView2<f64>) -> Result<Array2<f64>> {
        self.map_columns(values, |range, v| (v - range.min) / range.span())
    }

    /// The inverse of [`MinMaxScaling::scale`]: values back in their original units.
    pub fn unscale(&self, scaled: ArrayView2<f64>) -> Result<Array2<f64>> {
        self.map_columns(scaled, |range, v| range.min + v * range.span())
    }

    fn map_columns(
        &self,
        values: ArrayView2<f64>,
        f: impl Fn(&Range, f64) -> f64,
    ) -> Result<Array2<f64>> {
        if values.ncols() != self.ranges.len() {
            return Err(SurrogateError::ShapeMismatch {
                what: "min-max scaling (columns)".to_owned(),
                expected: (values.nrows(), self.ranges.len()),
                found: values.dim(),
            });
        }
        let mut out = values.to_owned();
        for (mut column, range) in out.axis_iter_mut(Axis(1)).zip(&self.ranges) {
            column.mapv_inplace(|v| f(range, v));
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn scales_training_set_onto_unit_interval_and_back() {
        let values = array![[2.0, -1.0], [4.0, 3.0], [3.0, 1.0]];
        let scaling = MinMaxScaling::fit(values.view()).unwrap();
        assert_eq!(
            scaling.ranges,
            vec![
                Range { min: 2.0, max: 4.0 },
                Range {
                    min: -1.0,
                    max: 3.0
                }
            ]
        );
        let scaled = scaling.scale(values.view()).unwrap();
        assert_eq!(scaled, array![[0.0, 0.0], [1.0, 1.0], [0.5, 0.5]]);
        let back = scaling.unscale(scaled.view()).unwrap();
        assert!(
            back.iter()
                .zip(values.iter())
                .all(|(a, b)| (a - b).abs() < 1e-12),
            "{back}"
        );
    }

    #[test]
    fn constant_column_scales_to_zero_and_back() {
        let values = array![[5.0], [5.0]];
        let scaling = MinMaxScaling::fit(values.view()).unwrap();
        let scaled = scaling.scale(values.view()).unwrap();
        assert_eq!(scaled, array![[0.0], [0.0]]);
        assert_eq!(scaling.unscale(scaled.view()).unwrap(), values);
    }

    #[test]
    fn impossible_ranges_are_named() {
        let scaling = |min: f64, max: f64| MinMaxScaling {
            ranges: vec![Range { min, max }],
        };
        assert!(scaling(0.1, 2.0).check(&["mu"], true).is_ok());
        assert!(scaling(0.5, 0.5).check(&["mu"], false).is_ok());
        let zero = scaling(0.5, 0.5).check(&["mu"], true).unwrap_err();
        assert!(zero.contains("`mu` is [0.5, 0.5], of zero width"), "{zero}");
        let inverted = scaling(2.0, 0.1).check(&["mu"], false).unwrap_err();
        assert!(inverted.contains("[2, 0.1], not a range"), "{inverted}");
        assert!(scaling(f64::NAN, 1.0).check(&["mu"], false).is_err());
    }

    #[test]
    fn ranges_survive_json() {
        let scaling = MinMaxScaling::fit(array![[0.1, 7.0], [0.3, 9.5]].view()).unwrap();
        let json = serde_json::to_string(&scaling).unwrap();
        assert_eq!(
            serde_json::from_str::<MinMaxScaling>(&json).unwrap(),
            scaling
        );
    }

    #[test]
    fn wrong_column_count_and_empty_input_are_errors() {
        let scaling = MinMaxScaling::fit(array![[1.0, 2.0]].view()).unwrap();
        assert!(matches!(
            scaling.scale(array![[1.0]].view()),
            Err(SurrogateError::ShapeMismatch { .. })
        ));
        let empty = Array2::<f64>::zeros((0, 2));
        assert!(matches!(
            MinMaxScaling::fit(empty.view()),
            Err(SurrogateError::EmptyDataset { .. })
        ));
    }
}
