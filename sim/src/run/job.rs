//! A kind of run: what it samples of the simulation, what it keeps between samples, and
//! when it is done. The [`driver`](crate::run::driver) owns everything else of the run's
//! life: the initial packing, the steps between samples, checkpoints, resume and
//! extension, interrupts and progress.
use crate::error::SimError;
use crate::integrate::simulation::{Simulation, SystemState};
use crate::run::Progress;
use serde::{de::DeserializeOwned, Serialize};
use std::path::Path;

/// What a sample says of the run.
pub enum Sampled {
    /// More samples to take.
    Continue,
    /// The run has what it needs.
    Finished,
    /// The run used up its budget (of strain, say) without finishing: the error to report.
    /// Its state is saved first, so that the same run with a larger budget continues it.
    OutOfBudget(SimError),
}

/// A kind of run (steady profile or homogeneous shear, Green-Kubo at rest).
pub trait Job {
    /// The job's own progress, saved in checkpoints beside the system's state.
    type State: Clone + Serialize + DeserializeOwned;
    /// What a finished run hands over.
    type Outcome;

    /// Refuses, before anything starts, a scene this kind of run cannot run.
    fn check(&self) -> Result<(), SimError>;

    /// The state of a run that has not started.
    fn fresh(&self) -> Self::State;

    /// The saved state of the run this job continues: the same job's, or that of a finished
    /// (or out-of-budget) run which this job extends, made ready for the rest. The message
    /// says why not: a run of another scene, or sums of another size than `system` and
    /// the scene.
    fn resume(&self, saved: Self::State, system: &SystemState) -> Result<Self::State, String>;

    /// Refuses to start afresh (no checkpoint to resume) in the folder `dir` of the finished
    /// run of another scene, whose results this one would replace.
    fn check_folder(&self, _dir: &Path) -> Result<(), SimError> {
        Ok(())
    }

    /// Steps from the last sample (or the start) to the next.
    fn interval(&self, state: &Self::State) -> u64;

    /// Called at the midpoint of every implicit Brownian step, with the system there (see
    /// [`Simulation::step_observed`]).
    fn at_midpoint(&mut self, _state: &mut Self::State, _sim: &Simulation) {}

    /// Takes the sample at the end of an interval.
    fn sample(
        &mut self,
        state: &mut Self::State,
        sim: &mut Simulation,
    ) -> Result<Sampled, SimError>;

    /// Whether the run has what it needs (a resumed finished run, say).
    fn finished(&self, state: &Self::State) -> bool;

    /// Where the run is, after a sample.
    fn progress(&self, state: &Self::State, sim: &Simulation) -> Progress;

    /// The outcome of a finished run, `wall_s` seconds of computing in all.
    fn finish(
        &self,
        state: Self::State,
        sim: &Simulation,
        wall_s: f64,
    ) -> Result<Self::Outcome, SimError>;
}
