//! Sample statistics shared by the rheology fits, the ensemble table and the report's
//! profiles of the non-local descriptors.

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

/// The `q`-quantile (0 < q <= 1) of ascending `sorted` by nearest rank: the value at rank
/// `ceil(q n)`; `None` when empty.
pub fn nearest_rank_quantile(sorted: &[f64], q: f64) -> Option<f64> {
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted.get(rank.clamp(1, sorted.len().max(1)) - 1).copied()
}

/// Variation and noise of one descriptor (e.g. Theta or Delta_v) along one profile.
pub struct DescriptorStats {
    /// Standard deviation along y over the mean (coefficient of variation).
    pub variation: f64,
    /// Median over bins of standard error / |value|.
    pub median_relative_se: f64,
    /// Largest such ratio.
    pub max_relative_se: f64,
    /// Standard deviation along y over the root mean square standard error: how many
    /// noise widths the profile spans.
    pub signal_to_noise: f64,
}

impl DescriptorStats {
    /// Statistics of `values` with standard errors `se` (non-finite entries skipped): the
    /// sample standard deviation `sd = sqrt(sum (v - m)^2 / (n - 1))` over `|m|`, the median
    /// and largest `se / |v|`, and `sd / sqrt(sum se^2 / n)`; all dimensionless.
    pub fn of(values: &[f64], se: &[f64]) -> Self {
        let pairs: Vec<(f64, f64)> = values
            .iter()
            .zip(se)
            .filter(|(v, s)| v.is_finite() && s.is_finite())
            .map(|(&v, &s)| (v, s))
            .collect();
        let n = pairs.len() as f64;
        let mean = pairs.iter().map(|p| p.0).sum::<f64>() / n;
        let sd = (pairs.iter().map(|p| (p.0 - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let rms_se = (pairs.iter().map(|p| p.1 * p.1).sum::<f64>() / n).sqrt();
        let mut rel: Vec<f64> = pairs.iter().map(|p| p.1 / p.0.abs()).collect();
        rel.sort_by(f64::total_cmp);
        DescriptorStats {
            variation: sd / mean.abs(),
            median_relative_se: rel.get(rel.len() / 2).copied().unwrap_or(f64::NAN),
            max_relative_se: rel.last().copied().unwrap_or(f64::NAN),
            signal_to_noise: sd / rms_se,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_quantiles_of_ten_values() {
        let v: Vec<f64> = (1..=10).map(f64::from).collect();
        // Ranks ceil(1.6) = 2, ceil(5) = 5, ceil(8.4) = 9, ceil(10) = 10.
        let q = |q| nearest_rank_quantile(&v, q).unwrap();
        assert_eq!((q(0.16), q(0.5), q(0.84), q(1.0)), (2.0, 5.0, 9.0, 10.0));
        assert_eq!(nearest_rank_quantile(&[], 0.5), None);
    }

    #[test]
    fn descriptor_stats_of_a_known_profile() {
        let s = DescriptorStats::of(&[1.0, 3.0, f64::NAN], &[0.1, 0.3, 0.2]);
        assert!((s.variation - 2f64.sqrt() / 2.0).abs() < 1e-12);
        assert!((s.median_relative_se - 0.1).abs() < 1e-12);
        assert!((s.max_relative_se - 0.1).abs() < 1e-12);
        assert!((s.signal_to_noise - 2f64.sqrt() / (0.05f64).sqrt()).abs() < 1e-12);
    }
}
