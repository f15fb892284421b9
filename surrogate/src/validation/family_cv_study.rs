//! A whole leave-one-family-out study of a table (`cv.json`): per mapping the comparison of
//! trees, backbone and both ([`FamilyCv`]), optionally the learning curve
//! ([`LearningCurve`]), and the intervals' coverage on the same folds ([`IntervalStudy`]).
//! One writer and one reader for the command and Python.
use crate::data::dataset::Dataset;
use crate::data::files::write;
use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::data::table_kind::TableKind;
use crate::error::{Result, SurrogateError};
use crate::models::booster::HyperParameters;
use crate::validation::family_cv::{FamilyCv, FoldErrors};
use crate::validation::family_folds::family_names;
use crate::validation::family_learning_curve::LearningCurve;
use crate::validation::interval_calibration::{IntervalCoverage, IntervalStudy};
use crate::validation::target_noise::output_standard_errors;
use crate::validation::unseen_profiles::profile_names;
use serde::Serialize;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// What a study measures besides the three variants' errors.
#[derive(Clone, Debug)]
pub struct CvSettings {
    /// Numbers of training families of the learning curve (none: no curve).
    pub learning_curve: Vec<usize>,
    /// Seeded draws of the training families per held-out family and count.
    pub draws: usize,
    /// Seed of those draws.
    pub seed: u64,
    /// Level of the intervals whose coverage is measured, in (0, 1).
    pub level: f64,
}

/// What a running study reports, in order, for each mapping.
pub enum CvProgress<'a> {
    /// The mapping starts on `samples` (its usable rows; `skipped_rows` those left out), of
    /// `families` profile families, with trees `params`.
    Mapping {
        mapping: &'a Mapping,
        samples: &'a Samples,
        families: usize,
        params: &'a HyperParameters,
    },
    /// The learning curve starts, at `counts` training families with `draws` draws each.
    LearningCurve {
        mapping: &'a Mapping,
        counts: &'a [usize],
        draws: usize,
    },
    /// Fold `done` of `families` finished (folds finish in any order).
    Fold {
        mapping: &'a Mapping,
        done: usize,
        families: usize,
        fold: &'a FoldErrors,
    },
    /// The intervals' study starts.
    Intervals { mapping: &'a Mapping },
}

/// Everything a study measured: `cv.json`.
#[derive(Debug, Clone, Serialize)]
pub struct FamilyCvStudy {
    /// The table's source name.
    pub data: String,
    /// FNV-1a 64 hash of the data file, 16 hex digits.
    pub fnv1a_64: schema::Fingerprint,
    /// The table's kind, described ([`TableKind::describe`]), when it has one.
    pub table: Option<String>,
    pub families: Vec<String>,
    /// Where the trees' settings were read.
    pub models: String,
    /// Wall seconds of the study.
    pub seconds: f64,
    pub mappings: Vec<FamilyCv>,
    /// One per mapping when the settings ask for a learning curve.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub learning_curves: Vec<LearningCurve>,
    /// The intervals' coverage on the same folds, one per mapping.
    pub intervals: Vec<IntervalCoverage>,
}

impl FamilyCvStudy {
    /// Runs the study of `dataset` for each mapping with its trees' settings (`plan`, read
    /// from the models in `models`), telling `progress` as it goes. The folds run in
    /// parallel on rayon's pool; the figures do not depend on the number of threads.
    pub fn run(
        dataset: &Dataset,
        plan: &[(&Mapping, HyperParameters)],
        models: &Path,
        settings: &CvSettings,
        progress: &(dyn Fn(CvProgress) + Sync),
    ) -> Result<Self> {
        let started = Instant::now();
        let table = TableKind::of(dataset).ok().map(|kind| kind.describe());
        let families = profile_names(dataset)?;
        let (mut mappings, mut learning_curves, mut intervals) =
            (Vec::new(), Vec::new(), Vec::new());
        for (mapping, params) in plan {
            let within = |what: &str| {
                let what = format!("{what} `{}`", mapping.name);
                move |e| SurrogateError::Within {
                    what,
                    source: Box::new(e),
                }
            };
            let samples = Samples::from_dataset(dataset, mapping)?;
            let n = family_names(&samples)?.len();
            progress(CvProgress::Mapping {
                mapping,
                samples: &samples,
                families: n,
                params,
            });
            if !settings.learning_curve.is_empty() {
                progress(CvProgress::LearningCurve {
                    mapping,
                    counts: &settings.learning_curve,
                    draws: settings.draws,
                });
                let curve = LearningCurve::run(
                    mapping,
                    &samples,
                    params,
                    &settings.learning_curve,
                    settings.draws,
                    settings.seed,
                );
                learning_curves.push(curve.map_err(within("the learning curve of"))?);
            }
            let finished = AtomicUsize::new(0);
            let standard_errors = output_standard_errors(dataset, &samples)?;
            let cv = FamilyCv::run(
                mapping,
                &samples,
                standard_errors.as_ref(),
                params,
                &|fold| {
                    let done = finished.fetch_add(1, Ordering::Relaxed) + 1;
                    progress(CvProgress::Fold {
                        mapping,
                        done,
                        families: n,
                        fold,
                    });
                },
            );
            mappings.push(cv.map_err(within("cross-validating"))?);
            progress(CvProgress::Intervals { mapping });
            let study = IntervalStudy::run(
                mapping,
                &samples,
                standard_errors.as_ref().map(|se| se.view()),
                params,
                settings.level,
            );
            intervals.push(study.map_err(within("the intervals of"))?.coverage);
        }
        Ok(FamilyCvStudy {
            data: dataset.source_name().to_owned(),
            fnv1a_64: dataset.fingerprint(),
            table,
            families,
            models: models.display().to_string(),
            seconds: started.elapsed().as_secs_f64(),
            mappings,
            learning_curves,
            intervals,
        })
    }

    /// Writes the study as pretty JSON to `path`, atomically.
    pub fn write_json(&self, path: &Path) -> Result<()> {
        let json = serde_json::to_string_pretty(self).map_err(|source| SurrogateError::Json {
            path: path.to_path_buf(),
            source,
        })? + "\n";
        write(path, json.as_bytes())
    }
}
