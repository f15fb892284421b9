//! `suspflow simulate SCENE.toml --out DIR`: one scene to its steady-state profile.
use clap::builder::{PossibleValuesParser, TypedValueParser};
use sim::input::scene::Scene;
use sim::output::frame_writer::FrameWriter;
use sim::output::result_files::{write_results, RESULTS, WRITTEN};
use sim::output::snapshot_format::SnapshotFormat;
use sim::run::run_folder::{RunFolder, RunStatus};
use sim::run::{RunOptions, SteadyRun};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML, see README).
    scene: PathBuf,
    /// Output directory: scene.toml, profile.csv, stress.csv, summary.json,
    /// snapshot_sums.json and checkpoint.json (the state to continue from; not needed with
    /// --check).
    #[arg(long, required_unless_present = "check")]
    out: Option<PathBuf>,
    /// Continue from DIR/checkpoint.json if it exists: an interrupted run, or a finished one
    /// whose scene now asks for more (run.snapshots with run.blocks in proportion, or a
    /// larger run.max_strain after running out of it).
    #[arg(long)]
    resume: bool,
    /// Start over in a DIR that holds an earlier run (its checkpoint and results are replaced).
    #[arg(long, conflicts_with = "resume")]
    force: bool,
    /// Refuse scenes that only warrant a warning (Stokes number >= 0.1).
    #[arg(long)]
    strict: bool,
    /// Threads (0 = all cores).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::threads::count)]
    threads: usize,
    /// Validate the scene and print its derived quantities (N, bins, Stokes number, time
    /// step and what limits it) without running.
    #[arg(long)]
    check: bool,
    /// Write a particle frame every N snapshots to DIR/frames.xyz, DIR/frames.lammpstrj or
    /// DIR/frames.gsd (appended to on --resume).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = clap::value_parser!(u64).range(1..))]
    snapshot: Option<u64>,
    /// Format of the --snapshot frames: xyz (extended XYZ: ASE, OVITO), lammps (LAMMPS text
    /// dump: LAMMPS read_dump, OVITO, ASE, MDAnalysis) or gsd (binary, float32, about a fifth
    /// of the text's size: OVITO, MDAnalysis, gsd).
    #[arg(
        long,
        value_name = "FORMAT",
        default_value = "xyz",
        requires = "snapshot",
        value_parser = PossibleValuesParser::new(["xyz", "lammps", "gsd"])
            .map(|s| s.parse::<SnapshotFormat>().expect("a listed format parses"))
    )]
    snapshot_format: SnapshotFormat,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = Scene::from_path(&args.scene, args.strict)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    if args.check {
        return print_check(&scene);
    }
    let out = args
        .out
        .as_ref()
        .expect("clap requires --out without --check");
    crate::output_guard::out_dir(out)?;
    let folder = RunFolder::new(out);
    if !args.resume {
        let (file, what) = if folder.status(&RESULTS) == RunStatus::Done {
            (folder.profile_csv(), "the result of an earlier run")
        } else {
            (
                folder.checkpoint(),
                "the checkpoint of an unfinished run; --resume continues it",
            )
        };
        crate::output_guard::refuse_unless_force(&file, args.force, what, "choose another --out")?;
    }
    let mut job = SteadyRun::new(&scene, crate::CODE_VERSION);
    // Checked before the folder is touched: a run that cannot start leaves it as it was.
    sim::run::Job::check(&job)?;
    scene.check_fits_here()?;
    let _lock = folder.lock("`suspflow simulate`")?;
    if args.resume {
        folder.prepare(&scene.file)?;
    } else {
        // Nothing of an earlier run is there, or --force replaces it.
        folder.start_over(&WRITTEN)?;
        folder.record_scene(&scene.file)?;
    }
    if folder.status(&RESULTS) == RunStatus::Done && folder.records_exactly(&scene.file)? {
        println!(
            "{} holds the finished run of this scene: nothing to do (a longer run of it, \
             more run.snapshots or a larger run.max_strain, continues it with --resume)",
            out.display()
        );
        return Ok(());
    }
    crate::interrupt::install()?;
    let bar = crate::progress::bar()?;
    let n = scene.n_particles();
    let packing = |overlapping: usize| {
        bar.set_message(format!(
            "initial packing of {n} particles: {overlapping} pairs still overlap"
        ));
    };
    let opts = RunOptions {
        interrupt: Some(crate::interrupt::flag()),
        code_version: crate::CODE_VERSION,
        packing_progress: Some(&packing),
        ..RunOptions::default()
    };
    // A resumed run continues the frames of the run it resumes.
    let resuming = folder.checkpoint().exists();
    let mut frames = args
        .snapshot
        .map(|every| FrameWriter::open(out, args.snapshot_format, every, resuming))
        .transpose()?;
    let mut lines = crate::progress::lines();
    let ended = crate::threads::with_threads(args.threads, || {
        folder.run(
            &scene,
            &mut job,
            opts,
            &mut |p, sim| {
                crate::progress::show(&bar, &mut lines, p, "");
                if let Some(frames) = frames.as_mut() {
                    frames.after_sample(p.samples, sim);
                }
            },
            |dir, outcome| write_results(dir, &scene, outcome),
        )
    })??;
    bar.finish_and_clear();
    if let Some(frames) = frames {
        frames.finish()?;
    }
    let outcome = crate::exit_status::finished(ended, &folder)?;
    let s = &outcome.summary;
    println!("profile: {}", folder.profile_csv().display());
    println!("summary: {}", folder.summary_json().display());
    println!(
        "N = {}, dt = {:.3e} ({}), steps = {}, steady at strain {:.2}, wall {:.1} s, {:.3e} particle-steps/s",
        s.n_particles, s.dt, s.dt_limit, s.steps, s.strain_to_steady, s.wall_s, s.particle_steps_per_s
    );
    match s.momentum_residual {
        Some(r) => println!(
            "momentum residual {:.3} of the drag scale; mean overlap {:.2e} a, max {:.2e}",
            r, s.mean_overlap, s.max_overlap
        ),
        None => println!(
            "momentum residual: n/a (drag off); mean overlap {:.2e} a",
            s.mean_overlap
        ),
    }
    if let Some(iterations) = s.solver_iterations_mean {
        println!(
            "implicit solve: {iterations:.1} conjugate-gradient iterations per step on average"
        );
    }
    let c = &s.stress_checks;
    println!(
        "stress checks: sigma_yy about its mean chi2 = {:.2} per bin (max |z| {:.2}); \
         d sigma_xy/dy = f_x from the bin stress: residual {} of the drag scale",
        c.sigma_yy_chi2,
        c.sigma_yy_max_z,
        c.balance_residual
            .map_or("n/a (drag off)".into(), |r| format!("{r:.3}"))
    );
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    Ok(())
}

