//! The speed benchmark on the LAMMPS peer's scene (`../shared/peers/lammps/run.sh`): phi
//! 0.54, u = 0.1 sin(2 pi y/L), L_y = 50, radii 1 : 1.4, k_n = 1e4, lubrication on, from
//! rest. The explicit scheme runs at the peer's dt = 5e-4, the implicit one at its automatic
//! dt, both over the same physical window; the measurement runs on the caller's thread pool.
use crate::error::SimError;
use crate::input::initial_state::initial_particles;
use crate::input::integrator::Integrator;
use crate::input::run_cost::RunCost;
use crate::input::scene::{Scene, SceneFile};
use crate::integrate::pass_times::PassTimes;
use crate::integrate::simulation::Simulation;
use crate::integrate::stage_timers::StageTimers;
use serde::Serialize;
use std::f64::consts::PI;
use std::time::Instant;

/// The explicit scheme's step here: the peer's stable LAMMPS step.
pub const PEER_DT: f64 = 5e-4;

/// What to measure: windows in steps of [`PEER_DT`] (the implicit scheme covers the same
/// simulated time in its own, larger steps).
#[derive(Clone, Copy, Debug)]
pub struct BenchSettings {
    pub lubrication: bool,
    /// Verlet-list skin (units a); the scene default when `None`.
    pub skin: Option<f64>,
    /// Timed window (at least 1 step of [`PEER_DT`]).
    pub steps: u64,
    /// Untimed warm-up window.
    pub warmup: u64,
    /// The peer's measured particle-steps per second at [`PEER_DT`], for the ratio.
    pub lammps_pps: Option<f64>,
}

/// One measurement.
#[derive(Debug, Serialize)]
pub struct BenchRecord {
    pub n: usize,
    pub threads: usize,
    pub lubrication: bool,
    pub integrator: Integrator,
    pub particle_steps_per_s: f64,
    /// Wall seconds per unit strain (strain = largest shear rate x time).
    pub s_per_strain: f64,
    pub steps: u64,
    pub dt: f64,
    pub loop_s: f64,
    pub contacts_per_particle: f64,
    /// Mean conjugate-gradient iterations per implicit step.
    pub solver_iterations: Option<f64>,
    /// LAMMPS' time per unit strain at dt = 5e-4 over ours (with the peer's speed given).
    pub lammps_ratio: Option<f64>,
    /// Wall seconds of the timed loop spent in each stage of the step.
    pub stages: StageTimers,
    /// The implicit solve's parallel passes in the timed loop: the ranges' work added
    /// up, the busiest range's, and the passes' wall time.
    pub solve_passes: Option<PassTimes>,
}

/// The peer's scene at `n` particles: L_x = L_z = sqrt(V_particles / (phi L_y)); the
/// explicit scheme at [`PEER_DT`], the implicit one at its automatic step.
pub fn peer_scene(
    n: usize,
    lubrication: bool,
    skin: Option<f64>,
    integrator: Integrator,
) -> Result<Scene, SimError> {
    let (phi, l_y) = (0.54, 50.0);
    let v_particles = (n / 2) as f64 * 4.0 / 3.0 * PI * (1.0 + 1.4f64.powi(3));
    let l = (v_particles / (phi * l_y)).sqrt();
    let mut f =
        SceneFile::with_defaults(&format!("bench{n}"), [l, l_y, l], phi, "0.1*sin(2*pi*y/L)");
    f.seed = 12345;
    f.forces.lubrication = lubrication;
    // The bench steps its own windows ([`cost`]): the scene's run to a steady state is
    // the shortest valid, so that its cost (checked by the scene) does not stand for the
    // bench's.
    f.run.max_strain = f.run.sample_strain;
    f.run.snapshots = f.run.blocks;
    f.run.integrator = integrator;
    if integrator == Integrator::Explicit {
        f.run.dt = Some(PEER_DT);
    }
    if let Some(skin) = skin {
        f.run.skin = skin;
    }
    Scene::from_file(f, false)
}

/// The smallest particle number from `n` up whose peer scene is valid (its box width must
/// reach twice the interaction range plus skin), by bisection on the scene's own
/// validation; `None` when no box up to 2^24 particles is (the skin is too large).
pub fn smallest_valid_n(n: usize, lubrication: bool, skin: Option<f64>) -> Option<usize> {
    let valid = |m: usize| peer_scene(m, lubrication, skin, Integrator::Explicit).is_ok();
    let mut hi = n.max(2);
    while !valid(hi) {
        if hi > 1 << 24 {
            return None;
        }
        hi *= 2;
    }
    let mut lo = n;
    while lo + 1 < hi {
        let mid = lo + (hi - lo) / 2;
        if valid(mid) {
            hi = mid
        } else {
            lo = mid
        }
    }
    Some(if valid(n) { n } else { hi })
}

