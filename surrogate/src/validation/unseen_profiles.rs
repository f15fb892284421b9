//! A trained mapping measured on unseen flow profiles (thesis section 6.2, figures 6.2-6.4):
//! the relative L2 error (eq 6.6) of each output on each validation profile and on all of
//! them together, on outputs scaled with the training ranges stored in the model.

use ndarray::{Array2, Axis};

use crate::data::dataset::{Dataset, PROFILE_COLUMN};
use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::error::Result;
use crate::models::intervals::{mean_widths, Intervals, DEFAULT_LEVEL};
use crate::models::model::TrainedModel;
use crate::validation::interval_calibration::fraction;
use crate::validation::target_noise::{beyond_noise, output_standard_errors, target_noise};

/// The name under which the errors over all validation rows together are reported.
pub const ALL_PROFILES: &str = "all";

/// The names under which the errors over the rows inside and outside the model's training
/// domain (see [`crate::data::training_domain`]) are reported.
pub const IN_DOMAIN: &str = "in domain";
pub const OUT_OF_DOMAIN: &str = "out of domain";

/// The seeds' validation error for `output` of mapping `mapping` (thesis figures 6.2-6.4, on
/// the two validation profiles of docs/physics.md section 8 together), as a fraction.
pub fn seeds_validation_error(mapping: &str, output: &str) -> Option<f64> {
    const SEEDS: [(&str, &str, f64); 5] = [
        ("mu", "mu", 0.085),
        ("theta", "phi_loc", 0.007),
        ("theta", "mu", 0.064),
        ("dv", "phi_loc", 0.010),
        ("dv", "mu", 0.086),
    ];
    SEEDS
        .iter()
        .find(|(m, o, _)| *m == mapping && *o == output)
        .map(|&(_, _, error)| error)
}

/// Errors of one group of validation rows.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileError {
    /// The profile, or [`ALL_PROFILES`].
    pub profile: String,
    /// Number of rows measured.
    pub rows: usize,
    /// Relative L2 error of each output (eq 6.6), as a fraction.
    pub per_output: Vec<f64>,
    /// The group's targets' own noise per output ([`Validation::target_noise`] on these
    /// rows); `None` without standard errors.
    pub target_noise: Option<Vec<f64>>,
    /// Per output, the fraction of the rows inside their interval and the mean width of the
    /// intervals (output units); `None` for a model without intervals.
    pub coverage: Option<Vec<f64>>,
    pub mean_width: Option<Vec<f64>>,
}

impl ProfileError {
    /// Each output's error beyond the targets' own noise ([`beyond_noise`]); `None` without
    /// standard errors.
    pub fn beyond_noise(&self) -> Option<Vec<f64>> {
        self.target_noise.as_ref().map(|noise| {
            self.per_output
                .iter()
                .zip(noise)
                .map(|(&e, &n)| beyond_noise(e, n))
                .collect()
        })
    }
}

/// A model's predictions and errors on a validation dataset.
#[derive(Debug, Clone)]
pub struct Validation {
    /// The validation rows the mapping can use (rows with an empty cell are left out).
    pub samples: Samples,
    /// The profile of each row of `samples`.
    pub profiles: Vec<String>,
    /// Predictions in original units, one row per row of `samples`.
    pub predicted: Array2<f64>,
    /// Their intervals at the level asked for; `None` for a model without intervals.
    pub intervals: Option<Intervals>,
    /// One entry per profile, in order of first appearance in the dataset, then one for
    /// [`ALL_PROFILES`]. A profile all of whose rows were left out has no entry.
    pub errors: Vec<ProfileError>,
    /// Whether each row of `samples` lies inside the model's training domain.
    pub in_domain: Vec<bool>,
    /// Errors over the rows inside ([`IN_DOMAIN`]) and outside ([`OUT_OF_DOMAIN`]) the
    /// training domain, all profiles together; a class without rows has no entry.
    pub domain_errors: Vec<ProfileError>,
    /// The targets' own noise on all rows, per output: the relative L2 error (eq 6.6, same
    /// scaling) of the targets shifted by one standard error (`<output>_se`), i.e. what a
    /// model that predicts the true mean scores against targets as noisy as stated. `None`
    /// when an output has no standard-error column or an empty one in a validation row.
    pub target_noise: Option<Vec<f64>>,
}

