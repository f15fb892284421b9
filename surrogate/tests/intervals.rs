//! Prediction intervals: calibrated on held-out families, they cover new rows at their level;
//! saved and read back, the tree walk gives the library's bounds; a calibration of another
//! training is refused.

mod common;

use common::{scratch_dir, synthetic_csv_with_families, Lcg};
use ndarray::Array2;
use surrogate::{
    output_standard_errors, Dataset, HyperParameters, IntervalMethod, IntervalStudy, Mapping,
    Predictor, Samples, TrainedModel, DEFAULT_LEVEL,
};

/// Half-width of the uniform noise added to mu: the spread the intervals must learn.
const NOISE: f64 = 0.05;

/// [`synthetic_csv_with_families`] with uniform noise of half-width [`NOISE`] on `mu`.
fn noisy_dataset(scenes: usize, rows: usize, seed: u64, families: usize) -> Dataset {
    let csv = synthetic_csv_with_families(scenes, rows, seed, families);
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    let mu = header.split(',').position(|c| c == "mu").unwrap();
    let mut rng = Lcg::new(seed + 100);
    let mut out = header.to_owned() + "\n";
    for line in lines {
        let mut cells: Vec<String> = line.split(',').map(str::to_owned).collect();
        let value: f64 = cells[mu].parse().unwrap();
        cells[mu] = (value + NOISE * (2.0 * rng.uniform() - 1.0)).to_string();
        out += &(cells.join(",") + "\n");
    }
    Dataset::from_csv_bytes(out.as_bytes(), "noisy").unwrap()
}

fn params() -> HyperParameters {
    HyperParameters {
        n_estimators: 100,
        max_depth: 3,
        learning_rate: 0.1,
        ..HyperParameters::default()
    }
}

/// Within `k` binomial standard errors of the level for `n` independent rows.
fn near_level(coverage: f64, n: usize, k: f64) -> bool {
    let se = (DEFAULT_LEVEL * (1.0 - DEFAULT_LEVEL) / n as f64).sqrt();
    (coverage - DEFAULT_LEVEL).abs() <= k * se
}

#[test]
fn intervals_cover_their_level_on_held_out_families_and_on_new_rows() {
    let mapping = Mapping::by_name("mu").unwrap();
    let data = noisy_dataset(24, 40, 11, 8);
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    let study = IntervalStudy::run(mapping, &samples, None, &params(), DEFAULT_LEVEL).unwrap();
    assert_eq!(study.calibration.folds, 8);
    let n = samples.n_rows();
    // The noise is independent between rows, so the held-out rows' coverage is binomial
    // about the level: 960 rows, standard error 0.0097; 4 of them allowed.
    for method in [
        IntervalMethod::ConformalQuantiles,
        IntervalMethod::ConstantConformal,
    ] {
        let m = study
            .coverage
            .methods
            .iter()
            .find(|m| m.method == method)
            .unwrap();
        let c = m.per_output[0].coverage;
        assert!(
            near_level(c, n, 4.0),
            "{method:?}: coverage {c} of {n} rows"
        );
        // The widths must reflect the noise (full width 2 NOISE), not the smooth part.
        let w = m.per_output[0].mean_width;
        assert!(
            (1.2 * NOISE..3.0 * NOISE).contains(&w),
            "{method:?}: width {w}"
        );
    }
    let model = TrainedModel::fit(mapping, &samples, &params()).unwrap();
    let trees = model.fit_quantile_trees(&samples, &params()).unwrap();
    let model = model.with_intervals(trees, study.calibration).unwrap();
    // New rows of the same flows, other noise: 400 rows, standard error 0.015.
    let fresh = noisy_dataset(10, 40, 12, 8);
    let fresh_samples = Samples::from_dataset(&fresh, mapping).unwrap();
    let intervals = model
        .predict_intervals(fresh_samples.features.view(), None, DEFAULT_LEVEL)
        .unwrap()
        .unwrap();
    let covered = intervals.covers(fresh_samples.outputs.view());
    let coverage = covered.iter().filter(|&&c| c).count() as f64 / covered.len() as f64;
    assert!(
        near_level(coverage, covered.len(), 4.0),
        "new rows: coverage {coverage}"
    );
    // A lower level gives narrower intervals inside the wider ones.
    let narrow = model
        .predict_intervals(fresh_samples.features.view(), None, 0.5)
        .unwrap()
        .unwrap();
    assert!(narrow
        .lower
        .iter()
        .zip(&intervals.lower)
        .all(|(n, w)| n >= w));
    assert!(narrow
        .upper
        .iter()
        .zip(&intervals.upper)
        .all(|(n, w)| n <= w));
}

/// [`synthetic_csv_with_families`] with Gaussian noise on `mu` of a standard error drawn per
/// row from `sigmas` (uniformly), written in `mu_se`.
fn gaussian_noise_dataset(scenes: usize, rows: usize, seed: u64, sigmas: &[f64]) -> Dataset {
    let csv = synthetic_csv_with_families(scenes, rows, seed, 8);
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    let column = |name: &str| header.split(',').position(|c| c == name).unwrap();
    let (mu, mu_se) = (column("mu"), column("mu_se"));
    let mut rng = Lcg::new(seed + 200);
    let mut out = header.to_owned() + "\n";
    for line in lines {
        let mut cells: Vec<String> = line.split(',').map(str::to_owned).collect();
        let sigma = sigmas[((rng.uniform() * sigmas.len() as f64) as usize).min(sigmas.len() - 1)];
        // Box-Muller.
        let (u1, u2) = (1.0 - rng.uniform(), rng.uniform());
        let gauss = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
        let value: f64 = cells[mu].parse().unwrap();
        cells[mu] = (value + sigma * gauss).to_string();
        cells[mu_se] = sigma.to_string();
        out += &(cells.join(",") + "\n");
    }
    Dataset::from_csv_bytes(out.as_bytes(), "gaussian noise").unwrap()
}

