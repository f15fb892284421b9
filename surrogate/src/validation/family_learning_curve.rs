//! Would more profile families help? The leave-one-family-out error against the number of
//! families a model is trained on.
//!
//! For each held-out family (the folds of [`crate::validation::family_folds`]) and each count
//! `n` of training families, a model with the given hyper-parameters is fitted on the rows of
//! `n` of the other families, drawn at random (`draws` times; once when `n` is all of them),
//! and scored on the held-out rows by eq 6.6 with the outputs min-max scaled on the rows of
//! *all* the other families, so that every `n` is measured with the same yardstick. With all
//! the other families the point is the family cross-validation's own error for the same
//! trees ([`crate::validation::family_cv`]). The errors are averaged over the draws per
//! family, then over the families; the standard error is that of the mean over the
//! families. Since every count is measured on the same held-out families, its change from
//! the full count is also given with the standard error of the paired differences, which
//! is far smaller. A curve still falling at the full count says that more families would
//! help; a flat one that the error is in what the mapping's inputs can tell, not in the
//! data's extent.

use ndarray::Axis;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;

use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::data::scaling::MinMaxScaling;
use crate::error::{Result, SurrogateError};
use crate::models::booster::HyperParameters;
use crate::models::metrics::relative_l2_error;
use crate::models::model::TrainedModel;
use crate::rheology::statistics::mean_and_standard_error;
use crate::validation::family_folds::leave_one_family_out;

/// The held-out error when training on a given number of families.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LearningPoint {
    /// Profile families trained on.
    pub families: usize,
    /// Models fitted for this point (held-out families x draws).
    pub fits: usize,
    /// Mean over the held-out families of each output's eq 6.6 error, as a fraction.
    pub per_output: Vec<f64>,
    /// Standard error of that mean over the held-out families, per output.
    pub standard_error: Vec<f64>,
    /// Mean over the held-out families of this count's error minus the full count's, per
    /// output (0 at the full count).
    pub change_from_full: Vec<f64>,
    /// Standard error of that mean, from the spread of the paired differences.
    pub change_standard_error: Vec<f64>,
}

/// The learning curve of one mapping.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LearningCurve {
    pub mapping: String,
    pub outputs: Vec<String>,
    /// Whether the trees learn the backbone's residual (backbone + XGBoost) or the outputs.
    pub backbone: bool,
    /// Draws of the training families per held-out family and count below the full one.
    pub draws: usize,
    /// The seed of the draws.
    pub seed: u64,
    /// One point per count, in increasing order; the last is all the other families.
    pub points: Vec<LearningPoint>,
}

