//! Blow-up detection and the Stokes-number check (docs/physics.md sections 1 and 5).
use sim::input::initial_state::initial_particles;
use sim::input::scene::Scene;
use sim::integrate::simulation::Simulation;
use sim::SimError;

fn dense(run: &str) -> Scene {
    let text = format!(
        "[box]\nl_x = 10\nl_y = 12\nl_z = 10\n[particles]\nphi = 0.58\n[fluid]\nprofile = \"0.2*sin(2*pi*y/L)\"\n[run]\n{run}\n"
    );
    Scene::from_toml(&text, false).unwrap()
}

#[test]
fn a_time_step_far_above_the_stability_limit_is_caught_not_silent() {
    // Explicit: 20 times the lubrication limit; implicit: 3 times the damped contact limit.
    let whats: Vec<String> = ["integrator = \"explicit\"\ndt_factor = 20.0", "dt = 3.0"]
        .iter()
        .map(|run| time_step_is_caught(run))
        .collect();
    assert!(whats.iter().any(|w| w.contains("overlap")), "{whats:?}");
}

/// The blow-up of `run` on the dense scene: checked, and what it found returned.
fn time_step_is_caught(run: &str) -> String {
    let scene = dense(run);
    let mut sim = Simulation::new(&scene, initial_particles(&scene).unwrap()).unwrap();
    match sim.advance(20_000) {
        Err(SimError::BlowUp {
            step,
            particle,
            what,
            cause,
            ..
        }) => {
            assert!(step > 0 && particle < sim.particles.len());
            assert!(cause.contains("time step"), "cause: {cause}");
            // An overlap also names the two physical causes: soft contacts, a jammed flow.
            if what.contains("overlap") {
                assert!(
                    cause.contains("forces.k_n") && cause.contains("particles.phi"),
                    "cause: {cause}"
                );
            }
            what
        }
        other => panic!("{run}: expected a blow-up, got {other:?}"),
    }
}

#[test]
fn the_automatic_time_step_is_stable_on_the_same_scene() {
    let scene = dense("");
    let mut sim = Simulation::new(&scene, initial_particles(&scene).unwrap()).unwrap();
    sim.advance(20_000).unwrap();
    assert!(sim
        .particles
        .vel
        .iter()
        .all(|v| v.iter().all(|c| c.is_finite())));
    assert!(sim.contacts.max_overlap_ratio < 0.05);
}

#[test]
fn a_large_stokes_number_warns_and_strict_refuses() {
    let text = "[box]\nl_x = 8\nl_y = 12\nl_z = 8\n[particles]\nphi = 0.5\nrho = 20\n[fluid]\nprofile = \"0.1*sin(2*pi*y/L)\"\n";
    let lenient = Scene::from_toml(text, false).unwrap();
    assert!(lenient.stokes > 0.1);
    assert!(lenient.warnings.iter().any(|w| w.contains("Stokes")));
    match Scene::from_toml(text, true) {
        Err(SimError::Field { field, message }) => {
            assert_eq!(field, "particles.rho");
            assert!(message.contains("Stokes"));
        }
        other => panic!("expected a refusal, got {:?}", other.map(|s| s.stokes)),
    }
}

/// The explicit step at 10 times its automatic dt does not blow up on the tiny scene but
/// its dynamics are wrong (momentum residual 0.62 against 0.003 at the automatic dt): the
/// run fails saying so, and at the automatic dt it finishes.
#[test]
fn a_run_whose_momentum_balance_fails_is_a_failed_run() {
    let path =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/scenes/good/tiny.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let with = |dt_factor: f64| {
        let text = text.replace(
            "[run]",
            &format!("[run]\nintegrator = \"explicit\"\ndt_factor = {dt_factor}"),
        );
        let scene = Scene::from_toml(&text, false).unwrap();
        sim::run::run(&scene, &Default::default(), &mut |_, _| {})
    };
    match with(10.0) {
        Err(SimError::MomentumImbalance {
            residual, limit, ..
        }) => {
            assert!(residual > limit && limit == sim::run::MOMENTUM_RESIDUAL_MAX)
        }
        other => panic!("expected a momentum imbalance, got {:?}", other.map(|_| ())),
    }
    let residual = with(1.0).unwrap().summary.momentum_residual.unwrap();
    assert!(
        residual < 0.1 * sim::run::MOMENTUM_RESIDUAL_MAX,
        "{residual}"
    );
}
