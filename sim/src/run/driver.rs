//! The one driver of every kind of run ([`Job`]): the initial packing or the checkpoint it
//! resumes, the steps between samples in short chunks that look at the interrupt flag,
//! checkpoints (every `run.checkpoint_every_s`, on an interrupt, when the budget runs out,
//! and at the end, so that a finished run can be extended), and progress after every
//! sample. A run resumed from its checkpoint continues bit for bit.
use crate::error::SimError;
use crate::input::initial_state::initial_particles_watched;
use crate::input::scene::Scene;
use crate::integrate::simulation::{Simulation, SystemState};
use crate::output::checkpoint;
use crate::run::job::{Job, Sampled};
use crate::run::{Progress, RunOptions};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Steps between two looks at the interrupt flag inside a sample interval: a slowly
/// sheared scene may take millions of steps between snapshots, and Ctrl-C must not wait
/// for them (one look costs an atomic load; a step costs microseconds or more).
pub const INTERRUPT_POLL_STEPS: u64 = 256;

/// A job's state with what the driver keeps of the run (laid out flat in the checkpoint).
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Saved<S> {
    #[serde(flatten)]
    job: S,
    /// Seconds of computing before this invocation.
    wall_s: f64,
    /// Steps already taken towards the next sample (non-zero only in a checkpoint written
    /// inside a sample interval).
    #[serde(default)]
    steps_into_sample: u64,
}

/// Everything a resumed run needs, written at checkpoints.
#[derive(Debug, Serialize, Deserialize)]
struct Checkpoint<S> {
    run: Saved<S>,
    system: SystemState,
}

/// What in the saved `system` has the wrong size or an impossible value for `scene`, if
/// anything: every particle array and the list's reference positions hold one entry per
/// particle, identities are a permutation, species index the radii, positions and
/// velocities are finite.
fn system_mismatch(scene: &Scene, system: &SystemState) -> Option<String> {
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
    None
}

/// The simulation and the job's state continued from the checkpoint at `path`.
fn resume<J: Job>(
    scene: &Scene,
    job: &J,
    path: &Path,
) -> Result<(Simulation, Saved<J::State>), SimError> {
    let Checkpoint { run, system } = checkpoint::load::<Checkpoint<J::State>>(path)?;
    let unusable = |message: String| SimError::CheckpointUnusable {
        path: path.display().to_string(),
        message,
    };
    if let Some(what) = system_mismatch(scene, &system) {
        return Err(unusable(format!("is damaged: {what}")));
    }
    let state = job.resume(run.job, &system).map_err(unusable)?;
    let sim = Simulation::restore(scene, system)?;
    let springs = if scene.file.forces.mu_p > 0.0 {
        sim.list.len()
    } else {
        0
    };
    if sim.springs.len() != springs {
        return Err(unusable(format!(
            "is damaged: {} contact springs for {springs} listed pairs",
            sim.springs.len()
        )));
    }
    Ok((sim, Saved { job: state, ..run }))
}

/// Writes the checkpoints of one invocation of a run.
struct Saver<'a> {
    path: Option<&'a Path>,
    /// Seconds of computing before this invocation.
    wall_before: f64,
    started: Instant,
    /// When the last checkpoint was written (or the invocation began).
    last: Instant,
    every_s: f64,
}

impl Saver<'_> {
    /// Whether `run.checkpoint_every_s` has passed since the last checkpoint.
    fn due(&self) -> bool {
        self.last.elapsed().as_secs_f64() >= self.every_s
    }

    /// Brings the computing time of `saved` up to now and writes it with `sim`'s state.
    fn save<S: Clone + Serialize>(
        &mut self,
        saved: &mut Saved<S>,
        sim: &Simulation,
    ) -> Result<(), SimError> {
        saved.wall_s = self.wall_before + self.started.elapsed().as_secs_f64();
        self.last = Instant::now();
        match self.path {
            Some(path) => checkpoint::save(
                path,
                &Checkpoint {
                    run: saved.clone(),
                    system: sim.state(),
                },
            ),
            None => Ok(()),
        }
    }
}

/// Runs `job` on `scene` to its outcome, calling `progress` after every sample.
pub fn drive<J: Job>(
    scene: &Scene,
    job: &mut J,
    opts: &RunOptions,
    progress: &mut dyn FnMut(&Progress, &Simulation),
) -> Result<J::Outcome, SimError> {
    job.check()?;
    scene.check_fits_here()?;
    let started = Instant::now();
    let interrupt_requested = || opts.interrupt.is_some_and(|f| f.load(Ordering::SeqCst));
    let resume_from = opts
        .checkpoint
        .as_ref()
        .filter(|p| opts.resume && p.exists());
    if let (true, None, Some(dir)) = (
        opts.resume,
        resume_from,
        opts.checkpoint.as_ref().and_then(|p| p.parent()),
    ) {
        job.check_folder(dir)?;
    }
    let (mut sim, mut saved) = match resume_from {
        Some(path) => resume(scene, job, path)?,
        None => {
            let mut watch = |overlapping| {
                if let Some(report) = opts.packing_progress {
                    report(overlapping);
                }
                !interrupt_requested()
            };
            let particles = initial_particles_watched(scene, &mut watch)?;
            let fresh = Saved {
                job: job.fresh(),
                wall_s: 0.0,
                steps_into_sample: 0,
            };
            (Simulation::new(scene, particles)?, fresh)
        }
    };
    let mut saver = Saver {
        path: opts.checkpoint.as_deref(),
        wall_before: saved.wall_s,
        started,
        last: Instant::now(),
        every_s: scene.file.run.checkpoint_every_s,
    };
    while !job.finished(&saved.job) {
        let interval = job.interval(&saved.job);
        while saved.steps_into_sample < interval {
            let chunk = (interval - saved.steps_into_sample).min(INTERRUPT_POLL_STEPS);
            let state = &mut saved.job;
            sim.advance_observed(chunk, &mut |s| job.at_midpoint(state, s))?;
            saved.steps_into_sample += chunk;
            if saved.steps_into_sample < interval {
                if interrupt_requested() {
                    saver.save(&mut saved, &sim)?;
                    return Err(SimError::Interrupted { step: sim.step });
                }
                if saver.due() {
                    saver.save(&mut saved, &sim)?;
                }
            }
        }
        saved.steps_into_sample = 0;
        let sampled = job.sample(&mut saved.job, &mut sim)?;
        progress(&job.progress(&saved.job, &sim), &sim);
        match sampled {
            Sampled::Finished => break,
            Sampled::OutOfBudget(e) => {
                saver.save(&mut saved, &sim)?;
                return Err(e);
            }
            Sampled::Continue => {}
        }
        let interrupted = interrupt_requested();
        if interrupted || saver.due() {
            saver.save(&mut saved, &sim)?;
        }
        if interrupted {
            return Err(SimError::Interrupted { step: sim.step });
        }
    }
    // The final state, from which a longer run of the same scene continues.
    saver.save(&mut saved, &sim)?;
    job.finish(saved.job, &sim, saved.wall_s)
}