impl LearningCurve {
    /// The curve at the counts `families` (each between 1 and the number of families less
    /// one; the full count is added when missing), with `draws` (1 to [`MAX_DRAWS`]) seeded
    /// draws per held-out family and count. The held-out families run in parallel on
    /// rayon's pool; the result does not depend on the number of threads.
    pub fn run(
        mapping: &Mapping,
        samples: &Samples,
        params: &HyperParameters,
        families: &[usize],
        draws: usize,
        seed: u64,
    ) -> Result<Self> {
        let (folds, counts) = plan(samples, families, draws)?;
        let full = folds.len() - 1;
        let all_families = samples.families.as_deref().unwrap_or_default();
        let draws_at = |n: usize| draws_at(n, full, draws);
        // Per held-out family, per count: the error of each output, averaged over the draws.
        let per_fold = folds
            .par_iter()
            .enumerate()
            .map(|(k, fold)| {
                let test = samples.subset(&fold.fold.test)?;
                let yardstick =
                    MinMaxScaling::fit(samples.outputs.select(Axis(0), &fold.fold.train).view())?;
                let truth = yardstick.scale(test.outputs.view())?;
                let mut others: Vec<&String> = folds
                    .iter()
                    .map(|f| &f.family)
                    .filter(|f| **f != fold.family)
                    .collect();
                others.sort();
                counts
                    .iter()
                    .map(|&n| {
                        let draws = draws_at(n);
                        let mut sum = vec![0.0; samples.output_names.len()];
                        for draw in 0..draws {
                            // One stream per (held-out family, count, draw): each below
                            // 2^16 (counts are below the families, draws at most MAX_DRAWS).
                            let mut rng = ChaCha8Rng::seed_from_u64(seed);
                            rng.set_stream(((k as u64) << 32) | ((n as u64) << 16) | draw as u64);
                            let chosen: Vec<&String> =
                                others.choose_multiple(&mut rng, n).copied().collect();
                            let rows: Vec<usize> = fold
                                .fold
                                .train
                                .iter()
                                .copied()
                                .filter(|&i| chosen.contains(&&all_families[i]))
                                .collect();
                            let model = TrainedModel::fit(mapping, &samples.subset(&rows)?, params)
                                .map_err(|e| {
                                    SurrogateError::InvalidArgument(format!(
                                        "holding out `{}` and training on {n} families: {e}",
                                        fold.family
                                    ))
                                })?;
                            let predicted = yardstick
                                .scale(model.predict_features(test.features.view())?.view())?;
                            let e = relative_l2_error(truth.view(), predicted.view())?;
                            sum.iter_mut().zip(&e).for_each(|(s, e)| *s += e);
                        }
                        Ok(sum.into_iter().map(|s| s / draws as f64).collect())
                    })
                    .collect::<Result<Vec<Vec<f64>>>>()
            })
            .collect::<Result<Vec<_>>>()?;
        let last = counts.len() - 1;
        let points = counts
            .iter()
            .enumerate()
            .map(|(c, &n)| {
                let over_folds = |value: &dyn Fn(&Vec<Vec<f64>>, usize) -> f64| {
                    (0..samples.output_names.len())
                        .map(|j| {
                            let values: Vec<f64> = per_fold.iter().map(|f| value(f, j)).collect();
                            mean_and_standard_error(&values)
                        })
                        .unzip::<f64, f64, Vec<f64>, Vec<f64>>()
                };
                let (per_output, standard_error) = over_folds(&|f, j| f[c][j]);
                let (change_from_full, change_standard_error) =
                    over_folds(&|f, j| f[c][j] - f[last][j]);
                LearningPoint {
                    families: n,
                    fits: folds.len() * draws_at(n),
                    per_output,
                    standard_error,
                    change_from_full,
                    change_standard_error,
                }
            })
            .collect();
        Ok(LearningCurve {
            mapping: mapping.name.to_owned(),
            outputs: samples.output_names.clone(),
            backbone: params.backbone,
            draws,
            seed,
            points,
        })
    }
}

/// What a learning curve costs: the models it fits and their estimated wall time here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveCost {
    pub fits: usize,
    /// Seconds of one fit on the most rows any fit has (all the other families of a fold),
    /// as timed here.
    pub seconds_per_fit: f64,
    /// Fits running at once (rayon's threads, at most one per held-out family).
    pub parallel: usize,
}

impl CurveCost {
    /// The curve of [`LearningCurve::run`] with the same arguments, checked as it checks
    /// them, and timed by one fit on the most rows any of its fits has: an estimate at most.
    pub fn of(
        mapping: &Mapping,
        samples: &Samples,
        params: &HyperParameters,
        families: &[usize],
        draws: usize,
    ) -> Result<Self> {
        let (folds, counts) = plan(samples, families, draws)?;
        let full = folds.len() - 1;
        let fits = folds.len()
            * counts
                .iter()
                .map(|&n| draws_at(n, full, draws))
                .sum::<usize>();
        let largest = folds
            .iter()
            .max_by_key(|f| f.fold.train.len())
            .expect("a family cross-validation has at least two folds");
        let started = std::time::Instant::now();
        TrainedModel::fit(mapping, &samples.subset(&largest.fold.train)?, params)?;
        Ok(CurveCost {
            fits,
            seconds_per_fit: started.elapsed().as_secs_f64(),
            parallel: rayon::current_num_threads().clamp(1, folds.len()),
        })
    }

    /// Estimated wall seconds at most.
    pub fn seconds(&self) -> f64 {
        self.fits as f64 * self.seconds_per_fit / self.parallel as f64
    }

