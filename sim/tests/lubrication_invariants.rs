//! docs/physics.md section 9 invariants of the lubrication law: purely dissipative, blind to rigid
//! motion to leading order in xi, and conserving angular momentum to that order; for size
//! ratios from 1/7 to 7 (colloid-grain mixtures, thesis chapter 5: 1 : 1.4 colloids and 5 : 7
//! grains), and the squeeze against the exact two-sphere lubrication limit.
use rand::{Rng, SeedableRng};
use sim::forces::lubrication::LubricationCoefficients;
use sim::Vec3;

/// Size ratios `a_j / a_i`: the colloids' 1 : 1.4, and the colloid-grain ratios up to 7
/// (a grain of radius 7 against a colloid of radius 1) both ways.
const BETAS: [f64; 7] = [1.0, 1.4, 1.0 / 1.4, 5.0, 1.0 / 5.0, 7.0, 1.0 / 7.0];
const XI_MIN: f64 = 1e-3;
const XI_MAX: f64 = 0.05;

fn gaps() -> Vec<f64> {
    (0..=20)
        .map(|k| XI_MIN * (XI_MAX / XI_MIN).powf(k as f64 / 20.0) * 0.999)
        .collect()
}

fn random_unit(rng: &mut impl Rng) -> Vec3 {
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

fn random_vec(rng: &mut impl Rng) -> Vec3 {
    Vec3::new(
        rng.gen_range(-1.0..1.0),
        rng.gen_range(-1.0..1.0),
        rng.gen_range(-1.0..1.0),
    )
}

#[test]
fn lubrication_power_is_never_positive() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    for beta in BETAS {
        let (a_i, a_j) = (1.0, beta);
        let c = LubricationCoefficients::new(a_i, a_j, 1.0, XI_MIN, XI_MAX);
        for xi in gaps() {
            for _ in 0..2000 {
                let n = random_unit(&mut rng);
                let (v_i, v_j) = (random_vec(&mut rng), random_vec(&mut rng));
                let (w_i, w_j) = (random_vec(&mut rng), random_vec(&mut rng));
                let l = c.load(xi, &n, &(v_j - v_i), &w_i, &w_j);
                let power = l.force_i.dot(&v_i) - l.force_i.dot(&v_j)
                    + l.torque_i.dot(&w_i)
                    + l.torque_j.dot(&w_j);
                // Scale: the largest single dissipation term.
                let scale = c.x11a(xi) * (v_j - v_i).norm_squared() + 1.0;
                assert!(
                    power <= 1e-12 * scale,
                    "beta {beta}, xi {xi}: power {power} > 0"
                );
            }
        }
    }
}

#[test]
fn an_approaching_pair_is_pushed_apart() {
    let c = LubricationCoefficients::new(1.0, 1.4, 1.0, XI_MIN, XI_MAX);
    let n = Vec3::x();
    let l = c.load(
        0.01,
        &n,
        &Vec3::new(-1.0, 0.0, 0.0),
        &Vec3::zeros(),
        &Vec3::zeros(),
    );
    // j approaches i along -n: the squeeze force on i points away from j.
    assert!(l.force_i.x < 0.0);
}

