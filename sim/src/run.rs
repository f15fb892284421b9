//! A whole run (docs/physics.md section 7): initial packing, equilibration until the binned
//! profiles stop drifting, averaging over the requested snapshots, with checkpoints
//! that a resumed run continues from bit for bit.
use crate::error::SimError;
use crate::input::initial_state::initial_particles_watched;
use crate::input::scene::{Scene, SceneFile};
use crate::integrate::simulation::{Simulation, SystemState};
use crate::integrate::stage_timers::Stage;
use crate::output::checkpoint;
use crate::output::result_files::SNAPSHOT_SUMS;
use crate::output::run_summary::{RunOutcome, RunSummary};
use crate::sampling::bin_averages::{BinAverages, BinningContext};
use crate::sampling::block_sums::BlockSums;
use crate::sampling::shear_rheology::ShearRheology;
use crate::sampling::snapshot::{self, Sampler, StepPairSums};
use crate::sampling::species_temperatures::SpeciesTemperatureSums;
use crate::sampling::steady_state::SteadyState;
use crate::sampling::stress_checks::stress_checks;
use crate::sampling::stress_parts::StressParts;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Steps between two looks at the interrupt flag inside a sample interval: a slowly
/// sheared scene may take millions of steps between snapshots, and Ctrl-C must not wait
/// for them (one look costs an atomic load; a step costs microseconds or more).
const INTERRUPT_POLL_STEPS: u64 = 256;

/// Largest momentum residual (docs/physics.md section 7) of a run whose dynamics are
/// right; above it the run fails. Correct runs stay well below: the 140 shipped runs
/// 0.0003-0.0066 with a profile and 0.036-0.21 in homogeneous shear (where the drag
/// density it is relative to is only noise), the report's stability sweep at most 0.13;
/// the explicit step beyond its stability limit (`dt_factor = 10`) gives 0.62. 0.35 is
/// near their geometric mean, 1.7 times the largest correct run and 1.8 times below the
/// unstable one.
pub const MOMENTUM_RESIDUAL_MAX: f64 = 0.35;

/// Where a run is.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Phase {
    Equilibrating,
    Averaging,
}

/// Progress report, once per snapshot.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    pub phase: Phase,
    pub strain: f64,
    /// Strain budget of the equilibration.
    pub max_strain: f64,
    pub snapshots: usize,
    pub snapshots_target: usize,
    pub step: u64,
    /// Snapshots sampled since the run began (equilibration and averaging, counting those
    /// before a resume): 1 at the first call.
    pub samples: u64,
}

/// Options that do not change the physics.
#[derive(Default)]
pub struct RunOptions<'a> {
    /// Checkpoint file; none = no checkpoints.
    pub checkpoint: Option<PathBuf>,
    /// Continue from the checkpoint if it exists.
    pub resume: bool,
    /// Set (e.g. by Ctrl-C) to stop within [`INTERRUPT_POLL_STEPS`] steps after saving a
    /// checkpoint.
    pub interrupt: Option<&'static AtomicBool>,
    /// Version of the code, written into the summary (the caller's build stamp; empty when
    /// unstamped).
    pub code_version: &'static str,
    /// Told the overlapping pairs left after every iteration of the initial packing
    /// (which takes minutes for a million spheres), and polls the interrupt there too.
    pub packing_progress: Option<&'a (dyn Fn(usize) + Sync)>,
}

/// The run's own progress (the system's state is kept by the [`Simulation`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
struct RunState {
    scene: SceneFile,
    phase: Phase,
    steady: SteadyState,
    averaging: BlockSums,
    strain_to_steady: Option<f64>,
    overlap_mean_sum: f64,
    overlap_max: f64,
    wall_s: f64,
    /// Steps already taken towards the next snapshot (non-zero only in a checkpoint
    /// written on an interrupt inside a sample interval).
    #[serde(default)]
    steps_into_sample: u64,
    /// The pair sums of those steps (Brownian scenes, implicit step).
    #[serde(default)]
    step_pairs: StepPairSums,
    /// Kinetic temperatures per species over the averaging (Brownian scenes).
    #[serde(default)]
    temperatures: SpeciesTemperatureSums,
}

/// Everything a resumed run needs, written at checkpoints.
#[derive(Debug, Serialize, Deserialize)]
struct Checkpoint {
    run: RunState,
    system: SystemState,
}

