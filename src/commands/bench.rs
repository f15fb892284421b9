//! `suspflow bench`: particle-steps per second and time per unit strain of the force +
//! integration loop on the LAMMPS peer's scene (phi 0.54, u = 0.1 sin(2 pi y/L), L_y = 50,
//! radii 1 : 1.4, k_n = 1e4, lubrication on, from rest). The explicit scheme runs at the
//! peer's dt = 5e-4, the implicit one at its automatic dt, both over the same physical
//! window: 2000 warm-up + 10000 timed steps of 5e-4 by default.
use anyhow::Context;
use sim::input::integrator::Integrator;
use sim::input::run_cost::RunCost;
use sim::studies::benchmark::{
    checked_cost, measure, peer_scene, smallest_valid_n, BenchRecord, BenchSettings,
};

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

/// The peer's scene for `--n n`, or an error about `--n`: the smallest `n` that works when
/// the box is too narrow, else the scene's own reason.
fn bench_scene(
    n: usize,
    settings: &BenchSettings,
    integrator: Integrator,
) -> anyhow::Result<sim::Scene> {
    let (lubrication, skin) = (settings.lubrication, settings.skin);
    let refusal = match peer_scene(n, lubrication, skin, integrator) {
        Ok(scene) => return Ok(scene),
        Err(e) => e,
    };
    match smallest_valid_n(n, lubrication, skin) {
        Some(m) if m > n => anyhow::bail!(
            "--n {n}: too few particles for the bench box (its width must reach twice the \
             interaction range plus skin); use --n {m} or more"
        ),
        None if skin.is_some() && n <= 1 << 24 => anyhow::bail!(
            "no bench box of up to 2^24 particles is valid with --skin {}: the skin is too \
             large ({refusal})",
            skin.unwrap_or_default()
        ),
        _ => Err(refusal).with_context(|| format!("--n {n}: the bench scene is not valid")),
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.brownian {
        return brownian::run(&args);
    }
    let settings = BenchSettings {
        lubrication: !args.no_lubrication,
        skin: args.skin,
        steps: args.steps,
        warmup: args.warmup,
        lammps_pps: args.lammps_pps,
    };
    let mut plan = Vec::new();
    for &n in &args.n {
        for &integrator in &args.integrator {
            let scene = bench_scene(n, &settings, integrator)?;
            plan.push((checked_cost(&scene, &settings)?, scene));
        }
    }
    announce(&plan, args.threads.len())?;
    let mut records = Vec::new();
    for (_, scene) in &plan {
        for &threads in &args.threads {
            let r = crate::threads::with_threads(threads, || measure(scene, &settings))??;
            if !args.json {
                print_record(&r);
            }
            records.push(r);
        }
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&records)?);
    }
    Ok(())
}

/// Before any measurement: refuses a scene that needs more memory than this machine has,
/// shows the estimated wall time of them all (each scene's measurement once per thread
/// count), and the warning of a day-long one (`RunCost::check_levers`).
fn announce(
    plan: &[((RunCost, Option<String>), sim::Scene)],
    thread_counts: usize,
) -> anyhow::Result<()> {
    for (_, scene) in plan {
        scene
            .check_fits_here()
            .with_context(|| format!("--n {}: too many particles here", scene.n_particles()))?;
    }
    for ((_, warning), _) in plan {
        if let Some(w) = warning {
            eprintln!("warning: {w}");
        }
    }
    let seconds: f64 = plan.iter().map(|((c, _), _)| c.seconds()).sum();
    eprintln!(
        "{} measurement(s), estimated at most {} here",
        plan.len() * thread_counts,
        schema::work_cost::describe(seconds * thread_counts as f64)
    );
    Ok(())
}

fn print_record(r: &BenchRecord) {
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
