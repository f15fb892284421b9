//! `suspflow bench`: particle-steps per second and time per unit strain of the force +
//! integration loop on the LAMMPS peer's scene (phi 0.54, u = 0.1 sin(2 pi y/L), L_y = 50,
//! radii 1 : 1.4, k_n = 1e4, lubrication on, from rest). The explicit scheme runs at the
//! peer's dt = 5e-4, the implicit one at its automatic dt, both over the same physical
//! window: 2000 warm-up + 10000 timed steps of 5e-4 by default.
use serde::Serialize;
use sim::input::initial_state::initial_particles;
use sim::input::integrator::Integrator;
use sim::input::scene::{Scene, SceneFile};
use sim::integrate::pass_times::PassTimes;
use sim::integrate::simulation::Simulation;
use sim::integrate::stage_timers::StageTimers;
use std::f64::consts::PI;
use std::time::Instant;

mod brownian;

#[derive(clap::Args)]
pub struct Args {
    /// Particle numbers (comma separated).
    #[arg(long, value_delimiter = ',', default_values_t = [1000usize, 4000, 16000], allow_negative_numbers = true)]
    n: Vec<usize>,
    /// Thread counts (comma separated; 0 = all cores).
    #[arg(long, value_delimiter = ',', default_values_t = [1usize, 0], allow_negative_numbers = true, value_parser = crate::threads::count)]
    threads: Vec<usize>,
    /// Integrators (comma separated): implicit, explicit.
    #[arg(long, value_delimiter = ',', default_values_t = [Integrator::Implicit, Integrator::Explicit], value_parser = parse_integrator)]
    integrator: Vec<Integrator>,
    /// Timed window, in steps of the peer's dt = 5e-4 (at least 1); the implicit scheme
    /// covers the same simulated time in its own, larger steps.
    #[arg(long, default_value_t = 10000, allow_negative_numbers = true, value_parser = clap::value_parser!(u64).range(1..))]
    steps: u64,
    /// Untimed warm-up window, in steps of 5e-4.
    #[arg(long, default_value_t = 2000, allow_negative_numbers = true)]
    warmup: u64,
    /// The peer's measured particle-steps per second at dt = 5e-4 (its `run.sh` prints
    /// it); when given, each record also gives LAMMPS' time per unit strain over ours.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_positive)]
    lammps_pps: Option<f64>,
    /// Verlet-list skin (units a, finite and >= 0); the scene default when absent.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_skin)]
    skin: Option<f64>,
    /// Switch lubrication off (contact + drag only).
    #[arg(long)]
    no_lubrication: bool,
    /// Print a JSON array of records instead of lines.
    #[arg(long)]
    json: bool,
    /// The Brownian bench instead: thesis Table 4.1's state (monodisperse a = 1, phi
    /// 0.45, rho = eta = 0.1, kT = 0.017, k_n = 1e4, no flow; the peer's
    /// `brownian.sh`), timed per Brownian time tau_B, with the kinetic temperatures of the
    /// timed window.
    #[arg(long)]
    brownian: bool,
    /// With --brownian: the untimed warm-up, in Brownian times tau_B.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true, value_parser = parse_positive)]
    warmup_tau_b: f64,
    /// With --brownian: the timed window, in Brownian times tau_B.
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true, value_parser = parse_positive)]
    window_tau_b: f64,
    /// With --brownian: the peer's measured wall seconds per tau_B (its `brownian.sh`
    /// prints `wall_per_tau_B`); each record then gives the peer's time over ours.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_positive)]
    lammps_s_per_tau_b: Option<f64>,
}

/// The explicit scheme's step here: the peer's stable LAMMPS step.
const PEER_DT: f64 = 5e-4;

#[derive(Serialize)]
struct Record {
    n: usize,
    threads: usize,
    lubrication: bool,
    integrator: Integrator,
    particle_steps_per_s: f64,
    /// Wall seconds per unit strain (strain = largest shear rate x time).
    s_per_strain: f64,
    steps: u64,
    dt: f64,
    loop_s: f64,
    contacts_per_particle: f64,
    /// Mean conjugate-gradient iterations per implicit step.
    solver_iterations: Option<f64>,
    /// LAMMPS' time per unit strain at dt = 5e-4 over ours (with `--lammps-pps`).
    lammps_ratio: Option<f64>,
    /// Wall seconds of the timed loop spent in each stage of the step.
    stages: StageTimers,
    /// The implicit solve's parallel passes in the timed loop: the ranges' work added
    /// up, the busiest range's, and the passes' wall time.
    solve_passes: Option<PassTimes>,
}

fn parse_integrator(text: &str) -> Result<Integrator, String> {
    match text {
        "implicit" => Ok(Integrator::Implicit),
        "explicit" => Ok(Integrator::Explicit),
        _ => Err(format!(
            "`{text}` is not an integrator: implicit or explicit"
        )),
    }
}

