//! The folder of one run, the same for every front end (a single run's output folder, one
//! run of a batch, a Green-Kubo run): the scene it was made for (`scene.toml`), its lock
//! while a process writes it (`run.lock`), its checkpoint (`checkpoint.json`: while it runs,
//! and when finished the final state that a longer run of the same scene continues), and
//! then either its results (the [`Job`]'s files) or `failed.txt` with the reason. The files
//! say where the run is, so a re-run continues where the last one stopped.
use crate::error::SimError;
use crate::input::scene::{Scene, SceneFile};
use crate::integrate::simulation::Simulation;
use crate::output::file_lock::FileLock;
use crate::output::run_summary::RunSummary;
use crate::run::driver::drive;
use crate::run::{Job, Progress, RunOptions};
use schema::write_atomic;
use std::path::{Path, PathBuf};

/// The scene a folder was made for.
pub const SCENE_TOML: &str = "scene.toml";
/// The state a run continues from.
pub const CHECKPOINT: &str = "checkpoint.json";
/// The reason a run failed.
pub const FAILED: &str = "failed.txt";
/// The lock of the process that writes the folder.
pub const LOCK: &str = crate::output::file_lock::FOLDER_LOCK;

/// Where a run is.
#[derive(Debug, PartialEq, Eq)]
pub enum RunStatus {
    /// Finished: its results are there.
    Done,
    /// Failed for this reason; not retried unless asked.
    Failed(String),
    /// Not started, or interrupted (then it has a checkpoint).
    Pending,
}

/// What a run folder records of its scene ([`RunFolder::recorded_scene`]).
#[derive(Debug, PartialEq, Eq)]
pub enum Recorded {
    /// The scene asked about.
    Same,
    /// Another scene: the folder is of another grid, or the grid changed.
    Other,
    /// No `scene.toml`.
    None,
}

/// How a run in its folder ended, short of a problem with the folder itself.
#[derive(Debug)]
pub enum Ended<O> {
    /// Finished, its results written.
    Finished(O),
    /// Interrupted at this step, its checkpoint saved: the same run continues it.
    Interrupted { step: u64 },
    /// Interrupted during the initial packing: nothing to save (the packing is drawn again
    /// from the scene's seed).
    InterruptedPacking,
    /// The run failed (recorded in `failed.txt`).
    Failed(String),
}

/// A scene as its run folder records it.
fn scene_text(file: &SceneFile) -> Result<String, SimError> {
    toml::to_string(file).map_err(|e| SimError::Output {
        path: SCENE_TOML.into(),
        message: format!("writing the scene as TOML: {e}"),
    })
}

/// The folder of one run.
#[derive(Clone, Debug)]
pub struct RunFolder {
    pub dir: PathBuf,
}

impl RunFolder {
    /// The folder `dir` (not created).
    pub fn new(dir: impl Into<PathBuf>) -> RunFolder {
        RunFolder { dir: dir.into() }
    }

    /// The folder of the run named `label` (`GridRun::label`) under a batch's `root`.
    pub fn in_batch(root: &Path, label: &str) -> RunFolder {
        RunFolder::new(root.join(label))
    }

    fn io(&self, e: std::io::Error) -> SimError {
        SimError::Output {
            path: self.dir.display().to_string(),
            message: e.to_string(),
        }
    }

    /// Creates the folder and takes its lock for the life of the returned guard; `holder`
    /// names the writer in the refusal when another process holds it.
    pub fn lock(&self, holder: &str) -> Result<FileLock, SimError> {
        FileLock::folder(&self.dir, holder)
    }

    /// Creates the folder for `file`, or checks that an existing one was made for the same
    /// scene and seed (a changed grid must not mix old and new results). A longer run of the
    /// same scene (more snapshots, a larger budget, see
    /// [`SteadyRun`](crate::run::SteadyRun)) is the same scene here: its checkpoint decides.
    pub fn prepare(&self, file: &SceneFile) -> Result<(), SimError> {
        std::fs::create_dir_all(&self.dir).map_err(|e| self.io(e))?;
        match self.recorded_scene(file)? {
            Recorded::Other => Err(SimError::Output {
                path: self.scene_toml().display().to_string(),
                message: "holds a different scene than the one to run here (another grid, or \
                          the grid changed); remove the folder or run elsewhere"
                    .into(),
            }),
            Recorded::Same => Ok(()),
            Recorded::None => self.record_scene(file),
        }
    }

    /// Writes `file` as the folder's scene (a run started over, or extended).
    pub fn record_scene(&self, file: &SceneFile) -> Result<(), SimError> {
        Ok(write_atomic(
            &self.scene_toml(),
            scene_text(file)?.as_bytes(),
        )?)
    }

