//! Training the surrogate mappings of docs/physics.md section 8 into a folder, for
//! `suspflow train` and Python's `suspflow.train` alike ([`TrainingJob::run`]).
//!
//! Per mapping: its hyper-parameters ([`ParamsSource`]: chosen by cross-validating every
//! setting of `surrogate::standard_grid()` on the training data alone, recorded in
//! `<mapping>.tuning.json`; XGBoost's defaults; or those of the models in a folder), the fit
//! on every row, the intervals (`surrogate::IntervalStudy`: the conformal scores of the rows
//! predicted by the folds that held them out, and quantile trees), and the model saved.
//! Then, when `dv` and `theta` were trained with intervals, the bands of `solve`
//! ([`calibrate_bands`], every family's scenes solved with the models of its fold) into
//! `bands.json`. Nothing a user made is replaced unless the job is forced.

use ndarray::Array2;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;
use surrogate::{
    output_standard_errors, standard_grid, CvScore, Dataset, HyperParameters, IntervalCalibration,
    IntervalStudy, LeftOut, Mapping, ModelMeta, Samples, TrainedModel, Tuning, DEFAULT_LEVEL,
};

use crate::band_calibration::{calibrate_bands, ShippedModel};
use crate::bands::BandCalibration;
use crate::error::{Result, SolverError};

/// Where each mapping's hyper-parameters come from.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamsSource {
    /// Chosen by cross-validation over `surrogate::standard_grid()` (the lowest mean
    /// relative L2 error), the search recorded in `<out>/<mapping>.tuning.json`.
    Tune,
    /// XGBoost's defaults ([`HyperParameters::default`], the thesis's untuned setting).
    Defaults,
    /// Those of the model of the same mapping saved in this folder (its sidecar's).
    From(PathBuf),
}

/// One training: the data, the folder the models go to, and what to do.
pub struct TrainingJob<'a> {
    /// The training table (per-run or ensemble table).
    pub data: &'a Dataset,
    /// The table's file, recorded in each sidecar as the loaders look for it
    /// ([`ModelMeta::recorded_source`]); `None` keeps the dataset's own source name (a
    /// table that came as bytes).
    pub data_file: Option<&'a Path>,
    /// The folder of the models (created if missing).
    pub out: &'a Path,
    pub mappings: Vec<&'static Mapping>,
    pub params: ParamsSource,
    /// Calibrate the bands of `solve` when `dv` and `theta` are trained together.
    pub bands: bool,
    /// Replace the models (and bands) already in `out`.
    pub force: bool,
    /// Stamped into `bands.json`.
    pub code_version: &'a str,
    /// Checked before each mapping and before the bands: once set, the job stops with
    /// [`SolverError::Interrupted`], the models saved until then kept.
    pub interrupt: Option<&'a AtomicBool>,
}

