//! Homogeneous simple shear between Lees-Edwards images (docs/physics.md section 10): the
//! sliding images against a brute-force search over image copies, the remap of a particle
//! that leaves through a y face, pair loads through a sliding image, and the shear stress
//! linear in the shear rate.
use rand::{Rng, SeedableRng};
use sim::forces::force_field::ForceField;
use sim::input::scene::Scene;
use sim::integrate::simulation::Simulation;
use sim::run::{run, RunOptions};
use sim::state::particles::Particles;
use sim::state::periodic_box::PeriodicBox;
use sim::Vec3;
use std::path::PathBuf;

const LEN: [f64; 3] = [10.0, 12.0, 9.0];
const GDOT: f64 = 0.05;

/// A sheared box at a time where the offset is not a round number.
fn sheared_box(t: f64) -> PeriodicBox {
    let mut pbox = PeriodicBox::sheared(LEN, GDOT);
    pbox.set_time(t);
    pbox
}

/// Half the shortest box side: a copy closer than this is the unique nearest one, and
/// interacting pairs are always closer (the scene validation ensures it).
const UNIQUE: f64 = 4.5;

/// The nearest copy of `x_j` to `x_i` among every image `x_j + n_y (offset, L_y, 0) +
/// n_x (L_x, 0, 0) + n_z (0, 0, L_z)` with `|n| <= 2`, and its `n_y`: the definition of the
/// sliding images, searched without the box's own arithmetic.
fn brute_force_image(x_i: &Vec3, x_j: &Vec3, offset: f64) -> (Vec3, i32) {
    let mut best = (Vec3::repeat(f64::INFINITY), 0);
    for n_y in -2..=2 {
        for n_x in -2..=2 {
            for n_z in -2..=2 {
                let image = x_j
                    + Vec3::new(
                        n_y as f64 * offset + n_x as f64 * LEN[0],
                        n_y as f64 * LEN[1],
                        n_z as f64 * LEN[2],
                    );
                let d = image - x_i;
                if d.norm() < best.0.norm() {
                    best = (d, n_y);
                }
            }
        }
    }
    best
}

fn random_point(rng: &mut impl Rng) -> Vec3 {
    Vec3::new(
        rng.gen::<f64>() * LEN[0],
        rng.gen::<f64>() * LEN[1],
        rng.gen::<f64>() * LEN[2],
    )
}

#[test]
fn separation_is_the_nearest_sliding_image() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    let mut across = 0;
    for t in [0.0, 3.7, 16.1, 123.4] {
        let pbox = sheared_box(t);
        assert!((0.0..LEN[0]).contains(&pbox.shear_offset()));
        for _ in 0..2000 {
            let (x_i, x_j) = (random_point(&mut rng), random_point(&mut rng));
            let (d, n) = pbox.image(&x_i, &x_j);
            let (expected, n_expected) = brute_force_image(&x_i, &x_j, pbox.shear_offset());
            if expected.norm() >= UNIQUE {
                continue;
            }
            assert!((d - expected).norm() < 1e-12, "t {t}: {d} vs {expected}");
            assert_eq!(n, n_expected);
            across += (n != 0) as usize;
        }
    }
    assert!(across > 300, "too few pairs through a y face: {across}");
}

#[test]
fn a_particle_leaving_through_a_y_face_is_remapped() {
    let pbox = sheared_box(3.0);
    let offset = GDOT * LEN[1] * 3.0;
    for (start, v, expected_x, dv_x) in [
        // Out through the top: back in at the bottom, shifted by -offset, slower by gdot L_y.
        (
            Vec3::new(9.5, 12.3, 4.0),
            Vec3::new(0.2, 0.1, -0.3),
            Vec3::new(9.5 - offset, 0.3, 4.0),
            -GDOT * LEN[1],
        ),
        // Out through the bottom: back in at the top, shifted by +offset (wrapped in x).
        (
            Vec3::new(9.5, -0.2, 8.5),
            Vec3::new(0.2, -0.1, 0.0),
            Vec3::new(9.5 + offset - LEN[0], 11.8, 8.5),
            GDOT * LEN[1],
        ),
    ] {
        let (mut x, mut u) = (start, v);
        pbox.wrap(&mut x, &mut u);
        assert!((x - expected_x).norm() < 1e-12, "{x} vs {expected_x}");
        assert!((u - (v + Vec3::new(dv_x, 0.0, 0.0))).norm() < 1e-15, "{u}");
        // The remapped particle is the same physical image: its separation from any
        // particle inside is unchanged.
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        let mut compared = 0;
        while compared < 100 {
            let other = random_point(&mut rng);
            let before = brute_force_image(&other, &start, pbox.shear_offset()).0;
            if before.norm() < UNIQUE {
                assert!((pbox.separation(&other, &x) - before).norm() < 1e-12);
                compared += 1;
            }
        }
    }
}

