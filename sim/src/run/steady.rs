//! The steady run (docs/physics.md section 7), of a profile or of homogeneous shear:
//! equilibration until the binned profiles stop drifting, then averaging over the
//! requested snapshots. A finished run extends to more snapshots (the same number per
//! block: `run.snapshots` and `run.blocks` grown together), and one that ran out of its
//! strain budget to a larger `run.max_strain`.
use crate::error::SimError;
use crate::input::scene::{Scene, SceneFile};
use crate::integrate::simulation::{Simulation, SystemState};
use crate::integrate::stage_timers::Stage;
use crate::output::result_files::SNAPSHOT_SUMS;
use crate::output::run_summary::{RunOutcome, RunSummary};
use crate::run::job::{Job, Sampled};
use crate::run::{Phase, Progress};
use crate::sampling::bin_averages::{BinAverages, BinningContext};
use crate::sampling::block_sums::BlockSums;
use crate::sampling::shear_rheology::ShearRheology;
use crate::sampling::snapshot::{self, Sampler, StepPairSums};
use crate::sampling::species_temperatures::SpeciesTemperatureSums;
use crate::sampling::steady_state::SteadyState;
use crate::sampling::stress_checks::stress_checks;
use crate::sampling::stress_parts::StressParts;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Largest momentum residual (docs/physics.md section 7) of a run whose dynamics are
/// right; above it the run fails. Correct runs stay well below: the 140 shipped runs
/// 0.0003-0.0066 with a profile and 0.036-0.21 in homogeneous shear (where the drag
/// density it is relative to is only noise), the report's stability sweep at most 0.13;
/// the explicit step beyond its stability limit (`dt_factor = 10`) gives 0.62. 0.35 is
/// near their geometric mean, 1.7 times the largest correct run and 1.8 times below the
/// unstable one.
pub const MOMENTUM_RESIDUAL_MAX: f64 = 0.35;

/// The steady run's own progress (the system's state is kept by the [`Simulation`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunState {
    scene: SceneFile,
    phase: Phase,
    steady: SteadyState,
    averaging: BlockSums,
    strain_to_steady: Option<f64>,
    overlap_mean_sum: f64,
    overlap_max: f64,
    /// The pair sums of the steps since the last snapshot (Brownian scenes, implicit step).
    #[serde(default)]
    step_pairs: StepPairSums,
    /// Kinetic temperatures per species over the averaging (Brownian scenes).
    #[serde(default)]
    temperatures: SpeciesTemperatureSums,
}

/// A steady run of a scene, with its sampling buffers.
pub struct SteadyRun<'a> {
    scene: &'a Scene,
    ctx: BinningContext,
    sampler: Sampler,
    sums: Vec<f64>,
    steps_per_sample: u64,
    /// Version of the code, written into the summary.
    code_version: &'a str,
}

impl<'a> SteadyRun<'a> {
    /// The steady run of `scene`, its summary stamped with `code_version`.
    pub fn new(scene: &'a Scene, code_version: &'a str) -> Self {
        let ctx = BinningContext::for_scene(scene);
        let r = &scene.file.run;
        let steps = r.sample_strain / (scene.clock_rate() * scene.timestep.dt);
        SteadyRun {
            scene,
            sampler: Sampler::new(ctx.bins, ctx.a_mean),
            sums: vec![0.0; snapshot::field::FIELDS * scene.n_bins],
            ctx,
            steps_per_sample: (steps.round() as u64).max(1),
            code_version,
        }
    }

    /// The averaging's blocks of a fresh run.
    fn fresh_averaging(&self) -> BlockSums {
        let r = &self.scene.file.run;
        BlockSums::new(self.scene.n_bins, r.blocks, r.snapshots / r.blocks)
    }
}

/// The scene as its checkpoints compare it: without the settings a run may change as it
/// goes (the checkpoint interval) or that an extension changes (the snapshots, their blocks
/// and the strain budget).
fn comparable(file: &SceneFile, extension: bool) -> String {
    let mut s = file.clone();
    s.run.checkpoint_every_s = 0.0;
    if extension {
        s.run.snapshots = 0;
        s.run.blocks = 0;
        s.run.max_strain = 0.0;
    }
    serde_json::to_string(&s).unwrap_or_default()
}

