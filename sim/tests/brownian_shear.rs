//! Brownian suspensions in homogeneous shear (docs/physics.md section 11): the pair stress
//! sampled at the midpoints of the implicit Brownian steps, against the stress balance and
//! against the non-Brownian limit. Seeded, so they cannot flake.
use sim::input::scene::Scene;
use sim::output::run_summary::RunSummary;
use sim::run::{run, RunOptions};

/// A box of 10 a at phi 0.45 (about 70 spheres of radii 1 : 1.4 at equal volume) sheared
/// at gdot = 0.01, with `fluid` extra settings; four windows of 0.25 strain of warm-up, then
/// 2 strain of snapshots.
fn sheared(fluid: &str) -> RunSummary {
    let text = format!(
        "seed = 5\nbox = {{ l_x = 10.0, l_y = 10.0, l_z = 10.0 }}\n\
         particles = {{ phi = 0.45, radii = [1.0, 1.4], fractions = [0.733, 0.267], rho = 0.5 }}\n\
         fluid = {{ shear_rate = 0.01{fluid} }}\n\
         run = {{ window_strain = 0.25, sample_strain = 0.02, snapshots = 100, blocks = 10, \
         steady_chi2 = 1e9, max_strain = 5.0 }}\n"
    );
    let scene = Scene::from_toml(&text, false).expect("valid test scene");
    run(&scene, &RunOptions::default(), &mut |_, _| {})
        .expect("stable run")
        .summary
}

/// At Pe = 10 the lubrication stress, sampled at each step's midpoint with the step's mean
/// velocity, has a batch-means error far below the stress itself, and the bins' stress
/// balances the drag (`d sigma_xy / dy = f_x`, residual in units of the drag scale, 1 for
/// noise). Sampled at the end-of-step velocity `V' = 2 W - V`, whose stiff modes flip every
/// step, the same run had an error of 4x the mean and a residual of 80 (N = 1013).
#[test]
fn midpoint_sampling_keeps_the_lubrication_stress_out_of_the_noise() {
    let s = sheared(", peclet = 10.0");
    let part = |name: &str| s.stress_parts[name];
    let total = s.shear.expect("homogeneous shear").sigma_xy.mean.abs();
    let lub = part("sigma_xy_lubrication");
    assert!(
        lub.se < 0.1 * total,
        "lubrication {lub:?}, |sigma_xy| {total}"
    );
    let residual = s.stress_checks.balance_residual.expect("a sheared scene");
    assert!(residual < 3.0, "balance residual {residual}");
}

/// At Pe = 1e4 thermal motion no longer matters: `eta_r` of the Brownian step (midpoint,
/// dt capped for the noise) is that of the non-Brownian step (backward Euler, 3x longer
/// steps) within three combined standard errors plus 5 % (the two integrators' own
/// difference). An independent check: the two runs share no step, scheme or sampling.
#[test]
fn high_peclet_flow_meets_the_non_brownian_viscosity() {
    let brownian = sheared(", peclet = 1e4").shear.expect("shear").eta_r;
    let granular = sheared("").shear.expect("shear").eta_r;
    let tolerance = 3.0 * brownian.se.hypot(granular.se) + 0.05 * granular.mean;
    assert!(
        (brownian.mean - granular.mean).abs() < tolerance,
        "Pe = 1e4: {brownian:?}, kT = 0: {granular:?}"
    );
}

/// The automatic step of a Brownian scene is capped at `RELAXATION_STEP_LIMIT` velocity
/// relaxation times `m / (6 pi eta a)` of the smallest spheres (reports/brownian sections 5
/// and 9: at 3.2 of them eta_r is 15-25 % too high under shear, the Green-Kubo viscosity
/// 2.4x at rest), scaled by `run.dt_factor`, sheared or at rest; at rho = 0.5 the thermal
/// cap (0.32 relaxation times) is already the shorter, and without kT there is no cap.
#[test]
fn a_brownian_step_resolves_the_velocity_relaxation() {
    use sim::input::thermal_scales::RELAXATION_STEP_LIMIT;
    use sim::integrate::timestep::DtLimit;
    let step = |rho: f64, fluid: &str, run: &str| {
        let text = format!(
            "box = {{ l_x = 10.0, l_y = 10.0, l_z = 10.0 }}\n\
             particles = {{ phi = 0.45, radii = [1.0, 1.4], fractions = [0.733, 0.267], rho = {rho} }}\n\
             fluid = {{ {fluid} }}\nrun = {{ {run} }}\n"
        );
        Scene::from_toml(&text, false)
            .expect("valid test scene")
            .timestep
    };
    // a = 1, eta = 1: m / (6 pi eta a) = (4/3 pi rho) / (6 pi) = 2 rho / 9.
    let relaxation = |rho: f64| 2.0 * rho / 9.0;
    let sheared = "shear_rate = 0.01, peclet = 1.0";
    let light = step(0.05, sheared, "");
    assert_eq!(light.limit, DtLimit::Relaxation);
    assert!((light.dt / (RELAXATION_STEP_LIMIT * relaxation(0.05)) - 1.0).abs() < 1e-12);
    let halved = step(0.05, sheared, "dt_factor = 0.5");
    assert!((halved.dt / light.dt - 0.5).abs() < 1e-12, "{halved:?}");
    let at_rest = step(0.05, "kT = 0.0188", "");
    assert_eq!(at_rest.limit, DtLimit::Relaxation);
    assert!(
        (at_rest.dt / light.dt - 1.0).abs() < 1e-12,
        "{at_rest:?} against {light:?}"
    );
    let heavy_at_rest = step(0.5, "kT = 0.0188", "");
    assert_eq!(heavy_at_rest.limit, DtLimit::Thermal);
    let heavy = step(0.5, sheared, "");
    assert_eq!(heavy.limit, DtLimit::Thermal);
    assert!(
        heavy.dt < RELAXATION_STEP_LIMIT * relaxation(0.5),
        "{heavy:?}"
    );
    let granular = step(0.05, "shear_rate = 0.01", "");
    assert_ne!(granular.limit, DtLimit::Relaxation, "{granular:?}");
}
