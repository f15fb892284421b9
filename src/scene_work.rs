//! The work directory of `suspflow generate`: one folder per run (one replica of a scene,
//! named `<scene id>_seed<seed>`) holding the scene it was made for (`scene.toml`, with the
//! replica's seed), its checkpoint while it runs, and then either its results
//! (`profile.csv`, `summary.json`, as `simulate` writes them) or `failed.txt` with the reason.
//! The files say where each run is, so a re-run continues where the last one stopped.
use anyhow::{bail, Context};
use sim::input::scene::SceneFile;
use sim::output::run_summary::RunSummary;
use std::path::{Path, PathBuf};

/// Column names of [`summary_cells`], in order: what the scene table of `generate` shows of
/// a finished scene's summary.
pub const SUMMARY_COLUMNS: [&str; 10] = [
    "dt",
    "dt_limit",
    "steps",
    "strain_to_steady",
    "strain_total",
    "momentum_residual",
    "mean_overlap",
    "max_overlap",
    "wall_s",
    "code_version",
];

/// The [`SUMMARY_COLUMNS`] of `summary` as table cells, numbers written as in the JSON file
/// (not finite, an empty cell; so is an absent residual, a run without drag).
pub fn summary_cells(summary: &RunSummary) -> [String; 10] {
    let number = |v: f64| serde_json::Number::from_f64(v).map_or(String::new(), |n| n.to_string());
    [
        number(summary.dt),
        summary.dt_limit.clone(),
        summary.steps.to_string(),
        number(summary.strain_to_steady),
        number(summary.strain_total),
        summary.momentum_residual.map_or(String::new(), number),
        number(summary.mean_overlap),
        number(summary.max_overlap),
        number(summary.wall_s),
        summary.code_version.clone(),
    ]
}

/// Reads the `summary.json` at `path` that `simulate` wrote.
pub fn read_summary(path: &Path) -> anyhow::Result<RunSummary> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_slice(&bytes).with_context(|| format!("reading {}", path.display()))
}

/// Where a run is.
pub enum SceneStatus {
    /// Finished: its summary.json.
    Done(Box<RunSummary>),
    /// Failed for this reason; not retried unless asked.
    Failed(String),
    /// Not started, or interrupted (then it has a checkpoint).
    Pending,
}

/// What a run folder records of its scene ([`SceneWork::recorded_scene`]).
#[derive(Debug, PartialEq, Eq)]
pub enum Recorded {
    /// The scene asked about.
    Same,
    /// Another scene: the folder is of another grid, or the grid changed.
    Other,
    /// No `scene.toml`.
    None,
}

/// A scene as its run folder records it.
fn scene_text(file: &SceneFile) -> anyhow::Result<String> {
    toml::to_string(file).context("writing the scene as TOML")
}

/// The folder of one run.
pub struct SceneWork {
    pub dir: PathBuf,
}

impl SceneWork {
    /// The folder of the run named `label` (`GridRun::label`) under `root` (not created).
    pub fn new(root: &Path, label: &str) -> SceneWork {
        SceneWork {
            dir: root.join(label),
        }
    }

    /// Creates the folder for `file`, or checks that an existing one was made for the same
    /// scene and seed (a changed grid must not mix old and new results).
    pub fn prepare(&self, file: &SceneFile) -> anyhow::Result<()> {
        std::fs::create_dir_all(&self.dir)
            .with_context(|| format!("creating {}", self.dir.display()))?;
        let path = self.scene_toml();
        match self.recorded_scene(file)? {
            Recorded::Other => bail!(
                "{} holds a different scene than the grid now gives (the grid changed?); \
                 remove the work directory or write to another --out",
                path.display()
            ),
            Recorded::Same => Ok(()),
            Recorded::None => Ok(sim::output::atomic_write::write_atomic(
                &path,
                scene_text(file)?.as_bytes(),
            )?),
        }
    }

    /// Whether the folder's `scene.toml` is that of `file`, of another scene, or absent.
    pub fn recorded_scene(&self, file: &SceneFile) -> anyhow::Result<Recorded> {
        Ok(match std::fs::read_to_string(self.scene_toml()) {
            Ok(old) if old == scene_text(file)? => Recorded::Same,
            Ok(_) => Recorded::Other,
            Err(_) => Recorded::None,
        })
    }

    /// The scene the folder was made for.
    pub fn scene_toml(&self) -> PathBuf {
        self.dir.join("scene.toml")
    }

    /// The status the files record.
    pub fn status(&self) -> anyhow::Result<SceneStatus> {
        let summary = self.summary_json();
        if self.profile_csv().exists() && summary.exists() {
            return Ok(SceneStatus::Done(Box::new(read_summary(&summary)?)));
        }
        match std::fs::read_to_string(self.dir.join("failed.txt")) {
            Ok(reason) => Ok(SceneStatus::Failed(reason.trim().to_string())),
            Err(_) => Ok(SceneStatus::Pending),
        }
    }

    /// The checkpoint file.
    pub fn checkpoint(&self) -> PathBuf {
        self.dir.join("checkpoint.json")
    }

    /// Records a failure (its reason) and drops the checkpoint.
    pub fn record_failure(&self, reason: &str) -> anyhow::Result<()> {
        sim::output::atomic_write::write_atomic(
            &self.dir.join("failed.txt"),
            format!("{reason}\n").as_bytes(),
        )?;
        std::fs::remove_file(self.checkpoint()).ok();
        Ok(())
    }

    /// Forgets a recorded failure so the scene runs again.
    pub fn clear_failure(&self) {
        std::fs::remove_file(self.dir.join("failed.txt")).ok();
    }

    /// The finished scene's summary.
    pub fn summary_json(&self) -> PathBuf {
        self.dir.join("summary.json")
    }

    /// The finished scene's profile table.
    pub fn profile_csv(&self) -> PathBuf {
        self.dir.join("profile.csv")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_summary_missing_a_field_is_refused_naming_the_field_and_the_file() {
        let dir = crate::test_dir("summary");
        let work = SceneWork { dir: dir.clone() };
        std::fs::write(work.profile_csv(), "").unwrap();
        std::fs::write(work.summary_json(), r#"{"name": "tiny"}"#).unwrap();
        let Err(e) = work.status() else {
            panic!("a summary without n_particles was read")
        };
        let message = format!("{e:#}");
        assert!(message.contains("missing field `n_particles`"), "{message}");
        assert!(
            message.contains(&work.summary_json().display().to_string()),
            "{message}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