/// Whether a run of `new` continues one of `old`: the same scene, run for as long or
/// longer (more snapshots, a larger strain budget; the checkpoint says whether it can).
pub(crate) fn extends(old: &SceneFile, new: &SceneFile) -> bool {
    comparable(old, true) == comparable(new, true)
}

/// Whether `a` and `b` are the same scene, run for as long.
pub(crate) fn same_scene(a: &SceneFile, b: &SceneFile) -> bool {
    comparable(a, false) == comparable(b, false)
}

impl Job for SteadyRun<'_> {
    type State = RunState;
    type Outcome = RunOutcome;

    fn check(&self) -> Result<(), SimError> {
        crate::input::scene_limits::check_driven(&self.scene.file, self.scene.gdot_max())
    }

    fn fresh(&self) -> RunState {
        let r = &self.scene.file.run;
        let per_window = (r.window_strain / r.sample_strain).round().max(1.0) as usize;
        RunState {
            scene: self.scene.file.clone(),
            phase: Phase::Equilibrating,
            steady: SteadyState::new(self.scene.n_bins, per_window, r.steady_chi2),
            averaging: self.fresh_averaging(),
            strain_to_steady: None,
            overlap_mean_sum: 0.0,
            overlap_max: 0.0,
            step_pairs: StepPairSums::default(),
            temperatures: SpeciesTemperatureSums::default(),
        }
    }

    fn resume(&self, mut st: RunState, _system: &SystemState) -> Result<RunState, String> {
        let file = &self.scene.file;
        if comparable(&st.scene, true) != comparable(file, true) {
            return Err("was written for a different scene".into());
        }
        if !st.averaging.fits(self.scene.n_bins) {
            return Err("holds snapshot sums of an older layout".into());
        }
        let fresh = self.fresh();
        let layout = |b: &BlockSums| (b.n_bins, b.per_block, b.sums.len());
        let (r, old) = (&file.run, &st.scene.run);
        let saved_layout = (self.scene.n_bins, old.snapshots / old.blocks, old.blocks);
        if layout(&st.averaging) != saved_layout
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
                .any(|m| m.len() != self.scene.n_bins)
        {
            return Err(
                "is damaged: snapshot sums of another size than the scene's bins and blocks".into(),
            );
        }
        if st.phase == Phase::Equilibrating || st.averaging.taken == 0 {
            // Nothing averaged yet: the blocks are laid out afresh.
            st.averaging = fresh.averaging;
        } else if (r.snapshots, r.blocks) != (old.snapshots, old.blocks) {
            let per_block = st.averaging.per_block;
            if r.snapshots % r.blocks != 0
                || r.snapshots / r.blocks != per_block
                || r.snapshots < st.averaging.taken
            {
                return Err(format!(
                    "holds {} averaged snapshots in blocks of {per_block}: an extension keeps                      the blocks' length, so run.snapshots must be a multiple of {per_block}                      of at least {} with run.blocks = run.snapshots / {per_block} (e.g.                      snapshots = {}, blocks = {})",
                    st.averaging.taken,
                    st.averaging.taken,
                    2 * old.snapshots,
                    2 * old.snapshots / per_block
                ));
            }
            st.averaging
                .sums
                .resize(r.blocks, vec![0.0; st.averaging.sums[0].len()]);
        }
        st.scene = file.clone();
        Ok(st)
    }

    fn check_folder(&self, dir: &Path) -> Result<(), SimError> {
        refuse_finished_run_of_another_scene(dir, self.scene)
    }

    fn interval(&self, _st: &RunState) -> u64 {
        self.steps_per_sample
    }

    fn at_midpoint(&mut self, st: &mut RunState, sim: &Simulation) {
        // Only the implicit Brownian step calls this (see `StepPairSums`).
        self.sampler.add_step_pairs(sim, &mut st.step_pairs);
    }

    fn sample(&mut self, st: &mut RunState, sim: &mut Simulation) -> Result<Sampled, SimError> {
        let r = &self.scene.file.run;
        let strain = self.scene.clock_rate() * sim.time;
        let t = sim.timers.start();
        self.sums.iter_mut().for_each(|x| *x = 0.0);
        self.sampler
            .accumulate(sim, &mut st.step_pairs, &mut self.sums);
        let block = match st.phase {
            Phase::Equilibrating => &mut st.steady.window,
            Phase::Averaging => &mut st.averaging,
        };
        for (acc, v) in block.current().iter_mut().zip(&self.sums) {
            *acc += v;
        }
        block.commit();
        sim.timers.stop(Stage::Sampling, t);
        match st.phase {
            Phase::Equilibrating => {
                if st.steady.window.full() {
                    if st.steady.close_window(&self.ctx, strain)? {
                        st.phase = Phase::Averaging;
                        st.strain_to_steady = Some(strain);
                    } else if strain >= r.max_strain {
                        return Ok(Sampled::OutOfBudget(SimError::NotSteady {
                            budget: r.max_strain,
                            detail: st.steady.describe_last(),
                        }));
                    }
                }
            }
            Phase::Averaging => {
                st.overlap_mean_sum += sim.contacts.mean_overlap();
                st.overlap_max = st.overlap_max.max(sim.contacts.max_overlap_ratio);
                if let Some(thermal) = &self.scene.thermal {
                    let a = &st.averaging;
                    let block = ((a.taken - 1) / a.per_block).min(a.sums.len() - 1);
                    let shape = (self.scene.file.particles.radii.len(), a.sums.len());
                    st.temperatures.add(sim, thermal.kt, block, shape);
                }
            }
        }
        Ok(if self.finished(st) {
            Sampled::Finished
        } else {
            Sampled::Continue
        })
    }

    fn finished(&self, st: &RunState) -> bool {
        st.phase == Phase::Averaging && st.averaging.full()
    }

    fn progress(&self, st: &RunState, sim: &Simulation) -> Progress {
        let r = &self.scene.file.run;
        Progress {
            phase: st.phase,
            strain: self.scene.clock_rate() * sim.time,
            clock: self.scene.clock(),
            max_strain: r.max_strain,
            snapshots: st.averaging.taken,
            snapshots_target: st.averaging.capacity(),
            step: sim.step,
            samples: sim.step / self.steps_per_sample,
        }
    }

    fn finish(&self, st: RunState, sim: &Simulation, wall_s: f64) -> Result<RunOutcome, SimError> {
        let (scene, ctx) = (self.scene, &self.ctx);
        let mut profile = BinAverages::from_blocks(ctx, &st.averaging)?;
        let stress = StressParts::from_blocks(ctx, &st.averaging);
        let mut warnings = scene.warnings.clone();
        if scene.gdot_max() == 0.0 {
            profile.undefine_shear_observables();
            warnings.push(
                "no flow: J, mu, Theta and Delta_v are undefined at rest (no shear rate or \
                 shear stress to scale them): empty fields"
                    .into(),
            );
        }
        let undefined_bins = profile.undefined_bins();
        if !undefined_bins.is_empty() {
            warnings.push(format!(
                "P <= 0 in bins {undefined_bins:?}: J, mu and Theta undefined there (empty fields)"
            ));
        }
        let target = st.averaging.capacity();
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
            strain_total: scene.clock_rate() * sim.time,
            strain_to_steady: st.strain_to_steady.unwrap_or(f64::NAN),
            steady_drift: st.steady.history.clone(),
            snapshots: profile.snapshots,
            wall_s,
            particle_steps_per_s: sim.particles.len() as f64 * sim.step as f64 / wall_s.max(1e-9),
            momentum_residual: profile.momentum_residual,
            stress_checks: stress_checks(ctx, &st.averaging),
            stress_parts: stress.box_totals.clone(),
            temperatures: st.temperatures.estimates(&scene.file.particles.radii),
            shear: scene
                .shear_rate()
                .map(|g| ShearRheology::from_blocks(ctx, &st.averaging, g)),
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
            code_version: self.code_version.into(),
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
}

/// Fails when `dir` holds the finished run of another scene than `scene` (its snapshot
/// sums), whose results a run of `scene` would replace.
fn refuse_finished_run_of_another_scene(dir: &Path, scene: &Scene) -> Result<(), SimError> {
    /// The scene of a finished run's snapshot sums (the sums themselves are not read).
    #[derive(Deserialize)]
    struct FinishedScene {
        scene: SceneFile,
    }
    let sums = dir.join(SNAPSHOT_SUMS);
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
