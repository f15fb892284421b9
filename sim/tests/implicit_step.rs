//! The implicit step (docs/physics.md section 5) against independent references: the
//! squeeze of two spheres against an accurate solution of the same ODE at 100 times the
//! explicit step, no dissipation in rigid rotation, no energy created by the dissipative
//! update, and the stability bound of a lubricated contact.
use rand::{Rng, SeedableRng};
use sim::forces::lubrication::{gap, LubricationCoefficients};
use sim::input::integrator::Integrator;
use sim::input::scene::Scene;
use sim::integrate::simulation::Simulation;
use sim::integrate::timestep::damped_spring_limit;
use sim::state::particles::Particles;
use sim::Vec3;
use std::f64::consts::PI;

mod common;
use common::push_together;

fn scene(forces: &str, run: &str) -> Scene {
    let text = format!(
        "[box]\nl_x = 12\nl_y = 12\nl_z = 12\n[particles]\nphi = 0.3\nradii = [1.0]\n[fluid]\n\
         profile = \"0.1*sin(2*pi*y/L)\"\n[forces]\n{forces}\n[run]\n{run}\n"
    );
    Scene::from_toml(&text, false).expect("valid test scene")
}

/// Two unit spheres on the x axis at gap `xi`, at rest.
fn pair(xi: f64) -> Particles {
    let x_i = Vec3::new(3.0, 6.0, 6.0);
    let x_j = x_i + Vec3::x() * 2.0 * (1.0 + 0.5 * xi);
    Particles::at_rest(vec![x_i, x_j], vec![1.0, 1.0], vec![0, 0], 1.0)
}

fn current_gap(s: &Simulation) -> f64 {
    gap((s.particles.pos[1] - s.particles.pos[0]).norm(), 1.0, 1.0)
}

/// The gap of two unit spheres pushed together by `f` under the squeeze resistance alone,
/// `m_red dw/dt = -f - X11A(xi) w`, `dxi/dt = w` (units a = 1: xi = h), by classical RK4 at
/// a step far below the stiffness time; the gap at each multiple of `every`.
fn reference_gaps(xi0: f64, f: f64, every: f64, samples: usize) -> Vec<f64> {
    let c = LubricationCoefficients::new(1.0, 1.0, 1.0, 1e-3, 0.05);
    let m_red = 0.5 * 4.0 / 3.0 * PI;
    let rate = |(xi, w): (f64, f64)| (w, (-f - c.x11a(xi) * w) / m_red);
    let h = every / 2000.0;
    let (mut state, mut out) = ((xi0, 0.0), Vec::with_capacity(samples));
    for _ in 0..samples {
        for _ in 0..2000 {
            let k1 = rate(state);
            let k2 = rate((state.0 + 0.5 * h * k1.0, state.1 + 0.5 * h * k1.1));
            let k3 = rate((state.0 + 0.5 * h * k2.0, state.1 + 0.5 * h * k2.1));
            let k4 = rate((state.0 + h * k3.0, state.1 + h * k3.1));
            state.0 += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            state.1 += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
        out.push(state.0);
    }
    out
}

#[test]
fn squeeze_follows_the_reference_solution_at_100_times_the_explicit_step() {
    let forces = "contact = false\ndrag = false";
    let explicit = scene(forces, "integrator = \"explicit\"");
    let old_limit = explicit.timestep.dt;
    let (xi0, f) = (0.04, 0.05);
    for factor in [10.0, 100.0] {
        let dt = factor * old_limit;
        let implicit = scene(forces, &format!("dt = {dt}"));
        assert_eq!(implicit.file.run.integrator, Integrator::Implicit);
        let mut s = Simulation::new(&implicit, pair(xi0)).unwrap();
        push_together(&mut s, f);
        let steps_per_sample = 100;
        let every = steps_per_sample as f64 * dt;
        let samples = (200.0 / every).ceil() as usize;
        let reference = reference_gaps(xi0, f, every, samples);
        let mut worst: f64 = 0.0;
        for expected in &reference {
            s.advance(steps_per_sample).unwrap();
            worst = worst.max((current_gap(&s) - expected).abs() / expected);
        }
        let last = reference[samples - 1];
        assert!(
            last < 0.4 * xi0,
            "the reference must close the gap a lot ({last})"
        );
        assert!(
            worst < 0.01,
            "dt = {factor} x the explicit step: gap off the reference by {worst:.2e} (relative)"
        );
    }
}

/// Velocity change of one implicit step for a pair at gap `xi` moving with `v_i`, `v_j`
/// and spins `omega` (both), no other load.
fn velocity_change(xi: f64, v_i: Vec3, v_j: Vec3, omega: Vec3) -> f64 {
    let s = scene("contact = false\ndrag = false", "dt = 1e-3");
    let mut p = pair(xi);
    p.vel = vec![v_i, v_j];
    p.omega = vec![omega, omega];
    let mut sim = Simulation::new(&s, p).unwrap();
    let before: Vec<Vec3> = sim.particles.vel.clone();
    sim.step().unwrap();
    sim.particles
        .vel
        .iter()
        .zip(&before)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max)
}

