//! Sample statistics shared by the rheology fits and the ensemble table.

/// Mean `m = sum x / n` and standard error of the mean `sqrt(s^2 / n)`, with the sample
/// variance `s^2 = sum (x - m)^2 / (n - 1)`; the error is NaN for fewer than two values.
pub fn mean_and_standard_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let m = values.iter().sum::<f64>() / n;
    if values.len() < 2 {
        return (m, f64::NAN);
    }
    let var = values.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// The median of `values` (the upper one of the middle two for an even count); `values` is
/// not empty.
pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}
