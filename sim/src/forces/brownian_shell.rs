//! The pairs that the structural Brownian stress counts (thesis eq 3.54, paper eq 2.27;
//! docs/physics.md section 11): those whose surface gap is below a thin shell, each weighted
//! so that the stress's trace is the hard-sphere contact virial.

/// Shell width over the pair's mean radius, `Delta / a_ij` with `a_ij = (a_i + a_j) / 2`
/// (eq 3.54's `Delta = 0.05 a_i`, with `a_i` symmetrised to `a_ij` so that a 1 : 1.4 pair
/// is counted the same from either side).
pub const SHELL: f64 = 0.05;

/// Centre distance below which the pair (a_i, a_j) is in the shell:
/// `a_i + a_j + SHELL (a_i + a_j) / 2`.
pub fn reach(a_i: f64, a_j: f64) -> f64 {
    (a_i + a_j) * (1.0 + 0.5 * SHELL)
}

/// The pair's weight in the structural Brownian stress, in energy units, or `None` outside
/// the shell (centre distance `d`, overlapping pairs included): eq 3.54 sums
/// `(kT a_i / Delta) n n^T` over both orders of the pair, which is `2 kT / SHELL` per
/// unordered pair. The stress of a volume `V` is `sum of weight n n^T / V`, positive in
/// compression like the pair stresslets; its trace over 3 V is the contact virial
/// `(2 pi / 3) n^2 sigma^3 g(sigma) kT` of hard spheres when the shell is thin.
#[inline]
pub fn weight(kt: f64, a_i: f64, a_j: f64, d: f64) -> Option<f64> {
    (d < reach(a_i, a_j)).then_some(2.0 * kt / SHELL)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Independent of eq 3.54's form: an ideal gas of pairs at uniform density `n` with a
    /// flat contact value `g` puts `n g 4 pi sigma^2 Delta` neighbours per particle in the
    /// shell; the weighted count over 3 V must give `(2 pi / 3) n^2 sigma^3 g kT`.
    #[test]
    fn the_trace_is_the_hard_sphere_contact_virial() {
        let (kt, a, n, g) = (0.017, 1.3, 0.07, 2.5);
        let sigma = 2.0 * a;
        let delta = SHELL * a;
        let unordered_pairs_per_volume = 0.5 * n * n * g * 4.0 * PI * sigma * sigma * delta;
        let w = weight(kt, a, a, sigma + 0.5 * delta).expect("inside the shell");
        let pressure = unordered_pairs_per_volume * w / 3.0;
        let virial = 2.0 * PI / 3.0 * n * n * sigma.powi(3) * g * kt;
        assert!(
            (pressure / virial - 1.0).abs() < 1e-12,
            "{pressure} vs {virial}"
        );
    }

    #[test]
    fn the_shell_ends_at_its_width_and_holds_overlaps() {
        let (a_i, a_j) = (1.0, 1.4);
        let edge = a_i + a_j + SHELL * 1.2;
        assert!(weight(1.0, a_i, a_j, edge * (1.0 - 1e-12)).is_some());
        assert!(weight(1.0, a_i, a_j, edge * (1.0 + 1e-12)).is_none());
        assert!(weight(1.0, a_i, a_j, 0.99 * (a_i + a_j)).is_some());
        assert_eq!(
            weight(1.0, a_i, a_j, a_i + a_j),
            weight(1.0, a_j, a_i, a_i + a_j)
        );
    }
}