impl Validation {
    /// Predicts `dataset` with `model` and measures the errors per profile and overall, with
    /// the intervals at [`DEFAULT_LEVEL`].
    pub fn run(model: &TrainedModel, dataset: &Dataset) -> Result<Self> {
        Self::run_at(model, dataset, DEFAULT_LEVEL)
    }

    /// [`Validation::run`] with the intervals at `level`.
    pub fn run_at(model: &TrainedModel, dataset: &Dataset, level: f64) -> Result<Self> {
        let mapping = Mapping::by_name(&model.meta().mapping)?;
        let samples = Samples::from_dataset(dataset, mapping)?;
        let predicted = model.predict_features(samples.features.view())?;
        let standard_errors = output_standard_errors(dataset, &samples)?;
        // The intervals of the targets as noisy as their standard errors say.
        let intervals = model.predict_intervals(
            samples.features.view(),
            standard_errors.as_ref().map(|se| se.view()),
            level,
        )?;
        let scaling = &model.meta().scaling;
        let all_profiles = dataset.text(PROFILE_COLUMN)?;
        let profiles: Vec<String> = samples
            .data_rows
            .iter()
            .map(|&row| all_profiles[row - 1].clone())
            .collect();
        let group_error = |name: &str, select: &dyn Fn(usize) -> bool| -> Result<_> {
            let rows: Vec<usize> = (0..samples.n_rows()).filter(|&i| select(i)).collect();
            if rows.is_empty() {
                return Ok(None);
            }
            let truth = samples.outputs.select(Axis(0), &rows);
            let target_noise = standard_errors
                .as_ref()
                .map(|se| target_noise(scaling, truth.view(), se.select(Axis(0), &rows).view()))
                .transpose()?;
            let (coverage, mean_width) = match &intervals {
                Some(i) => {
                    let part = Intervals {
                        level,
                        lower: i.lower.select(Axis(0), &rows),
                        upper: i.upper.select(Axis(0), &rows),
                    };
                    let covered = part.covers(truth.view());
                    let coverage = covered
                        .columns()
                        .into_iter()
                        .map(|c| fraction(c.iter().copied()))
                        .collect();
                    (Some(coverage), Some(mean_widths(&part)))
                }
                None => (None, None),
            };
            Ok(Some(ProfileError {
                per_output: model.evaluate(&samples.subset(&rows)?)?,
                profile: name.to_owned(),
                rows: rows.len(),
                target_noise,
                coverage,
                mean_width,
            }))
        };
        let mut errors = Vec::new();
        for profile in profile_names(dataset)? {
            errors.extend(group_error(&profile, &|i| profiles[i] == profile)?);
        }
        errors.extend(group_error(ALL_PROFILES, &|_| true)?);
        let in_domain = model.domain().inside(samples.features.view())?;
        let mut domain_errors = Vec::new();
        domain_errors.extend(group_error(IN_DOMAIN, &|i| in_domain[i])?);
        domain_errors.extend(group_error(OUT_OF_DOMAIN, &|i| !in_domain[i])?);
        let target_noise = errors
            .iter()
            .find(|e| e.profile == ALL_PROFILES)
            .and_then(|e| e.target_noise.clone());
        Ok(Validation {
            samples,
            profiles,
            predicted,
            intervals,
            errors,
            in_domain,
            domain_errors,
            target_noise,
        })
    }
}

/// The distinct values of [`PROFILE_COLUMN`], in order of first appearance.
pub fn profile_names(dataset: &Dataset) -> Result<Vec<String>> {
    let mut names: Vec<String> = Vec::new();
    for profile in dataset.text(PROFILE_COLUMN)? {
        if !names.contains(profile) {
            names.push(profile.clone());
        }
    }
    Ok(names)
}
