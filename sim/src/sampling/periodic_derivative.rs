//! Derivatives along y of a periodic binned profile (docs/physics.md section 6, gdot): the
//! spectral derivative, exact for the bin averages of a band-limited profile, and the centred
//! difference with its `1 - sinc(2 pi w / lambda)` low bias on a wave of length lambda.
use std::f64::consts::PI;

/// Spectral derivative of `f`, values at `n` equally spaced points `spacing` apart on a
/// period `n * spacing`, by a direct DFT (`O(n^2)`, meant for `n` up to a few hundred). The
/// Nyquist mode of an even `n` is dropped (its derivative is not resolved). Since d/dy
/// commutes with the bin average, on the bin averages of a band-limited profile this gives
/// the bin averages of its derivative exactly: `(u(top face) - u(bottom face)) / w`.
pub fn spectral(f: &[f64], spacing: f64) -> Vec<f64> {
    let n = f.len();
    let angle = |k: usize| 2.0 * PI * k as f64 / n as f64;
    let (cos, sin): (Vec<f64>, Vec<f64>) = (0..n).map(|k| (angle(k).cos(), angle(k).sin())).unzip();
    let mut out = vec![0.0; n];
    for m in 1..n.div_ceil(2) {
        // c_m = sum_k f_k exp(-2 pi i m k / n); mode m and its conjugate n - m together.
        let (mut re, mut im) = (0.0, 0.0);
        for (k, &v) in f.iter().enumerate() {
            let q = m * k % n;
            re += v * cos[q];
            im -= v * sin[q];
        }
        // d/dy of (2/n) Re[c_m exp(2 pi i m j / n)] with wavenumber 2 pi m / (n spacing).
        let scale = 2.0 / n as f64 * 2.0 * PI * m as f64 / (n as f64 * spacing);
        for (j, o) in out.iter_mut().enumerate() {
            let q = m * j % n;
            *o -= scale * (re * sin[q] + im * cos[q]);
        }
    }
    out
}

/// Centred periodic difference `(f_{k+1} - f_{k-1}) / (2 spacing)`.
pub fn centred(f: &[f64], spacing: f64) -> Vec<f64> {
    let n = f.len();
    (0..n)
        .map(|k| (f[(k + 1) % n] - f[(k + n - 1) % n]) / (2.0 * spacing))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bin averages over `[k w, (k+1) w)` of `sin(2 pi q y / L)` and of its derivative.
    fn binned_sine(n: usize, w: f64, q: f64) -> (Vec<f64>, Vec<f64>) {
        let kq = 2.0 * PI * q / (n as f64 * w);
        let avg = |k: usize, g: &dyn Fn(f64) -> f64| (g((k + 1) as f64 * w) - g(k as f64 * w)) / w;
        let u = (0..n).map(|k| avg(k, &|y| -(kq * y).cos() / kq)).collect();
        let du = (0..n).map(|k| avg(k, &|y| (kq * y).sin())).collect();
        (u, du)
    }

    fn max_abs_error(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn spectral_derivative_of_bin_averages_is_the_bin_averaged_derivative() {
        for (n, q) in [(25, 1.0), (50, 1.0), (40, 3.0), (7, 2.0)] {
            let w = 2.0;
            let (u, du) = binned_sine(n, w, q);
            let scale = du.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let spectral_error = max_abs_error(&spectral(&u, w), &du) / scale;
            let centred_error = max_abs_error(&centred(&u, w), &du) / scale;
            assert!(spectral_error < 1e-12, "n = {n}, q = {q}: {spectral_error}");
            // The centred difference is low by 1 - sinc(2 pi q w / L): 1 % at L = 50, q = 1.
            let kw = 2.0 * PI * q / n as f64;
            let bias = 1.0 - kw.sin() / kw;
            assert!(
                (centred_error - bias).abs() < 1e-9 && centred_error > 1e6 * spectral_error,
                "n = {n}, q = {q}: centred {centred_error}, expected {bias}"
            );
        }
    }

    #[test]
    fn constants_have_no_slope_and_a_linear_combination_stays_linear() {
        let c = vec![3.5; 12];
        assert!(spectral(&c, 2.0).iter().all(|v| v.abs() < 1e-12));
        let (a, _) = binned_sine(12, 2.0, 1.0);
        let (b, _) = binned_sine(12, 2.0, 2.0);
        let sum: Vec<f64> = a.iter().zip(&b).map(|(x, y)| 2.0 * x - y).collect();
        let (da, db, ds) = (spectral(&a, 2.0), spectral(&b, 2.0), spectral(&sum, 2.0));
        for k in 0..12 {
            assert!((ds[k] - (2.0 * da[k] - db[k])).abs() < 1e-12);
        }
    }
}