#[test]
fn a_pair_in_rigid_rotation_is_not_slowed_down() {
    // Rotation about z through the pair's centre at rate w: v = w z x (x - c), spins w z.
    let (xi, w) = (0.01, 0.3);
    let arm = Vec3::x() * (1.0 + 0.5 * xi);
    let spin = Vec3::z() * w;
    let rigid = velocity_change(xi, spin.cross(&-arm), spin.cross(&arm), spin);
    // The same relative sliding velocity without the matching spins is damped.
    let sliding = velocity_change(xi, spin.cross(&-arm), spin.cross(&arm), Vec3::zeros());
    assert!(sliding > 1e-3, "sliding pair barely damped: {sliding}");
    assert!(
        rigid < 0.05 * sliding,
        "rigid rotation changes the velocities by {rigid:.3e} (sliding: {sliding:.3e})"
    );
}

#[test]
fn the_dissipative_update_never_creates_kinetic_energy() {
    let s = scene("contact = false\ndrag = false", "dt = 0.02");
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    for trial in 0..20 {
        let mut p = sim::input::initial_state::initial_particles(&s).unwrap();
        // Squeeze the packing so that many pairs are inside the lubrication range.
        for x in p.pos.iter_mut() {
            *x *= 0.99;
        }
        for v in p.vel.iter_mut().chain(p.omega.iter_mut()) {
            *v = Vec3::from_fn(|_, _| rng.gen_range(-0.1..0.1));
        }
        let mut sim = Simulation::new(&s, p).unwrap();
        // Drift and the (zero) conservative loads leave the kinetic energy as it is, so
        // the step's change is the dissipative update's.
        let before = sim.particles.kinetic_energy();
        sim.step().unwrap();
        let after = sim.particles.kinetic_energy();
        assert!(
            sim.last_solve().iterations > 1,
            "trial {trial}: no coupled pairs"
        );
        assert!(
            after <= before * (1.0 + 1e-9),
            "trial {trial}: kinetic energy {before} -> {after}"
        );
        assert!(after < 0.999 * before, "trial {trial}: nothing dissipated");
    }
}

/// Distance from the equilibrium overlap `f / k_n` after `steps` implicit steps of two
/// touching unit spheres pushed together by `f`, started 1e-3 away from it, at `dt`.
fn perturbation_after(dt: f64, steps: u64) -> f64 {
    let f = 200.0;
    let equilibrium = f / 1e4;
    let s = scene("drag = false", &format!("dt = {dt}"));
    let mut sim = Simulation::new(&s, pair(-(equilibrium + 1e-3))).unwrap();
    push_together(&mut sim, f);
    sim.advance(steps).unwrap();
    (-current_gap(&sim) - equilibrium).abs()
}

#[test]
fn a_lubricated_contact_is_stable_below_the_damped_spring_limit_only() {
    let c = LubricationCoefficients::new(1.0, 1.0, 1.0, 1e-3, 0.05);
    let m_red = 0.5 * 4.0 / 3.0 * PI;
    let limit = damped_spring_limit(m_red, 1e4, c.x11a(1e-3));
    assert!((damped_spring_limit(m_red, 1e4, 0.0) - 2.0 * (m_red / 1e4).sqrt()).abs() < 1e-15);
    // The overlap stays inside the contact, where the law is linear: the perturbation
    // shrinks (amplification about -0.8 per step) below the limit, grows (about -1.2)
    // above it.
    let below = perturbation_after(0.9 * limit, 6);
    let above = perturbation_after(1.1 * limit, 6);
    assert!(
        below < 0.5e-3,
        "perturbation {below:.2e} at 0.9 x the limit"
    );
    assert!(above > 2e-3, "perturbation {above:.2e} at 1.1 x the limit");
}