/// Derived quantities of a valid scene.
fn print_check(scene: &Scene) -> anyhow::Result<()> {
    sim::input::scene_limits::check_driven(&scene.file, scene.gdot_max())?;
    scene.check_fits_here()?;
    let t = scene.timestep;
    let r = &scene.file.run;
    let cost = scene.cost();
    println!("scene `{}` is valid", scene.file.name);
    println!(
        "particles: {} (species counts {:?}), phi = {:.4}",
        scene.n_particles(),
        scene.counts,
        scene.phi_actual
    );
    println!("bins: {} of width {}", scene.n_bins, r.bin_width);
    println!(
        "memory: about {} (estimate)",
        sim::input::memory_estimate::describe(scene.memory_bytes)
    );
    println!(
        "gdot_max = {:.4e}, rho = {:.4}, Stokes number = {:.3e}",
        scene.gdot_max(),
        scene.rho,
        scene.stokes
    );
    if let Some(th) = &scene.thermal {
        println!(
            "Brownian: kT = {:.4e}, tau_B = eta a^3/kT = {:.4e}, tau_I = rho a^2/eta = {:.4e}, tau_I/tau_B = {:.3e}, Peclet number = {}",
            th.kt,
            th.tau_b,
            th.tau_i,
            th.inertia_diffusion,
            th.peclet.map_or("none (no flow: run lengths count tau_B)".into(), |pe| format!("{pe:.4e}"))
        );
    }
    if let Some(c) = &scene.composition {
        let pe = |p: Option<f64>| p.map_or("none".into(), |pe| format!("{pe:.4e}"));
        println!(
            "mixture: alpha = {} (placed: {:.4}), a_c = {}, a_g = {}, a_cg = (1 - alpha) a_c + alpha a_g = {:.4}, Pe_c = {}, Pe_cg = {}",
            c.alpha, c.alpha_actual, c.a_c, c.a_g, c.a_cg, pe(c.peclet_c), pe(c.peclet_cg)
        );
    }
    println!(
        "{} integrator: dt = {:.3e} set by {} (critical steps: contact {:.3e}, friction {:.3e}, drag {:.3e}, lubrication {:.3e}; accuracy cap xi_min/gdot_max {:.3e})",
        t.integrator, t.dt, t.limit, t.contact_critical, t.friction_critical, t.drag_critical, t.lubrication_critical, t.accuracy_limit
    );
    if scene.thermal.is_some() && t.integrator == sim::input::integrator::Integrator::Implicit {
        println!(
            "Brownian limits (before run.dt_factor): diffusion {:.3e}, relaxation {:.3e}, cut-off relaxation {:.3e} (docs/physics.md section 11)",
            t.diffusion_limit, t.relaxation_limit, t.cutoff_limit
        );
    }
    println!(
        "{:.0} steps per unit of the run's clock (strain, or tau_B without flow); at most {:.3e} particle-steps to the budget {} plus {:.3e} for {} snapshots",
        cost.steps_per_strain,
        cost.equilibration_particle_steps,
        r.max_strain,
        cost.averaging_particle_steps,
        r.snapshots
    );
    println!(
        "run time: at most about {} here (at {:.1e} particle-steps/s)",
        schema::work_cost::describe(cost.seconds()),
        cost.rate
    );
    Ok(())
}