fn fresh_state(scene: &Scene) -> RunState {
    let r = &scene.file.run;
    let per_window = (r.window_strain / r.sample_strain).round().max(1.0) as usize;
    let blocks = r.blocks;
    RunState {
        scene: scene.file.clone(),
        phase: Phase::Equilibrating,
        steady: SteadyState::new(scene.n_bins, per_window, r.steady_chi2),
        averaging: BlockSums::new(scene.n_bins, blocks, r.snapshots / blocks),
        strain_to_steady: None,
        overlap_mean_sum: 0.0,
        overlap_max: 0.0,
        wall_s: 0.0,
        steps_into_sample: 0,
        step_pairs: StepPairSums::default(),
        temperatures: SpeciesTemperatureSums::default(),
    }
}

/// What in a checkpoint of `scene` (same scene file) has the wrong size or an impossible
/// value, if anything: every particle array and the list's reference positions hold one
/// entry per particle, identities are a permutation, species index the radii, positions
/// and velocities are finite, and the snapshot sums are laid out as a fresh run's.
fn shape_mismatch(scene: &Scene, st: &RunState, system: &SystemState) -> Option<String> {
    let n = scene.n_particles();
    let p = &system.particles;
    let lengths = [
        ("positions", p.pos.len()),
        ("velocities", p.vel.len()),
        ("angular velocities", p.omega.len()),
        ("forces", p.force.len()),
        ("torques", p.torque.len()),
        ("radii", p.radius.len()),
        ("species", p.species.len()),
        ("masses", p.mass.len()),
        ("identities", p.id.len()),
        (
            "neighbour-list reference positions",
            system.list_reference.len(),
        ),
    ];
    if let Some((what, len)) = lengths.iter().find(|(_, len)| *len != n) {
        return Some(format!("{len} {what} for the scene's {n} particles"));
    }
    let mut ids = p.id.clone();
    ids.sort_unstable();
    if ids.iter().enumerate().any(|(k, &id)| id as usize != k) {
        return Some("particle identities are not 0..N each once".into());
    }
    let species = scene.file.particles.radii.len();
    if p.species.iter().any(|&s| s as usize >= species) {
        return Some(format!(
            "a species index beyond the scene's {species} radii"
        ));
    }
    let vectors = [
        &p.pos,
        &p.vel,
        &p.omega,
        &p.force,
        &p.torque,
        &system.list_reference,
    ];
    if vectors
        .iter()
        .any(|v| v.iter().any(|x| !x.iter().all(|c| c.is_finite())))
    {
        return Some("a non-finite position, velocity or force".into());
    }
    let fresh = fresh_state(scene);
    let layout = |b: &BlockSums| (b.n_bins, b.per_block, b.sums.len());
    if layout(&st.averaging) != layout(&fresh.averaging)
        || layout(&st.steady.window) != layout(&fresh.steady.window)
        || st
            .steady
            .window
            .sums
            .iter()
            .any(|s| s.len() != fresh.steady.window.sums[0].len())
        || st
            .steady
            .window_means
            .iter()
            .flatten()
            .any(|m| m.len() != scene.n_bins)
    {
        return Some("snapshot sums of another size than the scene's bins and blocks".into());
    }
    None
}

/// Fails when the folder of `checkpoint` (which does not exist) holds the finished run
/// of another scene, whose results a run of `scene` would replace.
fn refuse_finished_run_of_another_scene(
    checkpoint: &std::path::Path,
    scene: &Scene,
) -> Result<(), SimError> {
    /// The scene of a finished run's snapshot sums (the sums themselves are not read).
    #[derive(Deserialize)]
    struct FinishedScene {
        scene: SceneFile,
    }
    let Some(sums) = checkpoint.parent().map(|d| d.join(SNAPSHOT_SUMS)) else {
        return Ok(());
    };
    let Ok(text) = std::fs::read_to_string(&sums) else {
        return Ok(());
    };
    let other = match serde_json::from_str::<FinishedScene>(&text) {
        Ok(finished) if same_scene(&finished.scene, &scene.file) => return Ok(()),
        Ok(finished) if finished.scene.name == scene.file.name => {
            format!("of scene `{}` with other settings", finished.scene.name)
        }
        Ok(finished) => format!("of scene `{}`", finished.scene.name),
        Err(_) => "of an unreadable scene".into(),
    };
    Err(SimError::Output {
        path: sums.display().to_string(),
        message: format!(
            "is the finished run {other}: there is nothing of this scene to resume, and \
             running would replace that run's results"
        ),
    })
}

fn same_scene(a: &SceneFile, b: &SceneFile) -> bool {
    let strip = |s: &SceneFile| {
        let mut s = s.clone();
        s.run.checkpoint_every_s = 0.0;
        serde_json::to_string(&s).unwrap_or_default()
    };
    strip(a) == strip(b)
}

