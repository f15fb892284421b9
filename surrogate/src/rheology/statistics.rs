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

/// The standard normal quantile `Phi^-1(p)` for `0 < p < 1` (P. J. Acklam's rational
/// approximation, relative error below 1.2e-9), NaN outside (0, 1).
pub fn standard_normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    const P_LOW: f64 = 0.024_25;
    if !(p > 0.0 && p < 1.0) {
        return f64::NAN;
    }
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < P_LOW {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - P_LOW {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
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
    fn the_standard_normal_quantile_matches_tabulated_values() {
        // Tables: Phi^-1(0.95) = 1.644853627, Phi^-1(0.975) = 1.959963985,
        // Phi^-1(0.999) = 3.090232306; odd about 0.5.
        for (p, z) in [
            (0.95, 1.644_853_627),
            (0.975, 1.959_963_985),
            (0.999, 3.090_232_306),
        ] {
            assert!((standard_normal_quantile(p) - z).abs() < 1e-8, "{p}");
            assert!((standard_normal_quantile(1.0 - p) + z).abs() < 1e-8, "{p}");
        }
        assert_eq!(standard_normal_quantile(0.5), 0.0);
        assert!(standard_normal_quantile(1.0).is_nan() && standard_normal_quantile(0.0).is_nan());
    }

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