#[test]
fn intervals_with_the_noise_apart_cover_quiet_and_noisy_targets_alike() {
    // Calibrated on rows of two noise levels, the intervals of new rows as quiet as the
    // quieter (or as noisy as the noisier) cover them at the level; blind to the noise,
    // one width for both over-covers the quiet rows and under-covers the noisy ones.
    let mapping = Mapping::by_name("mu").unwrap();
    let (quiet, noisy) = (0.01, 0.06);
    let data = gaussian_noise_dataset(24, 40, 31, &[quiet, noisy]);
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    let se = output_standard_errors(&data, &samples).unwrap().unwrap();
    let calibrate = |noise: Option<&Array2<f64>>| {
        let study = IntervalStudy::run(
            mapping,
            &samples,
            noise.map(Array2::view),
            &params(),
            DEFAULT_LEVEL,
        )
        .unwrap();
        let model = TrainedModel::fit(mapping, &samples, &params()).unwrap();
        let trees = model.fit_quantile_trees(&samples, &params()).unwrap();
        model.with_intervals(trees, study.calibration).unwrap()
    };
    let (apart, blind) = (calibrate(Some(&se)), calibrate(None));
    let coverage = |model: &TrainedModel, sigma: f64, with_noise: bool| {
        let fresh = gaussian_noise_dataset(10, 40, 37 + (sigma * 1e3) as u64, &[sigma]);
        let fresh_samples = Samples::from_dataset(&fresh, mapping).unwrap();
        let fresh_se = output_standard_errors(&fresh, &fresh_samples)
            .unwrap()
            .unwrap();
        let intervals = model
            .predict_intervals(
                fresh_samples.features.view(),
                with_noise.then(|| fresh_se.view()),
                DEFAULT_LEVEL,
            )
            .unwrap()
            .unwrap();
        let covered = intervals.covers(fresh_samples.outputs.view());
        let n = covered.len();
        (covered.iter().filter(|&&c| c).count() as f64 / n as f64, n)
    };
    for sigma in [quiet, noisy] {
        let (c, n) = coverage(&apart, sigma, true);
        // 400 independent rows: binomial standard error 0.015; 4 of them allowed.
        assert!(near_level(c, n, 4.0), "noise apart, sigma {sigma}: {c}");
    }
    let (c_quiet, _) = coverage(&blind, quiet, false);
    let (c_noisy, _) = coverage(&blind, noisy, false);
    assert!(c_quiet > 0.97, "noise-blind, quiet rows: {c_quiet}");
    assert!(c_noisy < 0.85, "noise-blind, noisy rows: {c_noisy}");
}

#[test]
fn saved_intervals_are_read_back_and_a_stale_calibration_is_refused() {
    let mapping = Mapping::by_name("dv").unwrap();
    let data = noisy_dataset(12, 30, 21, 4);
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    let se = output_standard_errors(&data, &samples).unwrap().unwrap();
    let study =
        IntervalStudy::run(mapping, &samples, Some(se.view()), &params(), DEFAULT_LEVEL).unwrap();
    let model = TrainedModel::fit(mapping, &samples, &params()).unwrap();
    let trees = model.fit_quantile_trees(&samples, &params()).unwrap();
    let model = model.with_intervals(trees, study.calibration).unwrap();
    let dir = scratch_dir("intervals_round_trip");
    model.save(&dir).unwrap();
    let predictor = Predictor::load(&dir, "dv").unwrap();
    // The table's standard errors (`<output>_se`) are the targets' noise of both.
    let library = model
        .predict_intervals(samples.features.view(), Some(se.view()), DEFAULT_LEVEL)
        .unwrap()
        .unwrap();
    let prediction = predictor
        .predict_with_intervals(&data, DEFAULT_LEVEL)
        .unwrap();
    assert!(prediction.with_target_noise);
    let own = prediction.intervals.unwrap();
    // Both walk the same f32 leaves; the sums' order may differ in the last bit.
    for (a, b) in library
        .lower
        .iter()
        .chain(&library.upper)
        .zip(own.lower.iter().chain(&own.upper))
    {
        assert!((a - b).abs() <= 1e-6 * (1.0 + a.abs()), "{a} vs {b}");
    }
    // Retrained on other rows without intervals, into the same folder: the old calibration
    // is removed rather than left to describe another model.
    let first_two_scenes: Vec<usize> = (0..60).collect();
    let other = TrainedModel::fit(
        mapping,
        &samples.subset(&first_two_scenes).unwrap(),
        &params(),
    )
    .unwrap();
    other.save(&dir).unwrap();
    assert!(Predictor::load(&dir, "dv").unwrap().intervals().is_none());
    // Put back by hand, it is refused as the calibration of another training.
    model.save(&scratch_dir("intervals_stale_source")).unwrap();
    std::fs::copy(
        scratch_dir_file("intervals_stale_source", "dv.intervals.json"),
        dir.join("dv.intervals.json"),
    )
    .unwrap();
    for output in ["phi_loc", "mu"] {
        let name = format!("dv.quantiles_{output}.json");
        std::fs::copy(
            scratch_dir_file("intervals_stale_source", &name),
            dir.join(&name),
        )
        .unwrap();
    }
    let message = Predictor::load(&dir, "dv").unwrap_err().to_string();
    assert!(message.contains("an earlier training"), "{message}");
}

/// A file in the scratch folder `name` (without emptying it).
fn scratch_dir_file(name: &str, file: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(name)
        .join(file)
}