fn tiny_shear() -> Scene {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/scenes/good/tiny_shear.toml");
    Scene::from_path(&path, false).unwrap()
}

/// A scene whose particles feel nothing while apart (contacts only).
fn ballistic_scene() -> Scene {
    let mut file = tiny_shear().file;
    file.forces.drag = false;
    file.forces.lubrication = false;
    Scene::from_file(file, false).unwrap()
}

#[test]
fn the_integrator_remaps_a_particle_crossing_a_y_face() {
    let scene = ballistic_scene();
    let [l_x, l_y, _] = scene.box_len;
    let gdot = scene.shear_rate().unwrap();
    // Two particles far apart; the first leaves through the top face within the first step.
    let pos = vec![Vec3::new(1.0, l_y - 1e-4, 2.0), Vec3::new(5.0, 5.0, 6.0)];
    let mut p = Particles::at_rest(pos, vec![1.0, 1.0], vec![0, 0], 1.0);
    let v0 = Vec3::new(0.3, 0.5, 0.1);
    p.vel[0] = v0;
    let mut sim = Simulation::new(&scene, p).unwrap();
    sim.advance(1).unwrap();
    let dt = sim.timestep.dt;
    let k = sim.particles.id.iter().position(|&id| id == 0).unwrap();
    let offset = (gdot * l_y * dt).rem_euclid(l_x);
    let expected = Vec3::new(
        1.0 + v0.x * dt - offset,
        l_y - 1e-4 + v0.y * dt - l_y,
        2.0 + v0.z * dt,
    );
    assert!(
        (sim.particles.pos[k] - expected).norm() < 1e-12,
        "{} vs {expected}",
        sim.particles.pos[k]
    );
    let v = sim.particles.vel[k];
    assert!(
        (v - (v0 - Vec3::new(gdot * l_y, 0.0, 0.0))).norm() < 1e-15,
        "{v}"
    );
    // Its velocity relative to the affine flow `gdot (y - L_y/2)`, taken at its unwrapped
    // height (above the box) before the remap, is unchanged by it.
    let y = sim.particles.pos[k].y;
    let unwrapped = v0.x - gdot * (y + l_y - 0.5 * l_y);
    assert!((v.x - scene.profile.u(y) - unwrapped).abs() < 1e-12);
}

/// Load on particle 0 of a pair of unit spheres at `x_0`, `x_1` with velocities `v_0`, `v_1`.
fn pair_force(scene: &Scene, pbox: &PeriodicBox, x: [Vec3; 2], v: [Vec3; 2]) -> Vec3 {
    let field = ForceField::from_file(&scene.file);
    let mut p = Particles::at_rest(x.to_vec(), vec![1.0, 1.0], vec![0, 0], 1.0);
    p.vel = v.to_vec();
    field
        .pair(&p, pbox, 0, 1, None, 0.0)
        .expect("within the lubrication range")
        .load
        .force_i
}

