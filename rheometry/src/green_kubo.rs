//! The result of a Green-Kubo run at rest ([`sim::run::green_kubo`]): the Brownian
//! viscosity `eta_B / eta` integrated to the largest lag and extrapolated as the seeds did
//! ([`Relaxation`]), written as `green_kubo.json` by [`GreenKuboResult`] and read back by it,
//! with the correlation and its running integral in `green_kubo.csv` beside it.
use crate::error::{Result, RheometryError};
use serde::{Deserialize, Serialize};
use sim::input::scene::Scene;
use sim::run::green_kubo::{GreenKuboJob, GreenKuboRun};
use sim::run::run_folder::{Ended, RunFolder};
use sim::run::{Progress, RunOptions};
use sim::sampling::green_kubo::GreenKubo;
use sim::Simulation;
use std::fmt::Write as _;
use std::path::Path;
use surrogate::rheology::relaxation_fit::Relaxation;

/// The viscosity of a finished run.
pub const JSON: &str = "green_kubo.json";
/// Its correlation and running integral.
pub const CSV: &str = "green_kubo.csv";
/// The files of a finished Green-Kubo run.
pub const WRITTEN: [&str; 2] = [CSV, JSON];

/// A Green-Kubo run's result (`green_kubo.json`); viscosities over the fluid's `eta`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GreenKuboResult {
    pub scene: String,
    pub n_particles: usize,
    pub phi_actual: f64,
    #[serde(rename = "kT")]
    pub kt: f64,
    pub tau_b: f64,
    /// The running integral at the largest lag, and its error from the blocks.
    pub eta_brownian_over_eta: f64,
    pub eta_brownian_over_eta_se: f64,
    /// The running integral extrapolated as `eta_inf (1 - exp(-s / tau))`, as the seeds
    /// did; its error is the integral's, scaled by limit / integral.
    pub extrapolated_eta_brownian_over_eta: f64,
    pub extrapolated_eta_brownian_over_eta_se: f64,
    /// The relaxation time `tau` of the extrapolation, in `tau_B`.
    pub relaxation_tau_b: f64,
    pub blocks: usize,
    pub warmup_tau_b: f64,
    pub span_tau_b: f64,
    pub max_lag_tau_b: f64,
    pub every_steps: u64,
    pub code_version: String,
    /// The scene's warnings (its time step, say): what limits the result's validity.
    #[serde(default)]
    pub warnings: Vec<String>,
}

impl GreenKuboResult {
    /// The result of the integral `gk` of the run `run` of `scene`.
    pub fn of(
        scene: &Scene,
        run: &GreenKuboRun,
        gk: &GreenKubo,
        code_version: &str,
    ) -> Result<Self> {
        let eta = scene.file.fluid.eta;
        let tau_b = scene.thermal.map_or(f64::NAN, |t| t.tau_b);
        let relaxation = Relaxation::fit(&gk.lags, &gk.running)?;
        // The blocks are not fitted one by one.
        let limit_se = gk.viscosity_se * (relaxation.limit / gk.viscosity).abs();
        Ok(GreenKuboResult {
            scene: scene.file.name.clone(),
            n_particles: scene.n_particles(),
            phi_actual: scene.phi_actual,
            kt: scene.file.fluid.kt,
            tau_b,
            eta_brownian_over_eta: gk.viscosity / eta,
            eta_brownian_over_eta_se: gk.viscosity_se / eta,
            extrapolated_eta_brownian_over_eta: relaxation.limit / eta,
            extrapolated_eta_brownian_over_eta_se: limit_se / eta,
            relaxation_tau_b: relaxation.time / tau_b,
            blocks: gk.blocks,
            warmup_tau_b: run.warmup_tau_b,
            span_tau_b: run.span_tau_b,
            max_lag_tau_b: run.max_lag_tau_b,
            every_steps: run.every,
            code_version: code_version.into(),
            warnings: scene.warnings.clone(),
        })
    }

    /// Writes `green_kubo.json` and, from `gk` (at fluid viscosity `eta`),
    /// `green_kubo.csv` into `dir`.
    pub fn write(&self, dir: &Path, gk: &GreenKubo, eta: f64) -> Result<()> {
        let mut csv = String::from("lag,lag_tau_b,correlation,running_eta_over_eta\n");
        for ((lag, c), r) in gk.lags.iter().zip(&gk.correlation).zip(&gk.running) {
            let _ = writeln!(csv, "{lag},{},{c},{}", lag / self.tau_b, r / eta);
        }
        schema::write_atomic(&dir.join(CSV), csv.as_bytes())?;
        let json = serde_json::to_string_pretty(self).expect("a result serialises");
        Ok(schema::write_atomic(&dir.join(JSON), json.as_bytes())?)
    }

    /// The result written in `dir`.
    pub fn read(dir: &Path) -> Result<Self> {
        let path = dir.join(JSON);
        let err = |message: String| RheometryError::File {
            path: path.display().to_string(),
            message,
        };
        let text = std::fs::read_to_string(&path)
            .map_err(|e| err(format!("{e} (a Green-Kubo run's folder?)")))?;
        serde_json::from_str(&text).map_err(|e| err(format!("not a Green-Kubo result: {e}")))
    }
}

/// Runs the Green-Kubo run `run` of `scene` in `folder` (see [`RunFolder::run`]), its
/// result written there when it finishes.
pub fn run_in_folder(
    folder: &RunFolder,
    scene: &Scene,
    run: GreenKuboRun,
    opts: RunOptions,
    progress: &mut dyn FnMut(&Progress, &Simulation),
) -> Result<Ended<GreenKuboResult>> {
    let mut result = None;
    let code_version = opts.code_version;
    let ended = folder.run(
        scene,
        &mut GreenKuboJob::new(scene, run),
        opts,
        progress,
        |dir, gk| {
            let r = GreenKuboResult::of(scene, &run, gk, code_version)
                .and_then(|r| r.write(dir, gk, scene.file.fluid.eta).map(|()| r))
                .map_err(|e| sim::SimError::Output {
                    path: dir.display().to_string(),
                    message: e.to_string(),
                })?;
            result = Some(r);
            Ok(())
        },
    )?;
    Ok(match ended {
        Ended::Finished(_) => Ended::Finished(result.expect("written when finished")),
        Ended::Interrupted { step } => Ended::Interrupted { step },
        Ended::InterruptedPacking => Ended::InterruptedPacking,
        Ended::Failed(reason) => Ended::Failed(reason),
    })
}