fn save_checkpoint(
    path: &std::path::Path,
    st: &RunState,
    sim: &Simulation,
) -> Result<(), SimError> {
    checkpoint::save(
        path,
        &Checkpoint {
            run: st.clone(),
            system: sim.state(),
        },
    )
}

/// Runs `scene` to a steady-state profile, calling `progress` after every snapshot
/// with the state just sampled.
pub fn run(
    scene: &Scene,
    opts: &RunOptions,
    progress: &mut dyn FnMut(&Progress, &Simulation),
) -> Result<RunOutcome, SimError> {
    crate::input::scene_limits::check_driven(&scene.file)?;
    crate::input::memory_estimate::check_fits_here(scene)?;
    let started = Instant::now();
    let interrupt_requested = || opts.interrupt.is_some_and(|f| f.load(Ordering::SeqCst));
    let resume_from = opts
        .checkpoint
        .as_ref()
        .filter(|p| opts.resume && p.exists());
    if let (true, None, Some(path)) = (opts.resume, resume_from, &opts.checkpoint) {
        refuse_finished_run_of_another_scene(path, scene)?;
    }
    let (mut sim, mut st) = match resume_from {
        Some(path) => {
            let Checkpoint { run: st, system } = checkpoint::load(path)?;
            if !same_scene(&st.scene, &scene.file) {
                return Err(SimError::CheckpointUnusable {
                    path: path.display().to_string(),
                    message: "was written for a different scene".into(),
                });
            }
            if !st.averaging.fits(scene.n_bins) {
                return Err(SimError::CheckpointUnusable {
                    path: path.display().to_string(),
                    message: "holds snapshot sums of an older layout".into(),
                });
            }
            let damaged = |what: String| SimError::CheckpointUnusable {
                path: path.display().to_string(),
                message: format!("is damaged: {what}"),
            };
            if let Some(what) = shape_mismatch(scene, &st, &system) {
                return Err(damaged(what));
            }
            let sim = Simulation::restore(scene, system)?;
            let springs = if scene.file.forces.mu_p > 0.0 {
                sim.list.len()
            } else {
                0
            };
            if sim.springs.len() != springs {
                return Err(damaged(format!(
                    "{} contact springs for {springs} listed pairs",
                    sim.springs.len()
                )));
            }
            (sim, st)
        }
        None => {
            let mut watch = |overlapping| {
                if let Some(report) = opts.packing_progress {
                    report(overlapping);
                }
                !interrupt_requested()
            };
            let particles = initial_particles_watched(scene, &mut watch)?;
            (Simulation::new(scene, particles)?, fresh_state(scene))
        }
    };
    let ctx = BinningContext::for_scene(scene);
    let r = &scene.file.run;
    let gdot = scene.clock_rate();
    let steps_per_sample = ((r.sample_strain / (gdot * sim.timestep.dt)).round() as u64).max(1);
    let target = st.averaging.capacity();
    let mut last_checkpoint = Instant::now();
    let wall_before = st.wall_s;
    let mut sums_scratch = vec![0.0; snapshot::field::FIELDS * scene.n_bins];
    let mut sampler = Sampler::new(ctx.bins, ctx.a_mean);
    loop {
        while st.steps_into_sample < steps_per_sample {
            let chunk = (steps_per_sample - st.steps_into_sample).min(INTERRUPT_POLL_STEPS);
            // Only the implicit Brownian step calls this (see `StepPairSums`).
            let pairs = &mut st.step_pairs;
            sim.advance_observed(chunk, &mut |s| sampler.add_step_pairs(s, pairs))?;
            st.steps_into_sample += chunk;
            if st.steps_into_sample < steps_per_sample && interrupt_requested() {
                if let Some(path) = &opts.checkpoint {
                    st.wall_s = wall_before + started.elapsed().as_secs_f64();
                    save_checkpoint(path, &st, &sim)?;
                }
                return Err(SimError::Interrupted { step: sim.step });
            }
        }
        st.steps_into_sample = 0;
        let strain = gdot * sim.time;
        let t = sim.timers.start();
        sums_scratch.iter_mut().for_each(|x| *x = 0.0);
        sampler.accumulate(&sim, &mut st.step_pairs, &mut sums_scratch);
        let block = match st.phase {
            Phase::Equilibrating => &mut st.steady.window,
            Phase::Averaging => &mut st.averaging,
        };
        for (acc, v) in block.current().iter_mut().zip(&sums_scratch) {
            *acc += v;
        }
        block.commit();
        sim.timers.stop(Stage::Sampling, t);
        match st.phase {
            Phase::Equilibrating => {
                if st.steady.window.full() {
                    if st.steady.close_window(&ctx, strain)? {
                        st.phase = Phase::Averaging;
                        st.strain_to_steady = Some(strain);
                    } else if strain >= r.max_strain {
                        return Err(SimError::NotSteady {
                            budget: r.max_strain,
                            detail: st.steady.describe_last(),
                        });
                    }
                }
            }
            Phase::Averaging => {
                st.overlap_mean_sum += sim.contacts.mean_overlap();
                st.overlap_max = st.overlap_max.max(sim.contacts.max_overlap_ratio);
                if let Some(thermal) = &scene.thermal {
                    let a = &st.averaging;
                    let block = ((a.taken - 1) / a.per_block).min(a.sums.len() - 1);
                    let shape = (scene.file.particles.radii.len(), a.sums.len());
                    st.temperatures.add(&sim, thermal.kt, block, shape);
                }
            }
        }
        progress(
            &Progress {
                phase: st.phase,
                strain,
                max_strain: r.max_strain,
                snapshots: st.averaging.taken,
                snapshots_target: target,
                step: sim.step,
                samples: sim.step / steps_per_sample,
            },
            &sim,
        );
        if st.phase == Phase::Averaging && st.averaging.full() {
            break;
        }
        let interrupted = interrupt_requested();
        if let Some(path) = &opts.checkpoint {
            if interrupted || last_checkpoint.elapsed().as_secs_f64() >= r.checkpoint_every_s {
                st.wall_s = wall_before + started.elapsed().as_secs_f64();
                save_checkpoint(path, &st, &sim)?;
                last_checkpoint = Instant::now();
            }
        }
        if interrupted {
            return Err(SimError::Interrupted { step: sim.step });
        }
    }
    let profile = BinAverages::from_blocks(&ctx, &st.averaging)?;
    let stress = StressParts::from_blocks(&ctx, &st.averaging);
    let wall_s = wall_before + started.elapsed().as_secs_f64();
    let mut warnings = scene.warnings.clone();
    let undefined_bins = profile.undefined_bins();
    if !undefined_bins.is_empty() {
        warnings.push(format!(
            "P <= 0 in bins {undefined_bins:?}: J, mu and Theta undefined there (empty fields)"
        ));
    }
    let summary = RunSummary {
        name: scene.file.name.clone(),
        n_particles: sim.particles.len(),
        phi: scene.file.particles.phi,
        phi_actual: scene.phi_actual,
        stokes: scene.stokes,
        thermal: scene.thermal,
        composition: scene.composition,
        dt: sim.timestep.dt,
        dt_limit: sim.timestep.limit.to_string(),
        timestep: sim.timestep,
        steps: sim.step,
        strain_total: gdot * sim.time,
        strain_to_steady: st.strain_to_steady.unwrap_or(f64::NAN),
        steady_drift: st.steady.history.clone(),
        snapshots: profile.snapshots,
        wall_s,
        particle_steps_per_s: sim.particles.len() as f64 * sim.step as f64 / wall_s.max(1e-9),
        momentum_residual: profile.momentum_residual,
        stress_checks: stress_checks(&ctx, &st.averaging),
        stress_parts: stress.box_totals.clone(),
        temperatures: st.temperatures.estimates(&scene.file.particles.radii),
        shear: scene
            .shear_rate()
            .map(|g| ShearRheology::from_blocks(&ctx, &st.averaging, g)),
        mean_overlap: st.overlap_mean_sum / target as f64,
        max_overlap: st.overlap_max,
        list_builds: sim.list_builds,
        solver_iterations_mean: (sim.solver_totals().0 > 0)
            .then(|| sim.solver_totals().1 as f64 / sim.solver_totals().0 as f64),
        timers: sim.timers,
        threads: rayon::current_num_threads(),
        undefined_bins,
        warnings,
        stress_convention: "sigma = sum of stresslets -F_ij (x) r_ij / V_b, positive in compression (minus the Cauchy stress); P = tr(sigma)/3".into(),
        observables: scene.file.observables,
        code_version: opts.code_version.into(),
    };
    // Not in a Brownian scene: its random loads are not in the binned stress (their
    // direct virial averages to zero, docs/physics.md section 11), so the binned balance
    // measures the thermal noise, not the dynamics.
    if let Some(residual) = summary
        .momentum_residual
        .filter(|r| scene.thermal.is_none() && !(..=MOMENTUM_RESIDUAL_MAX).contains(r))
    {
        return Err(SimError::MomentumImbalance {
            residual,
            limit: MOMENTUM_RESIDUAL_MAX,
            dt: summary.dt,
            dt_limit: summary.dt_limit,
        });
    }
    Ok(RunOutcome {
        profile,
        summary,
        stress,
        sums: st.averaging,
    })
}