/// `[warm-up, timed window]` of `settings` in `scene`'s own steps (at least one timed).
fn own_steps(scene: &Scene, settings: &BenchSettings) -> [f64; 2] {
    let in_own_steps = |peer_steps: u64| (peer_steps as f64 * PEER_DT / scene.timestep.dt).round();
    [
        in_own_steps(settings.warmup),
        in_own_steps(settings.steps).max(1.0),
    ]
}

/// What `settings` cost on `scene`: the warm-up's and the window's particle-steps at the
/// rate of a run here.
pub fn cost(scene: &Scene, settings: &BenchSettings) -> RunCost {
    RunCost::of_steps(
        scene.steps_per_strain(),
        scene.n_particles(),
        own_steps(scene, settings),
        false,
    )
}

/// [`cost`], or the refusal of a measurement that cannot finish (the rule of
/// [`schema::work_cost`]), with the warning of a day-long one.
pub fn checked_cost(
    scene: &Scene,
    settings: &BenchSettings,
) -> Result<(RunCost, Option<String>), SimError> {
    checked(
        cost(scene, settings),
        "shorten the timed window or the warm-up, or lower the particle number",
    )
}

/// The check behind both benches' `checked_cost`: `cost` with its warning, or its refusal;
/// `levers` says what to shorten.
pub(crate) fn checked(cost: RunCost, levers: &str) -> Result<(RunCost, Option<String>), SimError> {
    let warning = cost.check_levers(levers).map_err(SimError::Benchmark)?;
    Ok((cost, warning))
}

/// Times `settings.steps` steps of `scene` (a [`peer_scene`]) after the warm-up, on the
/// current thread pool; refuses windows that cannot finish ([`checked_cost`]) before it starts.
pub fn measure(scene: &Scene, settings: &BenchSettings) -> Result<BenchRecord, SimError> {
    checked_cost(scene, settings)?;
    let [warmup, steps] = own_steps(scene, settings).map(|s| s as u64);
    let mut sim = Simulation::new(scene, initial_particles(scene)?)?;
    sim.time_solve_passes();
    let dt = sim.timestep.dt;
    sim.advance(warmup)?;
    let before = sim.solver_totals();
    let timers_before = sim.timers;
    let passes_before = sim.solve_pass_times();
    let t = Instant::now();
    sim.advance(steps)?;
    let loop_s = t.elapsed().as_secs_f64();
    let n = sim.particles.len() as f64;
    let gdot_max = scene.gdot_max();
    let s_per_strain = loop_s / (steps as f64 * dt * gdot_max);
    Ok(BenchRecord {
        n: sim.particles.len(),
        threads: rayon::current_num_threads(),
        lubrication: scene.file.forces.lubrication,
        integrator: scene.file.run.integrator,
        particle_steps_per_s: n * steps as f64 / loop_s,
        s_per_strain,
        steps,
        dt,
        loop_s,
        contacts_per_particle: 2.0 * sim.contacts.contacts as f64 / n,
        solver_iterations: sim.iterations_per_solve_since(before),
        lammps_ratio: settings
            .lammps_pps
            .map(|pps| n / (pps * PEER_DT * gdot_max) / s_per_strain),
        stages: sim.timers.since(&timers_before),
        solve_passes: sim
            .solve_pass_times()
            .zip(passes_before)
            .filter(|_| sim.solver_totals().0 > before.0)
            .map(|(now, before)| now.since(&before)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smallest_valid_box_is_found_and_too_small_ones_are_not_valid() {
        let n = smallest_valid_n(10, true, None).expect("some box is valid");
        assert!(n > 10, "{n}");
        assert!(peer_scene(n, true, None, Integrator::Explicit).is_ok());
        assert!(peer_scene(n - 1, true, None, Integrator::Explicit).is_err());
        assert_eq!(smallest_valid_n(n + 5, true, None), Some(n + 5));
    }

    #[test]
    fn a_large_bench_is_limited_by_its_windows_not_by_the_scenes_run() {
        // 2e7 particles: the scene's default run would take years, the bench's window not.
        let scene = peer_scene(20_000_000, true, None, Integrator::Explicit).unwrap();
        let settings = |steps| BenchSettings {
            lubrication: true,
            skin: None,
            steps,
            warmup: 0,
            lammps_pps: None,
        };
        let (cost, warning) = checked_cost(&scene, &settings(1)).unwrap();
        assert!(warning.is_none() && cost.seconds() < 100.0, "{cost:?}");
        let e = checked_cost(&scene, &settings(u64::MAX)).unwrap_err();
        assert!(e.to_string().contains("cannot finish"), "{e}");
    }
}