    /// Whether the folder's `scene.toml` is that of `file` (up to the length of the run),
    /// of another scene, or absent.
    pub fn recorded_scene(&self, file: &SceneFile) -> Result<Recorded, SimError> {
        let Ok(old) = std::fs::read_to_string(self.scene_toml()) else {
            return Ok(Recorded::None);
        };
        if old == scene_text(file)? {
            return Ok(Recorded::Same);
        }
        Ok(match toml::from_str::<SceneFile>(&old) {
            Ok(old) if crate::run::steady::extends(&old, file) => Recorded::Same,
            _ => Recorded::Other,
        })
    }

    /// Whether the folder's scene is exactly `file` (not a longer run of it).
    pub fn records_exactly(&self, file: &SceneFile) -> Result<bool, SimError> {
        Ok(std::fs::read_to_string(self.scene_toml()).ok() == Some(scene_text(file)?))
    }

    /// The scene the folder was made for.
    pub fn scene_toml(&self) -> PathBuf {
        self.dir.join(SCENE_TOML)
    }

    /// The checkpoint file.
    pub fn checkpoint(&self) -> PathBuf {
        self.dir.join(CHECKPOINT)
    }

    /// The status the files record, a run being done when all of `results` are there.
    pub fn status(&self, results: &[&str]) -> RunStatus {
        if results.iter().all(|f| self.dir.join(f).exists()) {
            return RunStatus::Done;
        }
        match std::fs::read_to_string(self.dir.join(FAILED)) {
            Ok(reason) => RunStatus::Failed(reason.trim().to_string()),
            Err(_) => RunStatus::Pending,
        }
    }

    /// Records a failure (its reason).
    pub fn record_failure(&self, reason: &str) -> Result<(), SimError> {
        Ok(write_atomic(
            &self.dir.join(FAILED),
            format!("{reason}\n").as_bytes(),
        )?)
    }

    /// Forgets a recorded failure so the run goes again.
    pub fn clear_failure(&self) {
        std::fs::remove_file(self.dir.join(FAILED)).ok();
    }

    /// Removes what a run of `results` left (checkpoint, results, failure, frames), so the
    /// next one starts over; the scene and the lock stay.
    pub fn start_over(&self, results: &[&str]) -> Result<(), SimError> {
        let mut files = vec![CHECKPOINT, FAILED, "frames.xyz", "frames.lammpstrj"];
        files.extend_from_slice(results);
        for f in files {
            match std::fs::remove_file(self.dir.join(f)) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(self.io(e)),
                _ => {}
            }
        }
        Ok(())
    }

    /// The finished steady run's summary.
    pub fn summary(&self) -> Result<RunSummary, SimError> {
        RunSummary::read(&self.summary_json())
    }

    /// The finished steady run's summary file.
    pub fn summary_json(&self) -> PathBuf {
        self.dir.join(crate::output::result_files::SUMMARY)
    }

    /// The finished steady run's profile table.
    pub fn profile_csv(&self) -> PathBuf {
        self.dir.join(crate::output::result_files::PROFILE)
    }

    /// Runs `job` of `scene` in the folder (which [`RunFolder::prepare`] made): from its
    /// checkpoint when there is one, its results written by `write` when it finishes, and
    /// a failure of the run itself recorded. `opts.checkpoint` and `opts.resume` are the
    /// folder's. Only problems of the folder are errors.
    pub fn run<J: Job>(
        &self,
        scene: &Scene,
        job: &mut J,
        opts: RunOptions,
        progress: &mut dyn FnMut(&Progress, &Simulation),
        write: impl FnOnce(&Path, &J::Outcome) -> Result<(), SimError>,
    ) -> Result<Ended<J::Outcome>, SimError> {
        let opts = RunOptions {
            checkpoint: Some(self.checkpoint()),
            resume: true,
            ..opts
        };
        self.clear_failure();
        let failed = |reason: String| -> Result<Ended<J::Outcome>, SimError> {
            self.record_failure(&reason)?;
            Ok(Ended::Failed(reason))
        };
        match drive(scene, job, &opts, progress) {
            Ok(outcome) => {
                write(&self.dir, &outcome)?;
                self.record_scene(&scene.file)?;
                Ok(Ended::Finished(outcome))
            }
            Err(SimError::Interrupted { step }) => Ok(Ended::Interrupted { step }),
            Err(SimError::InterruptedPacking) => Ok(Ended::InterruptedPacking),
            Err(e @ SimError::CheckpointUnusable { .. }) => {
                failed(format!("{e}; remove it to run this scene from the start"))
            }
            Err(e @ (SimError::Output { .. } | SimError::Checkpoint { .. })) => Err(e),
            Err(e) => failed(e.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_summary_missing_a_field_is_refused_naming_the_field_and_the_file() {
        let dir = std::env::temp_dir().join(format!("sim-summary-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let folder = RunFolder::new(&dir);
        std::fs::write(folder.profile_csv(), "").unwrap();
        std::fs::write(folder.summary_json(), r#"{"name": "tiny"}"#).unwrap();
        let message = folder.summary().unwrap_err().to_string();
        assert!(message.contains("missing field `n_particles`"), "{message}");
        assert!(
            message.contains(&folder.summary_json().display().to_string()),
            "{message}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