#[test]
fn a_pair_across_a_y_face_moves_with_the_sliding_image() {
    let scene = tiny_shear();
    let [l_x, l_y, _] = scene.box_len;
    let gdot = scene.shear_rate().unwrap();
    let mut pbox = PeriodicBox::sheared(scene.box_len, gdot);
    pbox.set_time(7.3);
    let offset = pbox.shear_offset();
    // In the lubrication range, not touching: gap 0.03 (xi = 0.03).
    let r = Vec3::new(0.3, 2.0, 0.15).normalize() * 2.03;
    let x_0 = Vec3::new(4.0, l_y - 0.8, 3.0);
    // Particle 1 sits at x_0 + r through its image above: in the box it is one L_y lower
    // and `offset` to the left.
    let x_1 = Vec3::new(
        (x_0.x + r.x - offset).rem_euclid(l_x),
        x_0.y + r.y - l_y,
        x_0.z + r.z,
    );
    assert!((pbox.separation(&x_0, &x_1) - r).norm() < 1e-12);

    // Rigid translation through the image: no relative motion, no load.
    let v = Vec3::new(0.02, -0.01, 0.005);
    let rigid = pair_force(
        &scene,
        &pbox,
        [x_0, x_1],
        [v, v - Vec3::new(gdot * l_y, 0.0, 0.0)],
    );
    assert!(rigid.norm() < 1e-12, "{rigid}");
    // Without the image velocity the same pair would be sheared at gdot L_y.
    let naive = pair_force(&scene, &pbox, [x_0, x_1], [v, v]);
    assert!(naive.norm() > 1e-2, "{naive}");

    // Both at the affine velocity: the same load as the same pair inside the box.
    let affine = |x: &Vec3| Vec3::new(scene.profile.u(x.y), 0.0, 0.0);
    let across = pair_force(&scene, &pbox, [x_0, x_1], [affine(&x_0), affine(&x_1)]);
    let inside = [Vec3::new(4.0, 3.0, 3.0), Vec3::new(4.0, 3.0, 3.0) + r];
    let reference = pair_force(
        &scene,
        &pbox,
        inside,
        [affine(&inside[0]), affine(&inside[1])],
    );
    assert!(reference.norm() > 1e-4, "{reference}");
    assert!(
        (across - reference).norm() < 1e-9 * reference.norm(),
        "{across} vs {reference}"
    );
}

/// Box rheology and binned velocity of `tiny_shear` at shear rate `gdot` and its Stokes
/// number (the density scales as 1 / gdot).
fn sheared_run(
    gdot: f64,
) -> (
    sim::sampling::shear_rheology::ShearRheology,
    Vec<f64>,
    Vec<f64>,
) {
    let mut file = tiny_shear().file;
    file.fluid.shear_rate = Some(gdot);
    file.run.window_strain = 0.5;
    file.run.snapshots = 100;
    file.run.blocks = 5;
    let scene = Scene::from_file(file, false).unwrap();
    let out = run(&scene, &RunOptions::default(), &mut |_, _| {}).unwrap();
    (
        out.summary.shear.unwrap(),
        out.profile.y,
        out.profile.mean.u,
    )
}

#[test]
fn shear_stress_is_linear_in_the_shear_rate() {
    let (slow, y, u) = sheared_run(0.02);
    let (fast, _, _) = sheared_run(0.04);
    for r in [&slow, &fast] {
        // Dissipative: the (compression-positive) shear stress opposes the shear.
        assert!(r.sigma_xy.mean < 0.0 && r.eta_r.mean > 1.0, "{r:?}");
        assert!(r.p.mean > 0.0, "{r:?}");
    }
    let ratio = fast.sigma_xy.mean / slow.sigma_xy.mean;
    let ratio_se = ratio
        * ((fast.sigma_xy.se / fast.sigma_xy.mean).powi(2)
            + (slow.sigma_xy.se / slow.sigma_xy.mean).powi(2))
        .sqrt();
    assert!(
        (ratio - 2.0).abs() < 3.0 * ratio_se + 0.05,
        "sigma_xy ratio {ratio} +- {ratio_se}"
    );
    // The binned velocity follows the affine flow: least-squares slope within 10 % of gdot.
    let n = y.len() as f64;
    let (ym, um) = (y.iter().sum::<f64>() / n, u.iter().sum::<f64>() / n);
    let slope = y
        .iter()
        .zip(&u)
        .map(|(y, u)| (y - ym) * (u - um))
        .sum::<f64>()
        / y.iter().map(|y| (y - ym).powi(2)).sum::<f64>();
    assert!((slope / 0.02 - 1.0).abs() < 0.1, "slope {slope}");
}
