//! docs/physics.md section 9 invariants on the real force loop and integrator: equal and opposite
//! pair forces, the squeeze velocity F / X11A, and the analytic drag relaxation.
use rand::{Rng, SeedableRng};
use sim::forces::lubrication::LubricationCoefficients;
use sim::input::scene::Scene;
use sim::integrate::simulation::Simulation;
use sim::state::particles::Particles;
use sim::Vec3;
use std::f64::consts::PI;

mod common;
use common::push_together;

fn scene(extra_forces: &str, extra_run: &str) -> Scene {
    let text = format!(
        "[box]\nl_x = 12\nl_y = 12\nl_z = 12\n[particles]\nphi = 0.3\n[fluid]\nprofile = \"0.1*sin(2*pi*y/L)\"\n\
         [forces]\n{extra_forces}\n[run]\n{extra_run}\n"
    );
    Scene::from_toml(&text, false).expect("valid test scene")
}

/// Positions indexed by particle identity.
fn by_id(p: &Particles) -> Vec<Vec3> {
    let mut pos = vec![Vec3::zeros(); p.len()];
    for (k, &id) in p.id.iter().enumerate() {
        pos[id as usize] = p.pos[k];
    }
    pos
}

fn two_particles(x_i: Vec3, x_j: Vec3, a_i: f64, a_j: f64) -> Particles {
    Particles::at_rest(vec![x_i, x_j], vec![a_i, a_j], vec![0, 1], 1.0)
}

#[test]
fn pair_forces_cancel_in_a_random_dense_system() {
    let scene = scene("drag = false\nmu_p = 0.5", "");
    let mut p = sim::input::initial_state::initial_particles(&scene).unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(3);
    // Squeeze the configuration a little so that contacts and lubrication both act.
    for x in p.pos.iter_mut() {
        *x *= 0.985;
    }
    for v in p.vel.iter_mut().chain(p.omega.iter_mut()) {
        *v = Vec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
    }
    let sim = Simulation::new(&scene, p).unwrap();
    assert!(sim.contacts.contacts > 0, "the test needs contacts");
    let total: Vec3 = sim.particles.force.iter().sum();
    let scale: f64 = sim.particles.force.iter().map(|f| f.norm()).sum();
    assert!(scale > 0.0);
    assert!(
        total.norm() < 1e-12 * scale,
        "net pair force {} of {}",
        total.norm(),
        scale
    );
}

#[test]
fn same_thread_count_same_forces_and_threads_agree_to_round_off() {
    let scene = scene("", "");
    let p = sim::input::initial_state::initial_particles(&scene).unwrap();
    // Positions in the order of the particles' identities (the arrays are re-sorted in space).
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut s = Simulation::new(&scene, p.clone()).unwrap();
            s.advance(300).unwrap();
            by_id(&s.particles)
        })
    };
    let (a, b, c) = (run(2), run(2), run(1));
    assert_eq!(a, b, "same seed and thread count must be bitwise identical");
    let max_dev = a
        .iter()
        .zip(&c)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    assert!(max_dev < 1e-9, "1 and 2 threads differ by {max_dev}");
}

#[test]
fn approaching_spheres_reach_the_squeeze_velocity() {
    for (a_i, a_j) in [(1.0, 1.0), (1.0, 1.4)] {
        let mut scene = scene("contact = false\ndrag = false", "");
        scene.file.particles.radii = vec![a_i, a_j];
        let scene = Scene::from_file(scene.file, false).unwrap();
        let xi0 = 0.04;
        let x_i = Vec3::new(3.0, 6.0, 6.0);
        let x_j = x_i + Vec3::x() * (a_i + a_j) * (1.0 + 0.5 * xi0);
        let mut s = Simulation::new(&scene, two_particles(x_i, x_j, a_i, a_j)).unwrap();
        let f = 0.05;
        push_together(&mut s, f);
        let (first, second) = if s.particles.id[0] == 0 {
            (0, 1)
        } else {
            (1, 0)
        };
        let c = LubricationCoefficients::new(a_i, a_j, 1.0, 1e-3, 0.05);
        let mut checked = 0;
        for _ in 0..400 {
            s.advance(50).unwrap();
            let r = s.particles.pos[second] - s.particles.pos[first];
            let xi = sim::forces::lubrication::gap(r.norm(), a_i, a_j);
            if xi < 0.003 {
                break;
            }
            let closing = (s.particles.vel[first] - s.particles.vel[second]).x;
            let expected = f / c.x11a(xi);
            if s.time > 20.0 * s.timestep.dt * 50.0 {
                assert!(
                    (closing - expected).abs() < 0.02 * expected,
                    "xi {xi}: {closing} vs F/X11A {expected}"
                );
                checked += 1;
            }
        }
        assert!(checked > 20, "too few checks ({checked})");
    }
}

/// Largest deviation from `u (1 - exp(-t / tau))` over a relaxation of 2.5 tau at
/// `dt = tau / steps_per_tau`.
fn relaxation_error(steps_per_tau: f64) -> f64 {
    let (a, rho, eta) = (1.4, 1.0, 1.0);
    let m = 4.0 / 3.0 * PI * rho * a * a * a;
    let tau = m / (6.0 * PI * eta * a);
    let mut scene = scene("", &format!("dt = {}", tau / steps_per_tau));
    scene.file.particles.radii = vec![1.0, a];
    let scene = Scene::from_file(scene.file, false).unwrap();
    let y = 2.0;
    let p = Particles::at_rest(vec![Vec3::new(6.0, y, 6.0)], vec![a], vec![1], rho);
    let mut s = Simulation::new(&scene, p).unwrap();
    let u = scene.profile.u(y);
    let mut worst: f64 = 0.0;
    for _ in 0..50 {
        s.advance((steps_per_tau / 20.0) as u64).unwrap();
        // No force along y: the particle stays at y, where the streaming velocity is u.
        let expected = u * (1.0 - (-s.time / tau).exp());
        worst = worst.max((s.particles.vel[0].x - expected).abs() / u.abs());
        assert_eq!(s.particles.pos[0].y, y);
    }
    worst
}

#[test]
fn a_lone_particle_relaxes_to_the_streaming_velocity() {
    // Velocity Verlet with forces at the half-kicked velocity (the seeds' LAMMPS scheme)
    // is first order in dt / tau for the drag: the error halves with dt.
    let (coarse, fine) = (relaxation_error(200.0), relaxation_error(400.0));
    assert!(coarse < 0.5 / 200.0, "error {coarse} at dt = tau/200");
    let ratio = fine / coarse;
    assert!(
        (0.4..0.6).contains(&ratio),
        "error ratio {ratio} on halving dt (first order expected)"
    );
}