#[test]
fn rigid_motion_feels_no_lubrication_to_leading_order() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    for beta in BETAS {
        let (a_i, a_j) = (1.0, beta);
        let c = LubricationCoefficients::new(a_i, a_j, 1.0, XI_MIN, XI_MAX);
        for xi in gaps() {
            let n = random_unit(&mut rng);
            let dist = (a_i + a_j) * (1.0 + 0.5 * xi);
            let x_i = random_vec(&mut rng) * 5.0;
            let x_j = x_i + n * dist;
            // Translation: exactly zero.
            let u = random_vec(&mut rng);
            let l = c.load(xi, &n, &(u - u), &Vec3::zeros(), &Vec3::zeros());
            assert_eq!(
                l.force_i.norm() + l.torque_i.norm() + l.torque_j.norm(),
                0.0
            );
            // Rotation about the origin with angular velocity w: v = w x x, spin = w.
            let w = random_unit(&mut rng);
            let (v_i, v_j) = (w.cross(&x_i), w.cross(&x_j));
            let l = c.load(xi, &n, &(v_j - v_i), &w, &w);
            // One tangential term alone, for scale: Y11A |w x r|, and each sphere's own
            // rotational coefficient (Y11C, Y22C: a grain's is 7^3 a colloid's).
            let log = (1.0 / xi.max(XI_MIN)).ln();
            let scale_f = c.ya * log * w.cross(&n).norm() * dist;
            let rel_f = l.force_i.norm() / scale_f;
            let rel_t = (l.torque_i.norm() / c.yc11).max(l.torque_j.norm() / c.yc22) / log;
            assert!(
                rel_f < 2.0 * xi && rel_t < 2.0 * xi,
                "beta {beta} xi {xi}: residual force {rel_f}, torque {rel_t}"
            );
        }
    }
}

#[test]
fn flipped_b_terms_break_objectivity() {
    // The rigid-rotation test above is the one that catches a sign slip in Y11B, Y21B
    // (docs/physics.md section 4): with them flipped the residual is of order 2, not O(xi).
    let mut c = LubricationCoefficients::new(1.0, 1.4, 1.0, XI_MIN, XI_MAX);
    c.yb11 = -c.yb11;
    c.yb21 = -c.yb21;
    let n = Vec3::x();
    let w = Vec3::z();
    let dist = 2.4 * (1.0 + 0.5 * XI_MIN);
    let l = c.load(XI_MIN, &n, &w.cross(&(n * dist)), &w, &w);
    let scale = c.ya * (1.0 / XI_MIN).ln() * dist;
    assert!(l.force_i.norm() / scale > 1.0);
}

#[test]
fn angular_momentum_is_conserved_to_leading_order() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(5);
    for beta in BETAS {
        let (a_i, a_j) = (1.0, beta);
        let c = LubricationCoefficients::new(a_i, a_j, 1.0, XI_MIN, XI_MAX);
        for xi in gaps() {
            let n = random_unit(&mut rng);
            let dist = (a_i + a_j) * (1.0 + 0.5 * xi.max(0.0));
            let x_i = random_vec(&mut rng) * 3.0;
            let x_j = x_i + n * dist;
            let (v_i, v_j, w_i, w_j) = (
                random_vec(&mut rng),
                random_vec(&mut rng),
                random_vec(&mut rng),
                random_vec(&mut rng),
            );
            let l = c.load(xi, &n, &(v_j - v_i), &w_i, &w_j);
            let total = x_i.cross(&l.force_i) - x_j.cross(&l.force_i) + l.torque_i + l.torque_j;
            let scale =
                l.torque_i.norm() + l.torque_j.norm() + (x_j - x_i).cross(&l.force_i).norm();
            assert!(
                total.norm() <= 2.0 * xi.max(XI_MIN) * scale + 1e-12,
                "beta {beta} xi {xi}: {} of {}",
                total.norm(),
                scale
            );
        }
    }
}

#[test]
fn lubrication_vanishes_beyond_the_cutoff_and_saturates_below_xi_min() {
    let c = LubricationCoefficients::new(1.0, 1.4, 1.0, XI_MIN, XI_MAX);
    let n = Vec3::y();
    let dv = Vec3::new(0.3, -1.0, 0.2);
    assert_eq!(
        c.load(XI_MAX, &n, &dv, &Vec3::zeros(), &Vec3::zeros())
            .force_i,
        Vec3::zeros()
    );
    let at_min = c.load(XI_MIN, &n, &dv, &Vec3::zeros(), &Vec3::zeros());
    let overlapping = c.load(-0.01, &n, &dv, &Vec3::zeros(), &Vec3::zeros());
    assert_eq!(at_min, overlapping);
}

