//! `suspflow green-kubo SCENE.toml --out DIR`: the Green-Kubo Brownian viscosity of an
//! unsheared Brownian scene (docs/physics.md section 11, paper Fig. 3b): runs it from its
//! initial packing, samples the structural Brownian shear stress, and writes the
//! correlation and its running integral (`green_kubo.csv`) and the viscosity
//! (`green_kubo.json`), in units of the fluid viscosity as a part of `eta_r`.
use anyhow::Context;
use sim::input::scene::Scene;
use sim::output::atomic_write::write_atomic;
use sim::sampling::green_kubo::{equilibrium_viscosity, GreenKuboRun};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use surrogate::rheology::relaxation_fit::Relaxation;

#[derive(clap::Args)]
pub struct Args {
    /// Brownian scene without flow (fluid.kT > 0, no shear_rate, profile or peclet).
    scene: PathBuf,
    /// Output directory: green_kubo.csv and green_kubo.json.
    #[arg(long)]
    out: PathBuf,
    /// Warm-up before sampling, in Brownian times tau_B.
    #[arg(long, default_value_t = 5.0)]
    warmup: f64,
    /// Sampled span, in tau_B.
    #[arg(long, default_value_t = 100.0)]
    span: f64,
    /// Steps between two samples of the stress.
    #[arg(long, default_value_t = 5)]
    every: u64,
    /// Largest lag of the correlation (its integral's upper limit), in tau_B.
    #[arg(long, default_value_t = 5.0)]
    max_lag: f64,
    /// Consecutive parts of the series for the standard error.
    #[arg(long, default_value_t = 10)]
    blocks: usize,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    force: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    for (name, v) in [
        ("--warmup", args.warmup),
        ("--span", args.span),
        ("--max-lag", args.max_lag),
    ] {
        if !(v.is_finite() && v >= 0.0) || (name != "--warmup" && v == 0.0) {
            anyhow::bail!("{name} must be a positive number of tau_B, got {v}");
        }
    }
    let scene = Scene::from_path(&args.scene, false)?;
    crate::output_guard::out_dir(&args.out)?;
    let written = ["green_kubo.csv", "green_kubo.json"].map(|f| args.out.join(f));
    crate::output_guard::refuse_any_unless_force(
        &written,
        args.force,
        "an earlier Green-Kubo result",
        "choose another --out",
    )?;
    let run = GreenKuboRun {
        warmup_tau_b: args.warmup,
        span_tau_b: args.span,
        every: args.every,
        max_lag_tau_b: args.max_lag,
        blocks: args.blocks,
    };
    let mut last = 0;
    let gk = equilibrium_viscosity(&scene, run, &mut |f| {
        let percent = (100.0 * f) as u32;
        if percent >= last + 10 {
            last = percent;
            eprint!("\rsampling: {percent} %");
            let _ = std::io::stderr().flush();
        }
    })?;
    eprintln!();
    let eta = scene.file.fluid.eta;
    let tau_b = scene.thermal.map_or(f64::NAN, |t| t.tau_b);
    let relaxation = Relaxation::fit(&gk.lags, &gk.running)?;
    // The limit's error: the integral's, scaled by limit / integral (the blocks are not
    // fitted one by one).
    let limit_se = gk.viscosity_se * (relaxation.limit / gk.viscosity).abs();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let mut csv = String::from("lag,lag_tau_b,correlation,running_eta_over_eta\n");
    for ((lag, c), r) in gk.lags.iter().zip(&gk.correlation).zip(&gk.running) {
        let _ = writeln!(csv, "{lag},{},{c},{}", lag / tau_b, r / eta);
    }
    write_atomic(&written[0], csv.as_bytes())?;
    let json = serde_json::json!({
        "scene": scene.file.name,
        "n_particles": scene.n_particles(),
        "phi_actual": scene.phi_actual,
        "kT": scene.file.fluid.kt,
        "tau_b": tau_b,
        "eta_brownian_over_eta": gk.viscosity / eta,
        "eta_brownian_over_eta_se": gk.viscosity_se / eta,
        "extrapolated_eta_brownian_over_eta": relaxation.limit / eta,
        "extrapolated_eta_brownian_over_eta_se": limit_se / eta,
        "relaxation_tau_b": relaxation.time / tau_b,
        "blocks": gk.blocks,
        "warmup_tau_b": args.warmup,
        "span_tau_b": args.span,
        "max_lag_tau_b": args.max_lag,
        "every_steps": args.every,
        "code_version": crate::CODE_VERSION,
    });
    write_atomic(&written[1], serde_json::to_string_pretty(&json)?.as_bytes())?;
    println!(
        "Green-Kubo Brownian viscosity of {} (N = {}, phi = {:.4}): eta_B / eta = {:.3} +- {:.3} \
         (integral to {} tau_B over {} tau_B); extrapolated as eta_inf (1 - exp(-s/tau)): \
         {:.3} +- {:.3}, tau = {:.2} tau_B",
        scene.file.name,
        scene.n_particles(),
        scene.phi_actual,
        gk.viscosity / eta,
        gk.viscosity_se / eta,
        args.max_lag,
        args.span,
        relaxation.limit / eta,
        limit_se / eta,
        relaxation.time / tau_b
    );
    eprintln!("wrote {}", args.out.display());
    Ok(())
}
