//! Brownian forces and torques in pairwise form (thesis eqs 3.19-3.24, paper eqs
//! 2.19-2.25; docs/physics.md section 11): a one-body part from the Stokes drag and, for
//! every pair inside the lubrication cut-off, a pair part built from the same regularised
//! resistance functions that enter the deterministic lubrication, so that the random
//! loads of one step have covariance `(2 kT / dt) (D + R)` exactly, with no global
//! factorisation and a cost linear in the pairs.
//!
//! The normal deviates come from a counter-based generator (ChaCha8) keyed by the run's
//! seed, the step, and the identities of the particle or of the two particles of a pair:
//! a draw does not depend on the thread count, on the order of the neighbour list or on
//! where the particles sit in memory, and a resumed run draws the same numbers.
use crate::forces::drag;
use crate::forces::lubrication::PairResistance;
use crate::forces::pair_load::PairLoad;
use crate::state::Vec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// Six standard normal deviates: two independent 3-vectors.
pub type Deviates = [Vec3; 2];

/// The 32-bit words of a key's stream set aside for one draw: four ChaCha blocks.
const SLOT_WORDS: u128 = 64;

/// The unscaled pair factor `B (theta, chi)` of one lubricated pair: the loads whose
/// covariance over independent standard-normal `theta`, `chi` is the pair's resistance
/// block `R_pair` (the 12 x 12 map from `(v_i, omega_i, v_j, omega_j)` to minus the loads
/// of [`PairResistance::load`]), for unit vector `n` from i to j:
/// force on i `(sqrt(X11A) N + sqrt(Y11A) T) theta` (3.22, force on j its opposite),
/// torque on i `Y11B / sqrt(Y11A) theta x n + sqrt(Y11C - Y11B^2 / Y11A) T chi` (3.23),
/// torque on j `Y21B / sqrt(Y11A) theta x n - sqrt(Y22C - Y21B^2 / Y11A) T chi` (3.24, with
/// the sign of the last term that its own proof, eqs 3.28 and 3.45-3.52, requires; the
/// thesis prints `+`). Exact because every tangential function carries the same
/// `ln(1/xi)`: the tangential block of each direction has rank two (docs/physics.md
/// section 11). Units: sqrt of the resistance (sqrt(eta a), ...).
#[inline]
pub fn pair_factor(r: &PairResistance, n: &Vec3, [theta, chi]: &Deviates) -> PairLoad {
    let theta_n = n * n.dot(theta);
    let theta_t = theta - theta_n;
    let chi_t = chi - n * n.dot(chi);
    let sqrt_ya = r.y11a.max(0.0).sqrt();
    let (couple_i, couple_j, pump_i, pump_j) = if sqrt_ya > 0.0 {
        (
            r.y11b / sqrt_ya,
            r.y21b / sqrt_ya,
            (r.y11c - r.y11b * r.y11b / r.y11a).max(0.0).sqrt(),
            (r.y22c - r.y21b * r.y21b / r.y11a).max(0.0).sqrt(),
        )
    } else {
        (0.0, 0.0, r.y11c.max(0.0).sqrt(), r.y22c.max(0.0).sqrt())
    };
    let theta_x_n = theta.cross(n);
    PairLoad {
        force_i: theta_n * r.x11a.max(0.0).sqrt() + theta_t * sqrt_ya,
        torque_i: theta_x_n * couple_i + chi_t * pump_i,
        torque_j: theta_x_n * couple_j - chi_t * pump_j,
    }
}

/// The unscaled one-body factor of a sphere of radius `a` (3.20, 3.21): force
/// `sqrt(6 pi eta a) psi` and torque `sqrt(8 pi eta a^3) phi`.
#[inline]
pub fn one_body_factor(eta: f64, a: f64, [psi, phi]: &Deviates) -> (Vec3, Vec3) {
    (
        psi * drag::translational_resistance(eta, a).sqrt(),
        phi * drag::rotational_resistance(eta, a).sqrt(),
    )
}

/// What a draw belongs to: one particle (one-body noise) or one pair, by identity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseKey {
    Particle(u32),
    /// The pair's two identities, in either order.
    Pair(u32, u32),
}

