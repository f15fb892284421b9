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

/// A 10^3 box at phi 0.45 of the shipped bidisperse colloids at density `rho`, with the
/// `[fluid]` entries `fluid` and further TOML `more`.
fn small_brownian_scene(rho: f64, fluid: &str, more: &str) -> Scene {
    let text = format!(
        "box = {{ l_x = 10.0, l_y = 10.0, l_z = 10.0 }}\n\
         particles = {{ phi = 0.45, radii = [1.0, 1.4], fractions = [0.733, 0.267], rho = {rho} }}\n\
         fluid = {{ {fluid} }}\n{more}\n"
    );
    Scene::from_toml(&text, false).expect("valid test scene")
}

/// The automatic step of a Brownian scene (docs/physics.md section 11) in the shipped
/// grids' units (a = 1, eta = 1, kT = 6 pi 0.01, so D0 = kT / (6 pi eta a) = 0.01): the
/// diffusion limit `0.05 (0.05 a)^2 / (2 * 2 D0) = 3.125e-3` at rho 0.5, scaling as
/// 1 / kT until the relaxation limit; at rho = 0.05 the rotational relaxation
/// `RELAXATION_FRACTION * 0.3 m / (6 pi eta a)` (the fraction 0.175) is the shorter; in
/// homogeneous shear both are relaxed by Pe / 3, and from Pe = 100 on the
/// relaxation limit is dropped, so that at Pe 100 and 1e4 the step is within 1.5x of the
/// same scene without kT at rho 0.5 and 0.05 (the cost target); with the
/// seeds' sharp cut the squeeze relaxation at the cut-off caps it; friction is bounded by
/// its own spring, not by a share of it.
#[test]
fn the_brownian_step_follows_the_thermal_time_scales() {
    use sim::integrate::brownian_limits::RELAXATION_FRACTION;
    use sim::integrate::timestep::DtLimit;
    let step = |rho: f64, fluid: &str, more: &str| small_brownian_scene(rho, fluid, more).timestep;
    let kt = 6.0 * std::f64::consts::PI * 0.01;
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-9;
    let at_rest = step(0.5, &format!("kT = {kt}"), "");
    assert_eq!(at_rest.limit, DtLimit::Diffusion, "{at_rest:?}");
    assert!(close(at_rest.dt, 3.125e-3), "{at_rest:?}");
    // 1 / kT up to the rotational relaxation limit, 5.83e-3 at rho 0.5.
    let cooler = step(0.5, &format!("kT = {}", kt / 1.5), "");
    assert!(close(cooler.dt, 1.5 * at_rest.dt), "{cooler:?}");
    let colder = step(0.5, &format!("kT = {}", kt / 3.0), "");
    assert_eq!(colder.limit, DtLimit::Relaxation, "{colder:?}");
    let third = step(
        0.5,
        &format!("kT = {kt}"),
        "run = { dt_factor = 0.3333333333333333 }",
    );
    assert!(close(third.dt, at_rest.dt / 3.0), "{third:?}");
    // rho = 0.05: m / (6 pi eta a) = 2 rho / 9, the rotational time 0.3 of it.
    let light = step(0.05, &format!("kT = {kt}"), "");
    assert_eq!(light.limit, DtLimit::Relaxation, "{light:?}");
    assert!(
        close(light.dt, RELAXATION_FRACTION * 0.3 * 2.0 * 0.05 / 9.0),
        "{light:?}"
    );
    // Sheared below Pe = PECLET_ONSET (3) nothing is relaxed; at Pe = 6 the limits are 2x
    // longer.
    let pe1 = step(0.5, "shear_rate = 0.01, peclet = 1.0", "");
    assert!(close(pe1.dt, at_rest.dt), "{pe1:?}");
    let pe2 = step(0.5, &format!("kT = {kt}, peclet = 2.0"), "");
    assert!(close(pe2.dt, at_rest.dt), "{pe2:?}");
    let pe6 = step(0.5, &format!("kT = {kt}, peclet = 6.0"), "");
    assert!(close(pe6.dt, 2.0 * at_rest.dt), "{pe6:?}");
    for (pe, rho) in [(100.0, 0.5), (1e4, 0.5), (100.0, 0.05), (1e4, 0.05)] {
        let brownian = step(rho, &format!("shear_rate = 0.01, peclet = {pe}"), "");
        let granular = step(rho, "shear_rate = 0.01", "");
        assert!(
            brownian.dt * 1.5 >= granular.dt,
            "Pe {pe}, rho {rho}: {brownian:?} against {granular:?}"
        );
    }
    // At rho = 0.05 and Pe = 30 the relaxation limit, relaxed by 30 / 3, still binds (1.75
    // rotational relaxation times); at Pe = 100 it is gone.
    let light_pe30 = step(0.05, "shear_rate = 0.01, peclet = 30.0", "");
    assert_eq!(light_pe30.limit, DtLimit::Relaxation, "{light_pe30:?}");
    assert!(close(light_pe30.dt, light.dt * 10.0), "{light_pe30:?}");
    let light_pe100 = step(0.05, "shear_rate = 0.01, peclet = 100.0", "");
    let light_granular = step(0.05, "shear_rate = 0.01", "");
    assert!(
        close(light_pe100.dt, light_granular.dt),
        "{light_pe100:?} against {light_granular:?}"
    );
    // The sharp cut: lambda = X11A(0.05) / m_red + 6 pi eta a / m for the 1 : 1 pair.
    let sharp = step(0.5, &format!("kT = {kt}"), "forces = { xi_taper = 0.0 }");
    assert_eq!(sharp.limit, DtLimit::Cutoff, "{sharp:?}");
    let m = 4.0 / 3.0 * std::f64::consts::PI * 0.5;
    let x11a = 6.0 * std::f64::consts::PI * (0.25 / 0.05 + 0.225 * (1.0f64 / 0.05).ln());
    let rate = x11a / (0.5 * m) + 6.0 * std::f64::consts::PI / m;
    assert!(close(sharp.dt, 0.3 / rate), "{sharp:?}");
    // Friction: the tangential spring's own limit times the safety factor, as without kT.
    let frictional = step(
        0.5,
        "shear_rate = 0.01, peclet = 100.0",
        "forces = { mu_p = 1.0, k_n = 1e5 }",
    );
    let granular = step(
        0.5,
        "shear_rate = 0.01",
        "forces = { mu_p = 1.0, k_n = 1e5 }",
    );
    assert_eq!(frictional.limit, DtLimit::Friction, "{frictional:?}");
    assert!(
        close(frictional.dt, granular.dt),
        "{frictional:?} {granular:?}"
    );
    assert!(close(frictional.dt, 0.3 * frictional.friction_critical));
}

/// A step the scene sets warns when it exceeds a Brownian limit (the diffusion limit,
/// 3.125e-3 in the shipped units) by more than 1 %, naming the limit and the factor; a
/// step a hair above it (a limit's step written to a few digits, as the Table 4.1 grids
/// carry one, 2e-4 above today's limit) and one below it do not.
#[test]
fn a_step_beyond_a_brownian_limit_warns_with_its_factor() {
    let kt = 6.0 * std::f64::consts::PI * 0.01;
    let warning = |dt: f64| {
        small_brownian_scene(
            0.5,
            &format!("kT = {kt}"),
            &format!("run = {{ dt = {dt} }}"),
        )
        .warnings
        .iter()
        .find(|w| w.contains("Brownian"))
        .cloned()
    };
    let limit = 3.125e-3;
    for quiet in [0.5 * limit, limit * 1.0002, limit * 1.009] {
        assert_eq!(warning(quiet), None, "dt {quiet}");
    }
    let loud = warning(2.0 * limit).expect("a warning at twice the limit");
    assert!(
        loud.contains("diffusion limit 3.125e-3") && loud.contains("cut the step 2.00x"),
        "{loud}"
    );
}
