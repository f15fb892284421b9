//! The range a predicted output can physically take, and the clip that keeps predictions in
//! it.
//!
//! - `phi_loc` (local volume fraction): `0 < phi_loc < PHI_LOC_MAX`, with `PHI_LOC_MAX = 0.74`
//!   the densest packing of equal spheres (`pi / sqrt(18) = 0.7405`, rounded down);
//! - `mu` (stress ratio `|sigma_xy| / P`, docs/physics.md section 8) and `J = eta |gdot| / P`
//!   (for `P > 0`): `>= 0`.
//!
//! Why a clip and not a transform: the trees learn min-max scaled outputs (eq 6.4, the
//! thesis' setting, and the metric's scaling of eq 6.6), and inside the training range they
//! never leave it; the only way out is extrapolation, by the backbone's eq 6.7 (`phi_loc =
//! phi_J - sqrt(J / (alpha mu))` falls without bound as J grows) or by a residual added
//! where the law is near a bound (`mu -> 0` at a velocity extremum). A transform (e.g. a
//! logit of `phi_loc / PHI_LOC_MAX`) would change what the trees learn and the errors the
//! thesis reports; the clip changes nothing inside the range, and its count is reported
//! (`suspflow predict`) so that a clipped row is never silent. Such rows lie outside the
//! training domain in practice, where the prediction is already flagged.

use ndarray::{Array2, Axis};
use schema::columns as col;

use crate::data::scaling::Range;

/// The largest local volume fraction: the densest packing of equal spheres, rounded down.
pub const PHI_LOC_MAX: f64 = 0.74;

/// The closed range predictions of output `name` are clipped into, or `None` for an output
/// without bounds. Strict bounds are represented by the nearest representable value inside.
pub fn physical_range(name: &str) -> Option<Range> {
    match name {
        col::PHI_LOC => Some(Range {
            min: 0.0f64.next_up(),
            max: PHI_LOC_MAX.next_down(),
        }),
        col::MU | col::J => Some(Range {
            min: 0.0,
            max: f64::INFINITY,
        }),
        _ => None,
    }
}

/// The range a measured value of column `name` can take, with its reason, or `None` for a
/// column without physical bounds: the data a model is trained or validated on must lie in
/// it (a table with negative J or phi = 2 is corrupt, not a flow). Closed at 0: an empty
/// bin has phi_loc = 0, a velocity extremum mu = J = 0.
pub fn measured_range(name: &str) -> Option<(Range, &'static str)> {
    let at_least_zero = Range {
        min: 0.0,
        max: f64::INFINITY,
    };
    match name {
        col::PHI_LOC | col::PHI => Some((
            Range {
                min: 0.0,
                max: PHI_LOC_MAX,
            },
            "a volume fraction lies in [0, 0.74], 0.74 the densest packing of spheres",
        )),
        col::J => Some((at_least_zero, "J = eta |gdot| / P >= 0")),
        col::MU => Some((at_least_zero, "mu = |sigma_xy| / P >= 0")),
        col::THETA => Some((at_least_zero, "Theta = eta du / (a P) >= 0, eq 6.1")),
        col::DELTA_V => Some((
            at_least_zero,
            "Delta_v = |u_inf - u| / (|u_inf| + 1e-5) >= 0, eq 6.2",
        )),
        _ => None,
    }
}

/// Clips every column of `values` (rows x outputs, columns named by `outputs`) into its
/// output's [`physical_range`]; returns the number of cells changed. NaN stays NaN.
pub fn clip_to_physical_range<S: AsRef<str>>(outputs: &[S], values: &mut Array2<f64>) -> usize {
    let mut clipped = 0;
    for (name, mut column) in outputs.iter().zip(values.axis_iter_mut(Axis(1))) {
        let Some(range) = physical_range(name.as_ref()) else {
            continue;
        };
        for v in column.iter_mut() {
            if *v < range.min || *v > range.max {
                *v = v.clamp(range.min, range.max);
                clipped += 1;
            }
        }
    }
    clipped
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn measured_ranges_bound_the_local_state_and_leave_the_rest_free() {
        let inside =
            |name: &str, v: f64| measured_range(name).is_none_or(|(r, _)| v >= r.min && v <= r.max);
        assert!(inside("phi_loc", 0.0) && inside("phi_loc", 0.6) && !inside("phi_loc", -0.01));
        assert!(!inside("phi", 2.0) && !inside("J", -1e-9) && inside("J", 1e3));
        assert!(!inside("mu", -0.1) && !inside("Theta", -1.0) && !inside("Delta_v", -1.0));
        assert!(inside("u", -5.0) && inside("sigma_xy", -1.0));
    }

    #[test]
    fn clips_only_the_bounded_outputs_and_counts_the_cells() {
        let mut values = array![[-0.2, -1.0, -3.0], [0.9, 0.5, 2.0], [0.5, f64::NAN, 0.1]];
        let n = clip_to_physical_range(&["phi_loc", "mu", "Theta"], &mut values);
        assert_eq!(n, 3);
        assert!(values[[0, 0]] > 0.0 && values[[1, 0]] < PHI_LOC_MAX);
        assert_eq!(values[[2, 0]], 0.5);
        assert_eq!(values[[0, 1]], 0.0);
        assert!(values[[2, 1]].is_nan());
        assert_eq!(values.column(2).to_vec(), vec![-3.0, 2.0, 0.1]);
    }
}
