//! `suspflow bench --brownian`: wall seconds per Brownian time of the step loop on thesis
//! Table 4.1's state (monodisperse a = 1, phi 0.45, rho = eta = 0.1, kT = 0.017 so that
//! tau_B = eta a^3 / kT = 5.88, k_n = 1e4, no flow; the LAMMPS peer's `brownian.sh`), at
//! each integrator's automatic step, and the kinetic temperatures over kT measured in the
//! timed window (1 is equipartition).
use super::Args;
use anyhow::Context;
use sim::studies::brownian_benchmark::{
    brownian_scene, checked_cost, measure_brownian, BrownianBenchSettings,
};

pub fn run(args: &Args) -> anyhow::Result<()> {
    let settings = BrownianBenchSettings {
        warmup_tau_b: args.warmup_tau_b,
        window_tau_b: args.window_tau_b,
        lammps_s_per_tau_b: args.lammps_s_per_tau_b,
    };
    let mut plan = Vec::new();
    for &n in &args.n {
        for &integrator in &args.integrator {
            let scene = brownian_scene(n, integrator)
                .with_context(|| format!("--n {n}: the Brownian bench box of {n} particles"))?;
            plan.push((checked_cost(&scene, &settings)?, scene));
        }
    }
    super::announce(&plan, args.threads.len())?;
    let mut records = Vec::new();
    for (_, scene) in &plan {
        for &threads in &args.threads {
            let r = crate::threads::with_threads(threads, || measure_brownian(scene, &settings))??;
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
    if args.json {
        println!("{}", serde_json::to_string_pretty(&records)?);
    }
    Ok(())
}
