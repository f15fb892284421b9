//! `suspflow bench --brownian`: wall seconds per Brownian time of the step loop on thesis
//! Table 4.1's state (monodisperse a = 1, phi 0.45, rho = eta = 0.1, kT = 0.017 so that
//! tau_B = eta a^3 / kT = 5.88, k_n = 1e4, no flow; the LAMMPS peer's `brownian.sh`), at
//! each integrator's automatic step, and the kinetic temperatures over kT measured in the
//! timed window (1 is equipartition).
use super::Args;
use serde::Serialize;
use sim::input::initial_state::initial_particles;
use sim::input::integrator::Integrator;
use sim::input::scene::{Scene, SceneFile};
use sim::integrate::simulation::Simulation;
use sim::integrate::stage_timers::StageTimers;
use std::f64::consts::PI;
use std::time::Instant;

/// Table 4.1's thermal energy, viscosity and particle density.
const KT: f64 = 0.017;
const ETA: f64 = 0.1;
const RHO: f64 = 0.1;
const PHI: f64 = 0.45;

#[derive(Serialize)]
struct Record {
    n: usize,
    threads: usize,
    integrator: Integrator,
    dt: f64,
    /// What set the step.
    dt_limit: String,
    steps: u64,
    loop_s: f64,
    /// Wall seconds per Brownian time tau_B of the timed loop.
    s_per_tau_b: f64,
    /// Translational kinetic temperature `<m v^2> / 3` over kT, mean of the timed steps.
    t_trans_over_kt: f64,
    /// Rotational kinetic temperature `<I omega^2> / 3` over kT.
    t_rot_over_kt: f64,
    /// Mean conjugate-gradient iterations per solve.
    solver_iterations: Option<f64>,
    /// The peer's wall time per tau_B over ours (with `--lammps-s-per-tau-b`).
    lammps_ratio: Option<f64>,
    stages: StageTimers,
}

/// Table 4.1's state with `n` spheres in a cube, for `integrator` at its automatic step.
fn scene(n: usize, integrator: Integrator) -> anyhow::Result<Scene> {
    let l = (n as f64 * 4.0 / 3.0 * PI / PHI).cbrt();
    let mut f = SceneFile::with_defaults(&format!("brownian{n}"), [l, l, l], PHI, "");
    f.seed = 12345;
    f.particles.radii = vec![1.0];
    f.particles.fractions = vec![1.0];
    f.particles.rho = Some(RHO);
    f.fluid.eta = ETA;
    f.fluid.kt = KT;
    f.run.integrator = integrator;
    // Bins play no part in the bench; one width that divides any box into 4.
    f.run.bin_width = l / 4.0;
    Ok(Scene::from_file(f, false)?)
}

fn measure(
    n: usize,
    threads: usize,
    integrator: Integrator,
    args: &Args,
) -> anyhow::Result<Record> {
    let scene = scene(n, integrator)?;
    let tau_b = scene.thermal.map_or(f64::NAN, |t| t.tau_b);
    let particles = initial_particles(&scene)?;
    let (warmup, window) = (args.warmup_tau_b, args.window_tau_b);
    crate::threads::with_threads(threads, || -> anyhow::Result<Record> {
        let mut sim = Simulation::new(&scene, particles)?;
        let dt = sim.timestep.dt;
        let steps_of = |tau: f64| ((tau * tau_b / dt).round() as u64).max(1);
        sim.advance(steps_of(warmup))?;
        let steps = steps_of(window);
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
        let solves = sim.solver_totals().0 - before.0;
        Ok(Record {
            n: sim.particles.len(),
            threads: rayon::current_num_threads(),
            integrator,
            dt,
            dt_limit: sim.timestep.limit.to_string(),
            steps,
            loop_s,
            s_per_tau_b,
            t_trans_over_kt: trans / steps as f64,
            t_rot_over_kt: rot / steps as f64,
            solver_iterations: (solves > 0)
                .then(|| (sim.solver_totals().1 - before.1) as f64 / solves as f64),
            lammps_ratio: args.lammps_s_per_tau_b.map(|peer| peer / s_per_tau_b),
            stages: sim.timers.since(&timers_before),
        })
    })?
}

/// Runs every case of `args` and prints a line (or, with `--json`, a record) for each.
pub fn run(args: &Args) -> anyhow::Result<()> {
    let mut records = Vec::new();
    for &n in &args.n {
        for &integrator in &args.integrator {
            for &threads in &args.threads {
                let r = measure(n, threads, integrator, args)?;
                if !args.json {
                    let ratio = r.lammps_ratio.map_or(String::new(), |x| {
                        format!(" lammps_time_per_tau_b/ours={x:.1}")
                    });
                    let cg = r
                        .solver_iterations
                        .map_or(String::new(), |i| format!(" cg_iterations={i:.1}"));
                    println!(
                        "brownian n={} {} threads={} dt={:.3e} ({}) steps={} loop_s={:.2} s_per_tau_b={:.3} T_trans/kT={:.4} T_rot/kT={:.4}{cg}{ratio}",
                        r.n, r.integrator, r.threads, r.dt, r.dt_limit, r.steps, r.loop_s, r.s_per_tau_b, r.t_trans_over_kt, r.t_rot_over_kt
                    );
                }
                records.push(r);
            }
        }
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&records)?);
    }
    Ok(())
}