/// What a training reports while it works, for a front end to show.
pub enum TrainingEvent<'a> {
    /// The outputs were checked; training begins on `data`.
    Started { data: &'a Dataset },
    /// A mapping's rows were taken from the table (`samples.skipped_rows` left out for an
    /// empty cell).
    Samples {
        mapping: &'static Mapping,
        samples: &'a Samples,
    },
    /// A mapping's hyper-parameters were chosen by cross-validation.
    Tuned {
        mapping: &'static Mapping,
        tuning: &'a TuningSummary,
    },
    /// The table gives no standard error of every output: the intervals are calibrated as
    /// if its targets were noiseless.
    Noiseless { mapping: &'static Mapping },
    /// A mapping's intervals were calibrated.
    Intervals {
        mapping: &'static Mapping,
        intervals: &'a IntervalSummary,
    },
    /// A mapping is saved without intervals, for the reason given.
    WithoutIntervals {
        mapping: &'static Mapping,
        why: &'a str,
    },
    /// A mapping's model was saved.
    Trained {
        mapping: &'static Mapping,
        trained: &'a TrainedMapping,
    },
    /// The `done`-th fold of the bands' calibration solved the scenes of `family`.
    BandsFold { done: usize, family: &'a str },
}

/// The choice of one mapping's hyper-parameters by cross-validation (the record
/// `<mapping>.tuning.json` holds every setting's scores besides).
#[derive(Debug, Clone, Serialize)]
pub struct TuningSummary {
    /// Settings cross-validated.
    pub settings: usize,
    pub folds: usize,
    /// What each fold left out (`simulations` or `profile families`).
    pub left_out: String,
    /// The chosen setting and its mean relative L2 error per output (eq 6.6, a fraction).
    pub chosen: CvScore,
    /// XGBoost's defaults and their error.
    pub defaults: CvScore,
    /// Why the settings with the physics backbone were left out of the search, if they were.
    pub backbone_excluded: Option<String>,
    /// Wall time of the search, s.
    pub seconds: f64,
}

/// The calibration of one mapping's intervals at [`DEFAULT_LEVEL`].
#[derive(Debug, Clone, Serialize)]
pub struct IntervalSummary {
    pub level: f64,
    pub folds: usize,
    /// What each fold held out.
    pub held_out: String,
    /// Per output: the fraction of the rows inside the interval the other folds gave them.
    pub fold_coverage: Vec<f64>,
    /// Per output: the intervals' mean width (output units).
    pub fold_mean_width: Vec<f64>,
    /// Wall time of the study, s.
    pub seconds: f64,
}

/// One mapping trained and saved.
#[derive(Debug, Clone, Serialize)]
pub struct TrainedMapping {
    pub mapping: String,
    pub features: Vec<String>,
    pub outputs: Vec<String>,
    /// Rows trained on, and rows of the table left out for an empty cell.
    pub rows: usize,
    pub skipped_rows: usize,
    pub params: HyperParameters,
    /// The cross-validated choice, when the parameters were tuned.
    pub tuning: Option<TuningSummary>,
    /// Relative L2 error (eq 6.6, a fraction) of each output on the training rows.
    pub training_error: Vec<f64>,
    /// Whether the table gave the targets' standard errors (else the intervals take the
    /// targets as noiseless).
    pub target_noise: bool,
    /// The intervals, or why the model has none.
    pub intervals: Option<IntervalSummary>,
    pub without_intervals: Option<String>,
    /// Wall time of the fit on every row, s.
    pub fit_seconds: f64,
}

/// What became of the bands of `solve`.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum BandsOutcome {
    /// The job did not ask for them.
    Skipped,
    /// `dv` and `theta` were not both trained with intervals; `kept` names an earlier
    /// `bands.json` left as it was (no longer describing the models).
    NotTrained {
        kept: Option<PathBuf>,
    },
    /// `mapping`'s folds left out `held_out` rather than profile families (too few
    /// families), and the bands are calibrated leaving one family out.
    TooFewFamilies {
        mapping: String,
        held_out: String,
    },
    Calibrated(BandsSummary),
}

/// The bands' calibration, as `bands.json` holds it in full.
#[derive(Debug, Clone, Serialize)]
pub struct BandsSummary {
    pub folds: usize,
    pub held_out: String,
    pub closures: Vec<ClosureSummary>,
    pub seconds: f64,
}

/// One closure's bands.
#[derive(Debug, Clone, Serialize)]
pub struct ClosureSummary {
    pub closure: String,
    pub scenes: usize,
    /// Scenes whose solve stalled.
    pub failed: usize,
    /// Fraction of the held-out bins inside the band at 90 %, for u, phi_loc and mu.
    pub fold_coverage: [f64; 3],
}

/// A finished training.
#[derive(Debug, Clone, Serialize)]
pub struct TrainingResult {
    pub mappings: Vec<TrainedMapping>,
    pub bands: BandsOutcome,
    /// Wall time of the whole job, s.
    pub seconds: f64,
}

/// A mapping's interval study, kept for the bands.
type Study = (&'static Mapping, HyperParameters, IntervalStudy);

impl TrainingJob<'_> {
    /// The files the job writes that hold a user's work when they exist: each mapping's
    /// trees and sidecars (any one alone counts) and, when bands are asked for with `dv`
    /// and `theta`, `bands.json`; each with what it is.
    fn outputs(&self) -> Vec<(PathBuf, String)> {
        let mut files = Vec::new();
        for mapping in &self.mappings {
            let what = format!("a trained `{}` model", mapping.name);
            let model = ["json", "meta.json", "domain.json"]
                .iter()
                .map(|suffix| self.out.join(format!("{}.{suffix}", mapping.name)))
                .chain([
                    Tuning::path(self.out, mapping.name),
                    IntervalCalibration::path(self.out, mapping.name),
                ])
                .chain(
                    mapping
                        .outputs
                        .iter()
                        .map(|o| IntervalCalibration::trees_path(self.out, mapping.name, o)),
                );
            files.extend(model.map(|path| (path, what.clone())));
        }
        let trains = |name: &str| self.mappings.iter().any(|m| m.name == name);
        if self.bands && trains("dv") && trains("theta") {
            files.push((
                BandCalibration::path(self.out),
                "the calibration of solve's bands".to_owned(),
            ));
        }
        files
    }

    /// Fails with [`SolverError::WouldReplace`], naming the first existing output, unless
    /// the job is forced.
    fn refuse_replacing(&self) -> Result<()> {
        match self.outputs().into_iter().find(|(path, _)| path.exists()) {
            Some((path, what)) if !self.force => Err(SolverError::WouldReplace { path, what }),
            _ => Ok(()),
        }
    }

    /// Trains and saves every mapping, then the bands, telling `observe` as it goes. Fails
    /// with [`SolverError::WouldReplace`] before any work when `out` holds a file of a
    /// model (or the bands) the job would write and it is not forced. The folds run on
    /// rayon's pool.
    pub fn run(&self, observe: &(dyn Fn(TrainingEvent) + Sync)) -> Result<TrainingResult> {
        self.refuse_replacing()?;
        let started = Instant::now();
        observe(TrainingEvent::Started { data: self.data });
        let mut trained = Vec::new();
        let mut studies = Vec::new();
        for &mapping in &self.mappings {
            self.check_interrupt(&trained)?;
            let (result, study) = self.train(mapping, observe)?;
            observe(TrainingEvent::Trained {
                mapping,
                trained: &result,
            });
            trained.push(result);
            studies.extend(study);
        }
        let bands = if self.bands {
            self.check_interrupt(&trained)?;
            self.bands(&studies, observe)?
        } else {
            BandsOutcome::Skipped
        };
        Ok(TrainingResult {
            mappings: trained,
            bands,
            seconds: started.elapsed().as_secs_f64(),
        })
    }

    /// Fails with [`SolverError::Interrupted`] once the interrupt is set.
    fn check_interrupt(&self, trained: &[TrainedMapping]) -> Result<()> {
        match self.interrupt {
            Some(flag) if flag.load(Ordering::SeqCst) => Err(SolverError::Interrupted {
                saved: trained.iter().map(|t| t.mapping.clone()).collect(),
            }),
            _ => Ok(()),
        }
    }

    /// Trains, calibrates and saves one mapping; its interval study when it has one.
    fn train(
        &self,
        mapping: &'static Mapping,
        observe: &(dyn Fn(TrainingEvent) + Sync),
    ) -> Result<(TrainedMapping, Option<Study>)> {
        let mut samples = Samples::from_dataset(self.data, mapping)?;
        observe(TrainingEvent::Samples {
            mapping,
            samples: &samples,
        });
        if let Some(file) = self.data_file {
            // From the folder holding `out`, whatever the directory train ran in
            // (ModelMeta::training_file).
            samples.source_name = ModelMeta::recorded_source(file, self.out);
        }
        let (params, tuning) = match &self.params {
            ParamsSource::Tune => {
                let tuning = Tuning::run(mapping, &samples, &standard_grid())?;
                tuning.save(self.out).map_err(SolverError::during(format!(
                    "saving the {} tuning record",
                    mapping.name
                )))?;
                let summary = TuningSummary::of(&tuning);
                observe(TrainingEvent::Tuned {
                    mapping,
                    tuning: &summary,
                });
                (tuning.chosen.params, Some(summary))
            }
            ParamsSource::Defaults => {
                Tuning::remove_stale(self.out, mapping.name)?;
                (HyperParameters::default(), None)
            }
            ParamsSource::From(dir) => {
                Tuning::remove_stale(self.out, mapping.name)?;
                let params = ModelMeta::load_params(dir, mapping.name).map_err(
                    SolverError::during(format!(
                        "reading the hyper-parameters of `{}` from {}",
                        mapping.name,
                        dir.display()
                    )),
                )?;
                (params, None)
            }
        };
        let t = Instant::now();
        let model = TrainedModel::fit(mapping, &samples, &params)?;
        let fit_seconds = t.elapsed().as_secs_f64();
        // The targets' standard errors keep the model's error apart from their noise.
        let noise = output_standard_errors(self.data, &samples)?;
        if noise.is_none() {
            observe(TrainingEvent::Noiseless { mapping });
        }
        let (model, intervals) =
            with_intervals(mapping, model, &samples, noise.as_ref(), &params, observe)?;
        let (study, without_intervals) = match intervals {
            Intervals::Calibrated(study, summary) => (Some((*study, summary)), None),
            Intervals::Without(why) => (None, Some(why)),
        };
        model.save(self.out).map_err(SolverError::during(format!(
            "saving the {} model",
            mapping.name
        )))?;
        let result = TrainedMapping {
            mapping: mapping.name.to_owned(),
            features: mapping.features.iter().map(|f| f.to_string()).collect(),
            outputs: mapping.outputs.iter().map(|o| o.to_string()).collect(),
            rows: samples.n_rows(),
            skipped_rows: samples.skipped_rows,
            params: params.clone(),
            tuning,
            training_error: model.evaluate(&samples)?,
            target_noise: noise.is_some(),
            intervals: study.as_ref().map(|(_, summary)| summary.clone()),
            without_intervals,
            fit_seconds,
        };
        Ok((result, study.map(|(s, _)| (mapping, params, s))))
    }

    /// Calibrates the bands of `solve` on the training scenes and writes `<out>/bands.json`,
    /// when `dv` and `theta` were trained with intervals whose folds left out families.
    fn bands(
        &self,
        studies: &[Study],
        observe: &(dyn Fn(TrainingEvent) + Sync),
    ) -> Result<BandsOutcome> {
        let trained = |name: &str| studies.iter().any(|(m, _, _)| m.name == name);
        if !(trained("dv") && trained("theta")) {
            let path = BandCalibration::path(self.out);
            let kept = path.exists().then_some(path);
            return Ok(BandsOutcome::NotTrained { kept });
        }
        if let Some((mapping, _, study)) = studies
            .iter()
            .find(|(_, _, s)| s.calibration.held_out != LeftOut::Family.plural())
        {
            return Ok(BandsOutcome::TooFewFamilies {
                mapping: mapping.name.to_owned(),
                held_out: study.calibration.held_out.clone(),
            });
        }
        let t = Instant::now();
        let models: Vec<ShippedModel> = studies
            .iter()
            .map(|(mapping, params, study)| ShippedModel {
                mapping,
                params,
                study,
            })
            .collect();
        let families = AtomicUsize::new(0);
        let calibration = calibrate_bands(self.data, &models, self.code_version, &|family| {
            let done = families.fetch_add(1, Ordering::Relaxed) + 1;
            observe(TrainingEvent::BandsFold { done, family });
        })
        .map_err(SolverError::during("calibrating the bands of solve"))?;
        calibration.save(self.out)?;
        Ok(BandsOutcome::Calibrated(BandsSummary {
            folds: calibration.folds,
            held_out: calibration.held_out.clone(),
            closures: calibration
                .closures
                .iter()
                .map(|c| ClosureSummary {
                    closure: c.closure.clone(),
                    scenes: c.scenes,
                    failed: c.failed,
                    fold_coverage: c.fold_coverage,
                })
                .collect(),
            seconds: t.elapsed().as_secs_f64(),
        }))
    }
}

impl TuningSummary {
    fn of(tuning: &Tuning) -> Self {
        TuningSummary {
            settings: tuning.scores.len(),
            folds: tuning.folds,
            left_out: tuning.left_out.plural().to_owned(),
            chosen: tuning.chosen.clone(),
            defaults: tuning.untuned.clone(),
            backbone_excluded: tuning.backbone_excluded.clone(),
            seconds: tuning.seconds,
        }
    }
}

/// A model's intervals: the study that calibrated them and its summary, or why there are
/// none.
enum Intervals {
    Calibrated(Box<IntervalStudy>, IntervalSummary),
    Without(String),
}

/// `model` with its intervals calibrated on the folds of `samples` (those of tuning), the
/// study that calibrated them and its summary; or the model as it is, with the reason, when
/// the data hold too few simulations to leave one out.
fn with_intervals(
    mapping: &'static Mapping,
    model: TrainedModel,
    samples: &Samples,
    noise: Option<&Array2<f64>>,
    params: &HyperParameters,
    observe: &(dyn Fn(TrainingEvent) + Sync),
) -> Result<(TrainedModel, Intervals)> {
    let t = Instant::now();
    let noise = noise.map(Array2::view);
    let study = match IntervalStudy::run(mapping, samples, noise, params, DEFAULT_LEVEL) {
        Ok(study) => study,
        Err(e) => {
            let why = e.to_string();
            observe(TrainingEvent::WithoutIntervals { mapping, why: &why });
            return Ok((model, Intervals::Without(why)));
        }
    };
    let c = &study.calibration;
    let summary = IntervalSummary {
        level: DEFAULT_LEVEL,
        folds: c.folds,
        held_out: c.held_out.clone(),
        fold_coverage: c.fold_coverage.clone(),
        fold_mean_width: c.fold_mean_width.clone(),
        seconds: t.elapsed().as_secs_f64(),
    };
    observe(TrainingEvent::Intervals {
        mapping,
        intervals: &summary,
    });
    let trees = model.fit_quantile_trees(samples, params)?;
    let model = model.with_intervals(trees, study.calibration.clone())?;
    Ok((model, Intervals::Calibrated(Box::new(study), summary)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four profile families of the power law mu = 3.6 J^0.44, ten rows each, with
    /// phi_loc from the jamming law and Delta_v a ramp in J.
    fn families() -> Dataset {
        let mut text = String::from("scene_id,profile,phi,seed,J,phi_loc,mu,Delta_v\n");
        for k in 0..4 {
            for b in 0..10 {
                let j = 1e-3 * 2.5f64.powi(k) * 10f64.powf(f64::from(b) / 10.0);
                let mu = 3.6 * j.powf(0.44);
                let phi_loc = 0.66 - (j / (2.0 * mu)).sqrt();
                let dv = 0.02 + 0.5 * j;
                text += &format!("f{k},\"0.{k}1*sin(2*pi*y/L)\",0.5,1,{j},{phi_loc},{mu},{dv}\n");
            }
        }
        Dataset::from_csv_bytes(text.as_bytes(), "families").unwrap()
    }

    /// A scratch folder for one test.
    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("solver_{name}_{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        dir
    }

    /// An untuned job training `mappings` of [`families`] into `out`.
    fn job<'a>(data: &'a Dataset, out: &'a Path, mappings: &[&str]) -> TrainingJob<'a> {
        TrainingJob {
            data,
            data_file: None,
            out,
            mappings: Mapping::select(mappings).unwrap(),
            params: ParamsSource::Defaults,
            bands: true,
            force: false,
            code_version: "test",
            interrupt: None,
        }
    }

    #[test]
    fn an_interrupt_stops_before_the_next_mapping_keeping_the_saved_ones() {
        let out = scratch("training_interrupt");
        let data = families();
        let stop = AtomicBool::new(false);
        let mut job = job(&data, &out, &["mu", "dv"]);
        job.interrupt = Some(&stop);
        let stop_when_trained = |event: TrainingEvent| {
            if let TrainingEvent::Trained { .. } = event {
                stop.store(true, Ordering::SeqCst);
            }
        };
        match job.run(&stop_when_trained) {
            Err(SolverError::Interrupted { saved }) => assert_eq!(saved, ["mu"]),
            other => panic!("not interrupted: {other:?}"),
        }
        assert!(out.join("mu.json").exists() && out.join("mu.intervals.json").exists());
        assert!(!out.join("dv.json").exists() && !out.join("dv.meta.json").exists());
        std::fs::remove_dir_all(&out).ok();
    }

    #[test]
    fn a_model_file_in_the_folder_is_replaced_only_when_forced() {
        let out = scratch("training_force");
        std::fs::create_dir_all(&out).unwrap();
        let lone = out.join("mu.intervals.json");
        std::fs::write(&lone, "mine").unwrap();
        let data = families();
        let mut job = job(&data, &out, &["mu"]);
        let events = AtomicUsize::new(0);
        let count = |_: TrainingEvent| {
            events.fetch_add(1, Ordering::Relaxed);
        };
        match job.run(&count) {
            Err(SolverError::WouldReplace { path, what }) => {
                assert_eq!(
                    (path, what.as_str()),
                    (lone.clone(), "a trained `mu` model")
                );
            }
            other => panic!("not refused: {other:?}"),
        }
        assert_eq!(events.load(Ordering::Relaxed), 0, "refused before any work");
        assert_eq!(std::fs::read_to_string(&lone).unwrap(), "mine");

        job.force = true;
        let result = job.run(&count).unwrap();
        let mu = &result.mappings[0];
        assert_eq!((mu.rows, mu.skipped_rows), (40, 0));
        assert_eq!(mu.intervals.as_ref().unwrap().held_out, "profile families");
        // Started, samples, noiseless, intervals, trained.
        assert_eq!(events.load(Ordering::Relaxed), 5);
        // `dv` and `theta` were not trained: no bands, and none were there to keep.
        assert!(matches!(
            result.bands,
            BandsOutcome::NotTrained { kept: None }
        ));
        assert_ne!(std::fs::read_to_string(&lone).unwrap(), "mine");
        std::fs::remove_dir_all(&out).ok();
    }
}
