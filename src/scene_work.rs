//! The work directory of `suspflow generate`: one folder per run (one replica of a scene,
//! named `<scene id>_seed<seed>`) holding the scene it was made for (`scene.toml`, with the
//! replica's seed), its checkpoint while it runs, and then either its results
//! (`profile.csv`, `summary.json`, as `simulate` writes them) or `failed.txt` with the reason.
//! The files say where each run is, so a re-run continues where the last one stopped.
use anyhow::{bail, Context};
use sim::input::scene::SceneFile;
use std::path::{Path, PathBuf};

/// The fields of a finished scene's `summary.json` (written by `sim`'s `RunSummary`) that the
/// scene table of `generate` shows, read typed.
#[derive(Debug, serde::Deserialize)]
pub struct SceneSummary {
    pub dt: f64,
    pub dt_limit: String,
    pub steps: u64,
    pub strain_to_steady: f64,
    pub strain_total: f64,
    pub momentum_residual: Option<f64>,
    pub mean_overlap: f64,
    pub max_overlap: f64,
    pub wall_s: f64,
    pub code_version: String,
}

impl SceneSummary {
    /// Column names of [`SceneSummary::cells`], in order.
    pub const COLUMNS: [&'static str; 10] = [
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

    /// The fields as table cells, numbers written as in the JSON file (an absent residual,
    /// a run without drag, is an empty cell).
    pub fn cells(&self) -> [String; 10] {
        let number =
            |v: f64| serde_json::Number::from_f64(v).map_or(String::new(), |n| n.to_string());
        [
            number(self.dt),
            self.dt_limit.clone(),
            self.steps.to_string(),
            number(self.strain_to_steady),
            number(self.strain_total),
            self.momentum_residual.map_or(String::new(), number),
            number(self.mean_overlap),
            number(self.max_overlap),
            number(self.wall_s),
            self.code_version.clone(),
        ]
    }
}

/// Where a run is.
pub enum SceneStatus {
    /// Finished: its summary.json.
    Done(SceneSummary),
    /// Failed for this reason; not retried unless asked.
    Failed(String),
    /// Not started, or interrupted (then it has a checkpoint).
    Pending,
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
        let text = toml::to_string(file).context("writing the scene as TOML")?;
        let path = self.dir.join("scene.toml");
        match std::fs::read_to_string(&path) {
            Ok(old) if old != text => bail!(
                "{} holds a different scene than the grid now gives (the grid changed?); \
                 remove the work directory or write to another --out",
                path.display()
            ),
            Ok(_) => Ok(()),
            Err(_) => Ok(sim::output::atomic_write::write_atomic(
                &path,
                text.as_bytes(),
            )?),
        }
    }

    /// The status the files record.
    pub fn status(&self) -> anyhow::Result<SceneStatus> {
        let summary = self.dir.join("summary.json");
        if self.dir.join("profile.csv").exists() && summary.exists() {
            let bytes = std::fs::read(&summary)
                .with_context(|| format!("reading {}", summary.display()))?;
            let value = serde_json::from_slice(&bytes)
                .with_context(|| format!("reading {}", summary.display()))?;
            return Ok(SceneStatus::Done(value));
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

    /// The finished scene's profile table.
    pub fn profile_csv(&self) -> PathBuf {
        self.dir.join("profile.csv")
    }
}
