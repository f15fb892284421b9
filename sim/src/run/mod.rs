//! The life of a run (docs/physics.md section 7), one for every kind: a [`Job`] says what
//! a kind of run samples and when it is done (the steady run of a profile or of
//! homogeneous shear, [`steady`]; the Green-Kubo run at rest, [`green_kubo`]), and the one
//! [`driver`] owns the rest: initial packing or resume, checkpoints that a resumed run
//! continues from bit for bit, extension of a finished run, interrupts and progress. A
//! [`RunFolder`](run_folder::RunFolder) holds one run on disk (its scene, checkpoint,
//! results or failure, and lock), and a [`batch`] runs many of them, resumably and in
//! parallel.
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

pub mod batch;
pub mod driver;
pub mod green_kubo;
pub mod job;
pub mod progress;
pub mod run_folder;
pub mod steady;
pub mod threads;

pub use job::{Job, Sampled};
pub use progress::{Phase, Progress};
pub use steady::{SteadyRun, MOMENTUM_RESIDUAL_MAX};

use crate::error::SimError;
use crate::input::scene::Scene;
use crate::integrate::simulation::Simulation;
use crate::output::run_summary::RunOutcome;

/// Options that do not change the physics.
#[derive(Default)]
pub struct RunOptions<'a> {
    /// Checkpoint file; none = no checkpoints.
    pub checkpoint: Option<PathBuf>,
    /// Continue from the checkpoint if it exists.
    pub resume: bool,
    /// Set (e.g. by Ctrl-C) to stop within [`driver::INTERRUPT_POLL_STEPS`] steps after
    /// saving a checkpoint.
    pub interrupt: Option<&'static AtomicBool>,
    /// Version of the code, written into the results (the caller's build stamp; empty when
    /// unstamped).
    pub code_version: &'static str,
    /// Told the overlapping pairs left after every iteration of the initial packing
    /// (which takes minutes for a million spheres), and polls the interrupt there too.
    pub packing_progress: Option<&'a (dyn Fn(usize) + Sync)>,
}

/// Runs `scene` to a steady-state profile ([`SteadyRun`]), calling `progress` after every
/// snapshot with the state just sampled.
pub fn run(
    scene: &Scene,
    opts: &RunOptions,
    progress: &mut dyn FnMut(&Progress, &Simulation),
) -> Result<RunOutcome, SimError> {
    driver::drive(
        scene,
        &mut SteadyRun::new(scene, opts.code_version),
        opts,
        progress,
    )
}
