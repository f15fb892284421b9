//! `suspflow green-kubo SCENE.toml --out DIR`: the Green-Kubo Brownian viscosity of an
//! unsheared Brownian scene (docs/physics.md section 11, paper Fig. 3b): runs it from its
//! initial packing, samples the structural Brownian shear stress, and writes the
//! correlation and its running integral (`green_kubo.csv`) and the viscosity
//! (`green_kubo.json`), in units of the fluid viscosity as a part of `eta_r`.
use rheometry::green_kubo::{run_in_folder, WRITTEN};
use sim::input::scene::Scene;
use sim::run::green_kubo::{GreenKuboJob, GreenKuboRun};
use sim::run::run_folder::{RunFolder, RunStatus};
use sim::run::RunOptions;
use std::path::PathBuf;

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
    let scene = Scene::from_path(&args.scene, false)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    crate::output_guard::out_dir(&args.out)?;
    let folder = RunFolder::new(&args.out);
    if !args.resume {
        let (file, what) = if folder.status(&WRITTEN) == RunStatus::Done {
            (
                args.out.join(rheometry::green_kubo::JSON),
                "an earlier Green-Kubo result",
            )
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
    // Checked before the folder is made: a run that cannot give a result does not start.
    let job = GreenKuboJob::new(&scene, plan);
    sim::run::Job::check(&job)?;
    scene.check_fits_here()?;
    let cost = job.cost();
    eprintln!(
        "estimated at most {} here ({:.2e} particle-steps)",
        schema::work_cost::describe(cost.seconds()),
        cost.equilibration_particle_steps + cost.averaging_particle_steps
    );
    if let Ok(Some(long)) = cost.check_levers("") {
        eprintln!("warning: {long}");
    }
    let _lock = folder.lock("`suspflow green-kubo`")?;
    if args.resume {
        folder.prepare(&scene.file)?;
    } else {
        // Nothing of an earlier run is there, or --force replaces it.
        folder.start_over(&WRITTEN)?;
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
        run_in_folder(&folder, &scene, plan, opts, &mut |p, _| {
            crate::progress::show(&bar, &mut lines, p, "")
        })
    })??;
    bar.finish_and_clear();
    let g = crate::exit_status::finished(ended, &folder)?;
    debug_assert_eq!(folder.status(&WRITTEN), RunStatus::Done);
    println!(
        "Green-Kubo Brownian viscosity of {} (N = {}, phi = {:.4}): eta_B / eta = {:.3} +- {:.3} \
         (integral to {} tau_B over {} tau_B); extrapolated as eta_inf (1 - exp(-s/tau)): \
         {:.3} +- {:.3}, tau = {:.2} tau_B",
        g.scene,
        g.n_particles,
        g.phi_actual,
        g.eta_brownian_over_eta,
        g.eta_brownian_over_eta_se,
        g.max_lag_tau_b,
        g.span_tau_b,
        g.extrapolated_eta_brownian_over_eta,
        g.extrapolated_eta_brownian_over_eta_se,
        g.relaxation_tau_b
    );
    for w in &g.warnings {
        eprintln!("warning (kept in {}): {w}", rheometry::green_kubo::JSON);
    }
    eprintln!("wrote {}", args.out.display());
    Ok(())
}