/// Independent of the Jeffrey-Onishi coefficients: two spheres squeezed at a surface gap h
/// much smaller than both radii meet the Reynolds force `6 pi eta a*^2 U / h`, `a*` the
/// reduced radius `a_i a_j / (a_i + a_j)`, up to the relative correction `O(xi ln xi)` of
/// the log term. Checked at xi = 1e-4 (below the shipped xi_min, so the regularisation is
/// set lower) for every ratio, and the squeeze is the same from either sphere.
#[test]
fn the_squeeze_meets_the_two_sphere_reynolds_limit_for_every_size_ratio() {
    let (eta, xi) = (0.7, 1e-4);
    for beta in BETAS {
        let (a_i, a_j) = (1.3, 1.3 * beta);
        let c = LubricationCoefficients::new(a_i, a_j, eta, 1e-6, XI_MAX);
        let h = 0.5 * xi * (a_i + a_j);
        let reduced = a_i * a_j / (a_i + a_j);
        let reynolds = 6.0 * std::f64::consts::PI * eta * reduced * reduced / h;
        let x11a = c.x11a(xi);
        let bound = 5.0 * xi * (1.0 / xi).ln();
        assert!(
            (x11a / reynolds - 1.0).abs() < bound,
            "beta {beta}: X11A {x11a}, Reynolds {reynolds}"
        );
        let swapped = LubricationCoefficients::new(a_j, a_i, eta, 1e-6, XI_MAX);
        assert!(
            (swapped.x11a(xi) / x11a - 1.0).abs() < 1e-12,
            "beta {beta}: {} from j against {x11a} from i",
            swapped.x11a(xi)
        );
    }
}

/// Exchange of i and j (docs/physics.md section 9): the same pair seen from j, with radii
/// swapped, `n -> -n`, `dv -> -dv` and the spins swapped, puts on j minus the force on i and
/// the same torques on each sphere, for every ratio from 1/7 to 7 and every gap. Fails on a
/// coefficient whose swapped form (`Y11B` against `Y21B`, `Y11C` against `Y22C`, `Y12C`)
/// does not match, to a relative 1e-12.
#[test]
fn exchanging_i_and_j_gives_opposite_forces_and_the_same_torques() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(29);
    for beta in BETAS {
        let (a_i, a_j) = (1.0, beta);
        let c = LubricationCoefficients::new(a_i, a_j, 1.0, XI_MIN, XI_MAX);
        let swapped = LubricationCoefficients::new(a_j, a_i, 1.0, XI_MIN, XI_MAX);
        for xi in gaps() {
            let n = random_unit(&mut rng);
            let dv = random_vec(&mut rng);
            let (w_i, w_j) = (random_vec(&mut rng), random_vec(&mut rng));
            let l = c.load(xi, &n, &dv, &w_i, &w_j);
            let m = swapped.load(xi, &(-n), &(-dv), &w_j, &w_i);
            let scale = l.force_i.norm() + l.torque_i.norm() + l.torque_j.norm();
            let mismatch = (m.force_i + l.force_i).norm()
                + (m.torque_i - l.torque_j).norm()
                + (m.torque_j - l.torque_i).norm();
            assert!(
                mismatch <= 1e-12 * scale,
                "beta {beta}, xi {xi}: mismatch {mismatch} of {scale}"
            );
        }
    }
}

/// The squeeze resistance is positive at every gap inside the cut-off, for every ratio,
/// and grows as the gap closes (the `1/xi` term dominates the log term).
#[test]
fn the_squeeze_resistance_is_positive_and_grows_as_the_gap_closes() {
    for beta in BETAS {
        let c = LubricationCoefficients::new(1.0, beta, 1.0, XI_MIN, XI_MAX);
        let values: Vec<f64> = gaps().into_iter().map(|xi| c.x11a(xi)).collect();
        assert!(values.iter().all(|&x| x > 0.0), "beta {beta}: {values:?}");
        assert!(
            values.windows(2).all(|w| w[0] >= w[1]),
            "beta {beta}: {values:?}"
        );
    }
}