    /// The rule of [`schema::work_cost`]: an error for a curve that cannot finish, the
    /// warning of a day-long one.
    pub fn check(&self) -> Result<Option<String>> {
        schema::work_cost::check(
            "learning curve",
            self.seconds(),
            &self.describe(),
            "take fewer draws per count, or fewer counts of families",
        )
        .map_err(SurrogateError::InvalidArgument)
    }

    /// `N fits of at most S s each, P at a time`.
    pub fn describe(&self) -> String {
        format!(
            "{} fits of at most {:.2} s each, {} at a time",
            self.fits, self.seconds_per_fit, self.parallel
        )
    }
}

/// The folds and the counts (with the full one) of a curve, or the error for a count or a
/// number of draws outside their ranges.
fn plan(
    samples: &Samples,
    families: &[usize],
    draws: usize,
) -> Result<(Vec<crate::validation::family_folds::FamilyFold>, Vec<usize>)> {
    let folds = leave_one_family_out(samples)?;
    let counts = counts_with_full(families, folds.len() - 1)?;
    if !(1..=MAX_DRAWS).contains(&draws) {
        return Err(SurrogateError::InvalidArgument(format!(
            "a learning curve takes 1 to {MAX_DRAWS} draws of training families per count, \
             not {draws}"
        )));
    }
    Ok((folds, counts))
}

/// Draws at a count of `n` of the `full` other families: all of them can be chosen one
/// way only.
fn draws_at(n: usize, full: usize, draws: usize) -> usize {
    if n == full {
        1
    } else {
        draws
    }
}

/// Most draws per held-out family and count (their index has 16 bits of the random
/// stream's number).
pub const MAX_DRAWS: usize = 1 << 12;

