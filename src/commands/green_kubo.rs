//! `suspflow green-kubo SCENE.toml --out DIR`: the Green-Kubo Brownian viscosity of an
//! unsheared Brownian scene (docs/physics.md section 11, paper Fig. 3b): runs it from its
//! initial packing, samples the structural Brownian shear stress, and writes the
//! correlation and its running integral (`green_kubo.csv`) and the viscosity
//! (`green_kubo.json`), in units of the fluid viscosity as a part of `eta_r`.
use crate::exit_status::Stop;
use schema::write_atomic;
use sim::input::scene::Scene;
use sim::run::green_kubo::{GreenKuboJob, GreenKuboRun};
use sim::run::run_folder::{Ended, RunFolder, RunStatus};
use sim::run::RunOptions;
use sim::sampling::green_kubo::GreenKubo;
use sim::SimError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use surrogate::rheology::relaxation_fit::Relaxation;

/// The files of a finished Green-Kubo run.
const RESULTS: [&str; 2] = ["green_kubo.csv", "green_kubo.json"];

#[derive(clap::Args)]
pub struct Args {
    /// Brownian scene without flow (fluid.kT > 0, no shear_rate, profile or peclet).
    scene: PathBuf,
    /// Output directory: scene.toml, green_kubo.csv, green_kubo.json and checkpoint.json
    /// (the state to continue from).
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
    /// Continue from DIR/checkpoint.json: an interrupted run, or a finished one to a longer
    /// --span (the same --warmup and --every).
    #[arg(long)]
    resume: bool,
    /// Start over in a DIR that holds an earlier run (its checkpoint and results are replaced).
    #[arg(long, conflicts_with = "resume")]
    force: bool,
    /// Threads (0 = all cores).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::threads::count)]
    threads: usize,
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
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    crate::output_guard::out_dir(&args.out)?;
    let folder = RunFolder::new(&args.out);
    if !args.resume {
        let (file, what) = if folder.status(&RESULTS) == RunStatus::Done {
            (args.out.join(RESULTS[1]), "an earlier Green-Kubo result")
        } else {
            (
                folder.checkpoint(),
                "the checkpoint of an unfinished Green-Kubo run; --resume continues it",
            )
        };
        crate::output_guard::refuse_unless_force(&file, args.force, what, "choose another --out")?;
    }
    let plan = GreenKuboRun {
        warmup_tau_b: args.warmup,
        span_tau_b: args.span,
        every: args.every,
        max_lag_tau_b: args.max_lag,
        blocks: args.blocks,
    };
    let mut job = GreenKuboJob::new(&scene, plan);
    // Checked before the folder is made: a run that cannot give a result does not start.
    sim::run::Job::check(&job)?;
    sim::input::memory_estimate::check_fits_here(&scene)?;
    let _lock = folder.lock("`suspflow green-kubo`")?;
    if args.resume {
        folder.prepare(&scene.file)?;
    } else {
        // Nothing of an earlier run is there, or --force replaces it.
        folder.start_over(&RESULTS)?;
        folder.record_scene(&scene.file)?;
    }
    crate::interrupt::install()?;
    let bar = crate::progress::bar()?;
    let mut lines = crate::progress::lines();
    let opts = RunOptions {
        interrupt: Some(crate::interrupt::flag()),
        code_version: crate::CODE_VERSION,
        ..RunOptions::default()
    };
    let ended = crate::threads::with_threads(args.threads, || {
        folder.run(
            &scene,
            &mut job,
            opts,
            &mut |p, _| crate::progress::show(&bar, &mut lines, p, ""),
            |dir, gk| write_result(dir, &scene, &args, gk),
        )
    })??;
    bar.finish_and_clear();
    let gk = match ended {
        Ended::Finished(gk) => gk,
        Ended::Interrupted { step } => {
            return Err(Stop::Interrupted(format!(
                "interrupted at step {step}; state saved in {}; continue with --resume",
                folder.checkpoint().display()
            ))
            .into())
        }
        Ended::InterruptedPacking => {
            return Err(Stop::Interrupted(SimError::InterruptedPacking.to_string()).into())
        }
        Ended::Failed(reason) => return Err(Stop::Failed(reason).into()),
    };
    debug_assert_eq!(folder.status(&RESULTS), RunStatus::Done);
    let eta = scene.file.fluid.eta;
    let tau_b = scene.thermal.map_or(f64::NAN, |t| t.tau_b);
    let relaxation = Relaxation::fit(&gk.lags, &gk.running)?;
    let limit_se = gk.viscosity_se * (relaxation.limit / gk.viscosity).abs();
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

/// Writes `green_kubo.csv` (the correlation and its running integral) and
/// `green_kubo.json` (the viscosity) of `gk` into `dir`.
fn write_result(dir: &Path, scene: &Scene, args: &Args, gk: &GreenKubo) -> Result<(), SimError> {
    let eta = scene.file.fluid.eta;
    let tau_b = scene.thermal.map_or(f64::NAN, |t| t.tau_b);
    let relaxation =
        Relaxation::fit(&gk.lags, &gk.running).map_err(|e| SimError::GreenKubo(e.to_string()))?;
    // The limit's error: the integral's, scaled by limit / integral (the blocks are not
    // fitted one by one).
    let limit_se = gk.viscosity_se * (relaxation.limit / gk.viscosity).abs();
    let mut csv = String::from("lag,lag_tau_b,correlation,running_eta_over_eta\n");
    for ((lag, c), r) in gk.lags.iter().zip(&gk.correlation).zip(&gk.running) {
        let _ = writeln!(csv, "{lag},{},{c},{}", lag / tau_b, r / eta);
    }
    write_atomic(&dir.join(RESULTS[0]), csv.as_bytes())?;
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
    let text = serde_json::to_string_pretty(&json).expect("a JSON value serialises");
    Ok(write_atomic(&dir.join(RESULTS[1]), text.as_bytes())?)
}