/// The random source of a Brownian run: thermal energy, time step and the keyed
/// generator.
#[derive(Clone, Debug)]
pub struct ThermalNoise {
    /// `sqrt(2 kT / dt)`, the scale of every factor (3.19).
    scale: f64,
    generator: ChaCha8Rng,
}

impl ThermalNoise {
    /// Noise at thermal energy `kt` (units of energy, > 0) for steps of `dt`, keyed by the
    /// run's `seed`.
    pub fn new(kt: f64, dt: f64, seed: u64) -> Self {
        Self {
            scale: (2.0 * kt / dt).sqrt(),
            // Its own key, apart from the packing's generator of the same seed.
            generator: ChaCha8Rng::seed_from_u64(seed ^ 0x6272_6f77_6e69_616e),
        }
    }

    /// `sqrt(2 kT / dt)`.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The six deviates of `key` at `step`: the normals drawn by the ziggurat from the
    /// key's stream at its own slot of [`SLOT_WORDS`] words, the four ChaCha blocks that one
    /// refill of the generator makes. The ziggurat takes one 64-bit word per normal but
    /// for its rare rejections (about 1 %), so six normals stay well inside the slot's 32
    /// 64-bit words and the draws of two keys or two steps never share words. A pair's
    /// deviates are
    /// oriented from its smaller identity to its larger: seen from the other particle they
    /// change sign, as the pair factor does when i and j swap (`n -> -n`, `Y11B <-> Y21B`,
    /// `Y11C <-> Y22C`), so the loads do not depend on which particle the list puts first.
    pub fn deviates(&self, key: NoiseKey, step: u64) -> Deviates {
        let (stream, kind, sign) = match key {
            NoiseKey::Particle(i) => (i as u64, 0, 1.0),
            NoiseKey::Pair(i, j) => {
                let (lo, hi) = (i.min(j) as u64, i.max(j) as u64);
                (lo << 32 | hi, 1, if i < j { 1.0 } else { -1.0 })
            }
        };
        let mut rng = self.generator.clone();
        rng.set_stream(stream);
        rng.set_word_pos(((step as u128) * 2 + kind) * SLOT_WORDS);
        let normals: [f64; 6] = std::array::from_fn(|_| rng.sample(StandardNormal));
        [
            Vec3::new(normals[0], normals[1], normals[2]) * sign,
            Vec3::new(normals[3], normals[4], normals[5]) * sign,
        ]
    }

    /// The Brownian load of a lubricated pair at `step`: `sqrt(2 kT / dt)` times the pair
    /// factor of its resistance, for identities `ids` and unit vector `n` from the first
    /// to the second.
    #[inline]
    pub fn pair_load(&self, r: &PairResistance, n: &Vec3, ids: (u32, u32), step: u64) -> PairLoad {
        let b = pair_factor(r, n, &self.deviates(NoiseKey::Pair(ids.0, ids.1), step));
        PairLoad {
            force_i: b.force_i * self.scale,
            torque_i: b.torque_i * self.scale,
            torque_j: b.torque_j * self.scale,
        }
    }