fn parse_positive(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{text}` is not a finite number > 0")),
    }
}

fn parse_skin(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(skin) if skin.is_finite() && skin >= 0.0 => Ok(skin),
        _ => Err(format!("`{text}` is not a finite number >= 0 (units a)")),
    }
}

/// [`scene`] for `--n n`; when `n` is too small for a valid box, an error about `--n` with
/// the smallest `n` that works (found by bisection on the scene's own validation).
fn bench_scene(n: usize, lubrication: bool, skin: Option<f64>) -> anyhow::Result<Scene> {
    scene(n, lubrication, skin, Integrator::Explicit).or_else(|_| {
        let valid = |m: usize| scene(m, lubrication, skin, Integrator::Explicit).is_ok();
        let mut hi = n.max(2);
        while !valid(hi) {
            if hi > 1 << 24 {
                anyhow::bail!("no bench box is valid with --skin {skin:?}: the skin is too large");
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
        anyhow::bail!(
            "--n {n}: too few particles for the bench box (its width must reach twice the \
             interaction range plus skin); use --n {hi} or more"
        )
    })
}

/// The peer's scene at N particles: L_x = L_z = sqrt(V_particles / (phi L_y)); the
/// explicit scheme at dt = 5e-4, the implicit one at its automatic step.
fn scene(
    n: usize,
    lubrication: bool,
    skin: Option<f64>,
    integrator: Integrator,
) -> anyhow::Result<Scene> {
    let (phi, l_y) = (0.54, 50.0);
    let v_particles = (n / 2) as f64 * 4.0 / 3.0 * PI * (1.0 + 1.4f64.powi(3));
    let l = (v_particles / (phi * l_y)).sqrt();
    let mut f =
        SceneFile::with_defaults(&format!("bench{n}"), [l, l_y, l], phi, "0.1*sin(2*pi*y/L)");
    f.seed = 12345;
    f.forces.lubrication = lubrication;
    f.run.integrator = integrator;
    if integrator == Integrator::Explicit {
        f.run.dt = Some(PEER_DT);
    }
    if let Some(skin) = skin {
        f.run.skin = skin;
    }
    Ok(Scene::from_file(f, false)?)
}

fn measure(
    n: usize,
    threads: usize,
    integrator: Integrator,
    args: &Args,
) -> anyhow::Result<Record> {
    let lubrication = !args.no_lubrication;
    bench_scene(n, lubrication, args.skin)?;
    let scene = scene(n, lubrication, args.skin, integrator)?;
    let particles = initial_particles(&scene)?;
    crate::threads::with_threads(threads, || -> anyhow::Result<Record> {
        let mut sim = Simulation::new(&scene, particles)?;
        sim.time_solve_passes();
        let dt = sim.timestep.dt;
        let in_own_steps = |peer_steps: u64| (peer_steps as f64 * PEER_DT / dt).round() as u64;
        let steps = in_own_steps(args.steps).max(1);
        sim.advance(in_own_steps(args.warmup))?;
        let before = sim.solver_totals();
        let timers_before = sim.timers;
        let passes_before = sim.solve_pass_times();
        let t = Instant::now();
        sim.advance(steps)?;
        let loop_s = t.elapsed().as_secs_f64();
        let n = sim.particles.len() as f64;
        let gdot_max = scene.gdot_max();
        let s_per_strain = loop_s / (steps as f64 * dt * gdot_max);
        let solves = sim.solver_totals().0 - before.0;
        Ok(Record {
            n: sim.particles.len(),
            threads: rayon::current_num_threads(),
            lubrication,
            integrator,
            particle_steps_per_s: n * steps as f64 / loop_s,
            s_per_strain,
            steps,
            dt,
            loop_s,
            contacts_per_particle: 2.0 * sim.contacts.contacts as f64 / n,
            solver_iterations: (solves > 0)
                .then(|| (sim.solver_totals().1 - before.1) as f64 / solves as f64),
            lammps_ratio: args
                .lammps_pps
                .map(|pps| n / (pps * PEER_DT * gdot_max) / s_per_strain),
            stages: sim.timers.since(&timers_before),
            solve_passes: sim
                .solve_pass_times()
                .zip(passes_before)
                .filter(|_| solves > 0)
                .map(|(now, before)| now.since(&before)),
        })
    })?
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.brownian {
        return brownian::run(&args);
    }
    let mut records = Vec::new();
    for &n in &args.n {
        for &integrator in &args.integrator {
            for &threads in &args.threads {
                let r = measure(n, threads, integrator, &args)?;
                if !args.json {
                    print_record(&r);
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

fn print_record(r: &Record) {
    let iterations = r
        .solver_iterations
        .map_or(String::new(), |i| format!(" cg_iterations={i:.1}"));
    let ratio = r.lammps_ratio.map_or(String::new(), |x| {
        format!(" lammps_time_per_strain/ours={x:.1}")
    });
    let passes = r.solve_passes.map_or(String::new(), |p| {
        format!(
            " solve_passes(work {:.2}, busiest range {:.2}, wall {:.2})",
            p.work_s, p.longest_s, p.wall_s
        )
    });
    let st = &r.stages;
    println!(
        "n={:<6} {} threads={} lubrication={} particle_steps_per_s={:.3e} s_per_strain={:.3} loop_s={:.2} (neighbours {:.2}, forces {:.2}, integration {:.2}) steps={} dt={:.2e} contacts/particle={:.2}{iterations}{passes}{ratio}",
        r.n, r.integrator, r.threads, r.lubrication, r.particle_steps_per_s, r.s_per_strain, r.loop_s, st.neighbours_s, st.forces_s, st.integration_s, r.steps, r.dt, r.contacts_per_particle
    );
}
