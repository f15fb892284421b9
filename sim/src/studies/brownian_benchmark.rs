//! The Brownian speed benchmark at thesis Table 4.1's state, the LAMMPS peer's
//! `brownian.sh`: monodisperse a = 1, phi 0.45, rho = eta = 0.1, kT = 0.017, k_n = 1e4, no
//! flow, timed per Brownian time tau_B, with the kinetic temperatures of the timed window
//! (both 1 in kT when the noise and the dissipation agree). Runs on the caller's pool.
use crate::error::SimError;
use crate::input::initial_state::initial_particles;
use crate::input::integrator::Integrator;
use crate::input::run_cost::RunCost;
use crate::input::scene::{Scene, SceneFile};
use crate::integrate::simulation::Simulation;
use crate::integrate::stage_timers::StageTimers;
use serde::Serialize;
use std::f64::consts::PI;
use std::time::Instant;

/// Thermal energy of Table 4.1 (`eta a^3 / time^2` units).
const KT: f64 = 0.017;
/// Fluid viscosity of Table 4.1.
const ETA: f64 = 0.1;
/// Particle density of Table 4.1.
const RHO: f64 = 0.1;
/// Volume fraction of Table 4.1.
const PHI: f64 = 0.45;

/// What to measure, in Brownian times tau_B.
#[derive(Clone, Copy, Debug)]
pub struct BrownianBenchSettings {
    /// Untimed warm-up.
    pub warmup_tau_b: f64,
    /// Timed window.
    pub window_tau_b: f64,
    /// The peer's measured wall seconds per tau_B, for the ratio.
    pub lammps_s_per_tau_b: Option<f64>,
}

/// One measurement.
#[derive(Debug, Serialize)]
pub struct BrownianBenchRecord {
    pub n: usize,
    pub threads: usize,
    pub integrator: Integrator,
    pub dt: f64,
    pub dt_limit: String,
    pub steps: u64,
    pub loop_s: f64,
    /// Wall seconds per Brownian time.
    pub s_per_tau_b: f64,
    /// Translational and rotational kinetic temperatures over kT, mean of the timed steps.
    pub t_trans_over_kt: f64,
    pub t_rot_over_kt: f64,
    /// Mean conjugate-gradient iterations per implicit step.
    pub solver_iterations: Option<f64>,
    /// The peer's wall time per tau_B over ours.
    pub lammps_ratio: Option<f64>,
    /// Wall seconds of the timed loop spent in each stage of the step.
    pub stages: StageTimers,
}

/// Table 4.1's state at about `n` particles in a cubic box.
pub fn brownian_scene(n: usize, integrator: Integrator) -> Result<Scene, SimError> {
    let l = (n as f64 * 4.0 / 3.0 * PI / PHI).cbrt();
    let mut f = SceneFile::with_defaults(&format!("brownian{n}"), [l, l, l], PHI, "");
    f.seed = 12345;
    f.particles.radii = vec![1.0];
    f.particles.fractions = vec![1.0];
    f.particles.rho = Some(RHO);
    f.fluid.eta = ETA;
    f.fluid.kt = KT;
    // The bench steps its own windows ([`cost`]): the scene's run to a steady state is
    // the shortest valid, so that its cost (checked by the scene) does not stand for the
    // bench's.
    f.run.max_strain = f.run.sample_strain;
    f.run.snapshots = f.run.blocks;
    f.run.integrator = integrator;
    f.run.bin_width = l / 4.0;
    Scene::from_file(f, false)
}

/// What `settings` cost on `scene`: the warm-up's and the window's particle-steps at the
/// rate of a Brownian scene here.
pub fn cost(scene: &Scene, settings: &BrownianBenchSettings) -> RunCost {
    // Without flow the scene's clock counts Brownian times.
    let per_tau_b = scene.steps_per_strain();
    RunCost::of_steps(
        per_tau_b,
        scene.n_particles(),
        [settings.warmup_tau_b, settings.window_tau_b].map(|tau| (tau * per_tau_b).max(1.0)),
        true,
    )
}

/// [`cost`], or the refusal of a measurement that cannot finish (the rule of
/// [`schema::work_cost`]), with the warning of a day-long one.
pub fn checked_cost(
    scene: &Scene,
    settings: &BrownianBenchSettings,
) -> Result<(RunCost, Option<String>), SimError> {
    crate::studies::benchmark::checked(
        cost(scene, settings),
        "shorten the warm-up or the window (in tau_B), or lower the particle number",
    )
}

/// Times the window of `settings` on `scene` (a [`brownian_scene`]) after the warm-up, on
/// the current thread pool; refuses windows that cannot finish ([`checked_cost`]) before it starts.
pub fn measure_brownian(
    scene: &Scene,
    settings: &BrownianBenchSettings,
) -> Result<BrownianBenchRecord, SimError> {
    checked_cost(scene, settings)?;
    let tau_b = scene.thermal.map_or(f64::NAN, |t| t.tau_b);
    let mut sim = Simulation::new(scene, initial_particles(scene)?)?;
    let dt = sim.timestep.dt;
    let steps_of = |tau: f64| ((tau * scene.steps_per_strain()).round() as u64).max(1);
    sim.advance(steps_of(settings.warmup_tau_b))?;
    let steps = steps_of(settings.window_tau_b);
    let before = sim.solver_totals();
    let timers_before = sim.timers;
    let (mut trans, mut rot) = (0.0, 0.0);
    let t = Instant::now();
    for _ in 0..steps {
        sim.step()?;
        let (tt, tr) = sim.particles.kinetic_temperatures(KT);
        trans += tt;
        rot += tr;
    }
    let loop_s = t.elapsed().as_secs_f64();
    let s_per_tau_b = loop_s / (steps as f64 * dt / tau_b);
    Ok(BrownianBenchRecord {
        n: sim.particles.len(),
        threads: rayon::current_num_threads(),
        integrator: scene.file.run.integrator,
        dt,
        dt_limit: sim.timestep.limit.to_string(),
        steps,
        loop_s,
        s_per_tau_b,
        t_trans_over_kt: trans / steps as f64,
        t_rot_over_kt: rot / steps as f64,
        solver_iterations: sim.iterations_per_solve_since(before),
        lammps_ratio: settings.lammps_s_per_tau_b.map(|peer| peer / s_per_tau_b),
        stages: sim.timers.since(&timers_before),
    })
}
