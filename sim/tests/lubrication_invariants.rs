//! docs/physics.md section 9 invariants of the lubrication law: purely dissipative, blind to rigid
//! motion to leading order in xi, and conserving angular momentum to that order.
use rand::{Rng, SeedableRng};
use sim::forces::lubrication::LubricationCoefficients;
use sim::Vec3;

const BETAS: [f64; 3] = [1.0, 1.4, 1.0 / 1.4];
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
            // One tangential term alone, for scale: Y11A |w x r|.
            let log = (1.0 / xi.max(XI_MIN)).ln();
            let scale_f = c.ya * log * w.cross(&n).norm() * dist;
            let scale_t = c.yc11 * log;
            let rel_f = l.force_i.norm() / scale_f;
            let rel_t = l.torque_i.norm().max(l.torque_j.norm()) / scale_t;
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