/// `families` sorted and deduplicated, with `full` appended when missing; an error for a
/// count outside 1..=full.
fn counts_with_full(families: &[usize], full: usize) -> Result<Vec<usize>> {
    if let Some(&bad) = families.iter().find(|&&n| n == 0 || n > full) {
        return Err(SurrogateError::InvalidArgument(format!(
            "cannot train on {bad} profile families: with one held out there are {full} to \
             train on, so a count must be between 1 and {full}"
        )));
    }
    let mut counts = families.to_vec();
    counts.push(full);
    counts.sort_unstable();
    counts.dedup();
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::mapping::MAPPINGS;
    use ndarray::Array2;

    /// Eight families of the `mu` mapping's columns, family `k` covering J in
    /// [0.1 k, 0.1 (k + 1)] with `mu = 0.3 + J` (phi_loc and phi constant): one smooth law,
    /// which a model of few families must extrapolate to a held-out family and a model of
    /// all the others only interpolates (for all but the two end families).
    fn banded_families() -> Samples {
        let (families, rows_per) = (8, 20);
        let n = families * rows_per;
        let mut features = Array2::zeros((n, 3));
        let mut outputs = Array2::zeros((n, 1));
        let (mut names, mut groups) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for i in 0..n {
            let (k, r) = (i / rows_per, i % rows_per);
            let j = 0.1 * (k as f64 + (r as f64 + 0.5) / rows_per as f64);
            features[[i, 0]] = j;
            features[[i, 1]] = 0.55;
            features[[i, 2]] = 0.55;
            outputs[[i, 0]] = 0.3 + j;
            names.push(format!("family {k}"));
            // Two simulations per family, as the training domain needs at least two.
            groups.push(format!("family {k} run {}", r % 2));
        }
        Samples {
            source_name: "banded".to_owned(),
            source_fingerprint: schema::Fingerprint::of(b"banded"),
            feature_names: MAPPINGS[0].features.iter().map(|s| s.to_string()).collect(),
            output_names: vec!["mu".to_owned()],
            features,
            outputs,
            groups,
            families: Some(names),
            data_rows: (1..=n).collect(),
            skipped_rows: 0,
        }
    }

    fn params() -> HyperParameters {
        HyperParameters {
            n_estimators: 50,
            max_depth: 2,
            learning_rate: 0.3,
            ..HyperParameters::default()
        }
    }

    #[test]
    fn the_error_falls_as_the_families_cover_the_held_out_one() {
        let samples = banded_families();
        let curve = LearningCurve::run(&MAPPINGS[0], &samples, &params(), &[1, 3], 4, 7).unwrap();
        let counts: Vec<usize> = curve.points.iter().map(|p| p.families).collect();
        assert_eq!(counts, [1, 3, 7]);
        assert_eq!(curve.points[0].fits, 8 * 4);
        assert_eq!(curve.points[2].fits, 8);
        let e: Vec<f64> = curve.points.iter().map(|p| p.per_output[0]).collect();
        // One random family leaves most held-out bands far outside the training J, where the
        // trees are flat; all seven cover every band but the ends.
        assert!(e[0] > 2.0 * e[2], "{e:?}");
        assert!(e[1] > e[2], "{e:?}");
        assert!(curve.points.iter().all(|p| p.standard_error[0] > 0.0));
        // The paired change from the full count: the difference of the means, zero at the
        // full count itself.
        let p = &curve.points[0];
        assert!((p.change_from_full[0] - (e[0] - e[2])).abs() < 1e-12);
        assert_eq!(curve.points[2].change_from_full[0], 0.0);
    }

    #[test]
    fn the_curve_does_not_depend_on_the_thread_count() {
        let samples = banded_families();
        let on = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| LearningCurve::run(&MAPPINGS[0], &samples, &params(), &[2], 2, 9))
                .unwrap()
        };
        assert_eq!(on(1), on(2));
    }

    #[test]
    fn the_draws_are_seeded() {
        let samples = banded_families();
        let run = |seed| LearningCurve::run(&MAPPINGS[0], &samples, &params(), &[2], 3, seed);
        assert_eq!(run(3).unwrap(), run(3).unwrap());
        assert_ne!(run(3).unwrap().points[0], run(4).unwrap().points[0]);
    }

    #[test]
    fn a_count_beyond_the_other_families_is_an_error() {
        let samples = banded_families();
        for bad in [0, 8] {
            let e = LearningCurve::run(&MAPPINGS[0], &samples, &params(), &[bad], 2, 1)
                .unwrap_err()
                .to_string();
            assert!(e.contains("between 1 and 7"), "{e}");
        }
        for draws in [0, MAX_DRAWS + 1] {
            let e =
                LearningCurve::run(&MAPPINGS[0], &samples, &params(), &[2], draws, 1).unwrap_err();
            assert!(e.to_string().contains("1 to 4096 draws"), "{e}");
        }
    }

    #[test]
    fn the_cost_counts_every_fit_and_refuses_a_curve_that_cannot_finish() {
        let samples = banded_families();
        let cost = CurveCost::of(&MAPPINGS[0], &samples, &params(), &[1, 3], 4).unwrap();
        // 8 held-out families x (4 draws at 1 and at 3 families, 1 at all 7).
        assert_eq!(cost.fits, 8 * (4 + 4 + 1));
        assert!(
            cost.seconds_per_fit > 0.0 && cost.seconds_per_fit < 60.0,
            "{cost:?}"
        );
        assert_eq!(cost.check().unwrap(), None);
        let e = CurveCost::of(&MAPPINGS[0], &samples, &params(), &[2], MAX_DRAWS + 1).unwrap_err();
        assert!(e.to_string().contains("1 to 4096 draws"), "{e}");
        let long = |seconds_per_fit| CurveCost {
            seconds_per_fit,
            ..cost
        };
        // 72 fits, 1 or 2 at a time: 2 days, then 2 years.
        let day = 2.0 * 86_400.0 * cost.parallel as f64 / 72.0;
        let warning = long(day).check().unwrap().unwrap();
        assert!(
            warning.contains("72 fits") && warning.contains("2.0 days"),
            "{warning}"
        );
        let e = long(365.0 * day).check().unwrap_err().to_string();
        assert!(
            e.contains("cannot finish") && e.contains("fewer draws"),
            "{e}"
        );
    }
}
