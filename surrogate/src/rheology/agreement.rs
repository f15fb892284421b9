//! Agreement of two binned profiles of the same scene, observable by observable: the mean
//! squared z-score `<(a - b)^2 / (se_a^2 + se_b^2)>` (about 1 when the two differ only by
//! their standard errors) and the relative L2 difference `|a - b| / |b|`.

/// Agreement of one observable: mean squared z-score and relative L2 difference over the
/// bins where both are defined, and how many bins that is.
pub struct Agreement {
    pub z2: f64,
    pub rel_l2: f64,
    pub bins: usize,
}

/// Compares `a` against `b` (with standard errors `sa`, `sb`), skipping undefined bins.
pub fn agreement(a: &[f64], sa: &[f64], b: &[f64], sb: &[f64]) -> Agreement {
    let (mut z2, mut diff2, mut norm2, mut bins) = (0.0, 0.0, 0.0, 0);
    for k in 0..a.len() {
        let (d, var) = (a[k] - b[k], sa[k] * sa[k] + sb[k] * sb[k]);
        if d.is_finite() && var.is_finite() {
            if var > 0.0 {
                z2 += d * d / var;
            }
            diff2 += d * d;
            norm2 += b[k] * b[k];
            bins += 1;
        }
    }
    Agreement {
        z2: z2 / bins.max(1) as f64,
        rel_l2: (diff2 / norm2).sqrt(),
        bins,
    }
}
