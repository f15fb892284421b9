//! `suspflow bench`: particle-steps per second of the force + integration loop on the
//! LAMMPS peer's scene (phi 0.54, u = 0.1 sin(2 pi y/L), L_y = 50, radii 1 : 1.4,
//! k_n = 1e4, lubrication on, dt = 5e-4, 2000 warm-up + 10000 timed steps from rest).
use serde::Serialize;
use sim::input::scene::{Scene, SceneFile};
use sim::integrate::simulation::Simulation;
use sim::run::initial_particles;
use std::f64::consts::PI;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Particle numbers (comma separated).
    #[arg(long, value_delimiter = ',', default_values_t = [1000usize, 4000, 16000])]
    n: Vec<usize>,
    /// Thread counts (comma separated; 0 = all cores).
    #[arg(long, value_delimiter = ',', default_values_t = [1usize, 0])]
    threads: Vec<usize>,
    /// Timed steps (at least 1).
    #[arg(long, default_value_t = 10000, value_parser = clap::value_parser!(u64).range(1..))]
    steps: u64,
    /// Untimed warm-up steps.
    #[arg(long, default_value_t = 2000)]
    warmup: u64,
    /// Verlet-list skin (units a, finite and >= 0); the scene default when absent.
    #[arg(long, value_parser = parse_skin)]
    skin: Option<f64>,
    /// Switch lubrication off (contact + drag only).
    #[arg(long)]
    no_lubrication: bool,
    /// Print a JSON array of records instead of lines.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Record {
    n: usize,
    threads: usize,
    lubrication: bool,
    particle_steps_per_s: f64,
    steps: u64,
    dt: f64,
    loop_s: f64,
    contacts_per_particle: f64,
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
    scene(n, lubrication, skin).or_else(|_| {
        let valid = |m: usize| scene(m, lubrication, skin).is_ok();
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

/// The peer's scene at N particles: L_x = L_z = sqrt(V_particles / (phi L_y)).
fn scene(n: usize, lubrication: bool, skin: Option<f64>) -> anyhow::Result<Scene> {
    let (phi, l_y) = (0.54, 50.0);
    let v_particles = (n / 2) as f64 * 4.0 / 3.0 * PI * (1.0 + 1.4f64.powi(3));
    let l = (v_particles / (phi * l_y)).sqrt();
    let mut f =
        SceneFile::with_defaults(&format!("bench{n}"), [l, l_y, l], phi, "0.1*sin(2*pi*y/L)");
    f.seed = 12345;
    f.forces.lubrication = lubrication;
    f.run.dt = Some(5e-4);
    if let Some(skin) = skin {
        f.run.skin = skin;
    }
    Ok(Scene::from_file(f, false)?)
}

fn measure(n: usize, threads: usize, args: &Args) -> anyhow::Result<Record> {
    let lubrication = !args.no_lubrication;
    let scene = bench_scene(n, lubrication, args.skin)?;
    let particles = initial_particles(&scene)?;
    crate::threads::with_threads(threads, || -> anyhow::Result<Record> {
        let mut sim = Simulation::new(&scene, particles)?;
        sim.advance(args.warmup)?;
        let t = Instant::now();
        sim.advance(args.steps)?;
        let loop_s = t.elapsed().as_secs_f64();
        Ok(Record {
            n: sim.particles.len(),
            threads: rayon::current_num_threads(),
            lubrication,
            particle_steps_per_s: sim.particles.len() as f64 * args.steps as f64 / loop_s,
            steps: args.steps,
            dt: sim.timestep.dt,
            loop_s,
            contacts_per_particle: 2.0 * sim.contacts.contacts as f64 / sim.particles.len() as f64,
        })
    })?
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut records = Vec::new();
    for &n in &args.n {
        for &threads in &args.threads {
            let r = measure(n, threads, &args)?;
            if !args.json {
                println!(
                    "n={:<6} threads={} lubrication={} particle_steps_per_s={:.3e} loop_s={:.2} steps={} dt={:.1e} contacts/particle={:.2}",
                    r.n, r.threads, r.lubrication, r.particle_steps_per_s, r.loop_s, r.steps, r.dt, r.contacts_per_particle
                );
            }
            records.push(r);
        }
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&records)?);
    }
    Ok(())
}