    /// The one-body Brownian force and torque (3.20, 3.21) of particle `id` of radius `a`
    /// at `step`.
    #[inline]
    pub fn one_body_load(&self, eta: f64, a: f64, id: u32, step: u64) -> (Vec3, Vec3) {
        let (f, t) = one_body_factor(eta, a, &self.deviates(NoiseKey::Particle(id), step));
        (f * self.scale, t * self.scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::lubrication::LubricationCoefficients;
    use nalgebra::{DMatrix, DVector};
    use rand::rngs::StdRng;
    use rand::Rng;

    fn unit_vector(rng: &mut StdRng) -> Vec3 {
        loop {
            let v = Vec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            );
            if v.norm() > 0.1 && v.norm() < 1.0 {
                return v.normalize();
            }
        }
    }

    /// The pair block of the resistance, column by column from the deterministic
    /// lubrication law: column k is minus the loads (F_i, T_i, F_j, T_j) that the unit
    /// motion k of (v_i, omega_i, v_j, omega_j) meets.
    fn resistance_block(r: &PairResistance, n: &Vec3) -> DMatrix<f64> {
        let mut block = DMatrix::zeros(12, 12);
        for k in 0..12 {
            let mut m = [Vec3::zeros(); 4];
            m[k / 3][k % 3] = 1.0;
            let load = r.load(n, &(m[2] - m[0]), &m[1], &m[3]);
            let column = [load.force_i, load.torque_i, -load.force_i, load.torque_j];
            for (b, v) in column.iter().enumerate() {
                for c in 0..3 {
                    block[(3 * b + c, k)] = -v[c];
                }
            }
        }
        block
    }

    /// The 12 x 6 factor: column k is the load of the unit deviate k of (theta, chi);
    /// `flip_pump` prints the sign of the chi term on j as thesis eq 3.24 does.
    fn factor_matrix(r: &PairResistance, n: &Vec3, flip_pump: bool) -> DMatrix<f64> {
        let mut b = DMatrix::zeros(12, 6);
        for k in 0..6 {
            let mut d = [Vec3::zeros(); 2];
            d[k / 3][k % 3] = 1.0;
            let load = pair_factor(r, n, &d);
            let torque_j = if flip_pump && k >= 3 {
                -load.torque_j
            } else {
                load.torque_j
            };
            let column = [load.force_i, load.torque_i, -load.force_i, torque_j];
            for (row, v) in column.iter().enumerate() {
                for c in 0..3 {
                    b[(3 * row + c, k)] = v[c];
                }
            }
        }
        b
    }

    /// For random orientations, gaps from below `xi_min` to past `xi_max` and size
    /// ratios 1, 1.4, 1/1.4, 5 (and 7, 1/7 for mixtures): `B B^T = R_pair` to 1e-12
    /// relative, checked against the block assembled independently from the deterministic
    /// load; no resistance and so no noise at or beyond the cut-off; the sign printed in
    /// eq 3.24 fails by far.
    #[test]
    fn pair_factor_squares_to_the_pair_resistance() {
        let mut rng = StdRng::seed_from_u64(11);
        for (a_i, a_j) in [
            (1.0, 1.0),
            (1.0, 1.4),
            (1.4, 1.0),
            (1.0, 5.0),
            (1.0, 7.0),
            (7.0, 1.0),
        ] {
            let lub = LubricationCoefficients::new(a_i, a_j, 0.37, 1e-3, 0.05);
            for xi in [5e-4, 1e-3, 2e-3, 0.01, 0.049, 0.05, 0.06] {
                let Some(r) = lub.resistance(xi) else {
                    assert!(xi >= 0.05);
                    continue;
                };
                for _ in 0..5 {
                    let n = unit_vector(&mut rng);
                    let block = resistance_block(&r, &n);
                    let b = factor_matrix(&r, &n, false);
                    let error = (&b * b.transpose() - &block).norm() / block.norm();
                    assert!(
                        error < 1e-12,
                        "a {a_i}:{a_j} xi {xi}: |BB^T - R|/|R| = {error:e}"
                    );
                    // The printed sign, measured on the block it changes: the coupling
                    // of the two spins, `Y12C T` (3.44-3.52).
                    let printed = factor_matrix(&r, &n, true);
                    let spins = |m: &DMatrix<f64>| m.view((3, 9), (3, 3)).into_owned();
                    let wrong = (spins(&(&printed * printed.transpose())) - spins(&block)).norm()
                        / spins(&block).norm();
                    assert!(wrong > 0.5, "the printed sign should fail: {wrong:e}");
                    // R is positive semi-definite: the smallest eigenvalue is not negative.
                    let least = block.clone().symmetric_eigen().eigenvalues.min();
                    assert!(least > -1e-10 * block.norm(), "{least:e}");
                }
            }
        }
    }

    /// Every draw's pair forces are equal and opposite, and a pair's loads do not depend
    /// on which particle comes first: swapping i and j (n -> -n, the ordered resistance
    /// of the swapped radii) gives the same load on each particle.
    #[test]
    fn pair_noise_is_antisymmetric_and_independent_of_the_pair_order() {
        let noise = ThermalNoise::new(0.017, 1e-3, 5);
        let (a_i, a_j) = (1.0, 1.4);
        let forward = LubricationCoefficients::new(a_i, a_j, 0.1, 1e-3, 0.05);
        let backward = LubricationCoefficients::new(a_j, a_i, 0.1, 1e-3, 0.05);
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        for step in 0..20 {
            let xi = 1e-3 + 0.002 * step as f64;
            let ij = noise.pair_load(&forward.resistance(xi).unwrap(), &n, (4, 9), step);
            let ji = noise.pair_load(&backward.resistance(xi).unwrap(), &-n, (9, 4), step);
            for (a, b) in [
                (ij.force_i, -ji.force_i),
                (ij.torque_i, ji.torque_j),
                (ij.torque_j, ji.torque_i),
            ] {
                assert!((a - b).norm() <= 1e-12 * a.norm().max(1.0), "{a} vs {b}");
            }
            assert!(ij.force_i.norm() > 0.0);
        }
    }

    /// Draws depend on the key and the step only: the same key and step give the same
    /// bits, any other key or step other numbers; over 2e5 draws each deviate has mean
    /// 0 and variance 1 within 5 standard errors (sd of the mean 1/sqrt(n) = 0.0022, of
    /// the variance sqrt(2/n) = 0.0032), and deviates of one draw are uncorrelated. The
    /// shape, pooled over the six deviates (m = 1.2e6): the fourth moment 3 within 5
    /// standard errors (sd sqrt(96/m) = 0.0089) and the fraction beyond 3 sd
    /// 2.70e-3 within 5 standard errors (sd sqrt(p/m) = 4.7e-5): the ziggurat's tail.
    #[test]
    fn deviates_are_keyed_standard_normals() {
        let noise = ThermalNoise::new(1.0, 1.0, 42);
        let a = noise.deviates(NoiseKey::Pair(3, 8), 17);
        assert_eq!(a, noise.clone().deviates(NoiseKey::Pair(3, 8), 17));
        assert_ne!(a, noise.deviates(NoiseKey::Pair(3, 8), 18));
        assert_ne!(a, noise.deviates(NoiseKey::Pair(3, 9), 17));
        assert_ne!(a, noise.deviates(NoiseKey::Particle(3), 17));
        assert_ne!(
            a,
            ThermalNoise::new(1.0, 1.0, 43).deviates(NoiseKey::Pair(3, 8), 17)
        );
        let draws = 200_000;
        let mut sum = DVector::<f64>::zeros(6);
        let mut outer = DMatrix::<f64>::zeros(6, 6);
        let (mut fourth, mut beyond_three) = (0.0, 0usize);
        for k in 0..draws {
            let key = if k % 2 == 0 {
                NoiseKey::Particle(k as u32)
            } else {
                NoiseKey::Pair(k as u32, 7)
            };
            let [x, y] = noise.deviates(key, k as u64 / 1000);
            let v = DVector::from_iterator(6, x.iter().chain(y.iter()).copied());
            sum += &v;
            outer += &v * v.transpose();
            fourth += v.iter().map(|x| x.powi(4)).sum::<f64>();
            beyond_three += v.iter().filter(|x| x.abs() > 3.0).count();
        }
        let n = draws as f64;
        let m = 6.0 * n;
        assert!(
            (fourth / m - 3.0).abs() < 5.0 * (96.0 / m).sqrt(),
            "<d^4> = {}",
            fourth / m
        );
        let tail = 2.6998e-3;
        let measured = beyond_three as f64 / m;
        assert!(
            (measured - tail).abs() < 5.0 * (tail / m).sqrt(),
            "P(|d| > 3) = {measured:e}"
        );
        for a in 0..6 {
            assert!((sum[a] / n).abs() < 5.0 / n.sqrt(), "mean {}", sum[a] / n);
            for b in 0..6 {
                let expected = if a == b { 1.0 } else { 0.0 };
                let tolerance = 5.0
                    * if a == b {
                        (2.0 / n).sqrt()
                    } else {
                        1.0 / n.sqrt()
                    };
                assert!(
                    (outer[(a, b)] / n - expected).abs() < tolerance,
                    "<d{a} d{b}> = {}",
                    outer[(a, b)] / n
                );
            }
        }
    }
}
