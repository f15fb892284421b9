//! Training, prediction, persistence and timing on synthetic data with known relations.

mod common;

use std::time::Instant;

use common::{scratch_dir, synthetic_dataset};
use ndarray::{Array2, Axis};
use surrogate::{
    relative_l2_error, HyperParameters, Mapping, MultiStrategy, Samples, TrainedModel, MAPPINGS,
};

/// Rows of the scenes named in `held_out` (test) and of all others (train).
fn split_by_scene(samples: &Samples, held_out: &[&str]) -> (Samples, Samples) {
    let (test, train): (Vec<usize>, Vec<usize>) =
        (0..samples.n_rows()).partition(|&row| held_out.contains(&samples.groups[row].as_str()));
    (
        samples.subset(&train).unwrap(),
        samples.subset(&test).unwrap(),
    )
}

/// Relative L2 error of always predicting the training mean, on `test` scaled like `model`.
fn constant_predictor_error(model: &TrainedModel, train: &Samples, test: &Samples) -> Vec<f64> {
    let scaling = &model.meta().scaling;
    let mean = scaling
        .scale(train.outputs.view())
        .unwrap()
        .mean_axis(Axis(0))
        .unwrap();
    let truth = scaling.scale(test.outputs.view()).unwrap();
    let constant = Array2::from_shape_fn(truth.dim(), |(_, j)| mean[j]);
    relative_l2_error(truth.view(), constant.view()).unwrap()
}

#[test]
fn learns_a_smooth_function_on_held_out_simulations() {
    let data = synthetic_dataset(16, 60, 1);
    let mapping = Mapping::by_name("mu").unwrap();
    let (train, test) = split_by_scene(
        &Samples::from_dataset(&data, mapping).unwrap(),
        &["s2", "s7", "s9", "s12"],
    );
    let model = TrainedModel::fit(mapping, &train, &HyperParameters::default()).unwrap();
    let error = model.evaluate(&test).unwrap()[0];
    let constant = constant_predictor_error(&model, &train, &test)[0];
    println!(
        "mu on held-out simulations: relative L2 error {:.4}, constant predictor {constant:.4}",
        error
    );
    assert!(error < 0.05, "relative L2 error {error}");
    assert!(
        error < constant / 5.0,
        "model {error} vs constant predictor {constant}"
    );
}

#[test]
fn multi_output_model_predicts_each_output_in_its_place() {
    let data = synthetic_dataset(16, 60, 2);
    let mapping = Mapping::by_name("theta").unwrap();
    let (train, test) = split_by_scene(
        &Samples::from_dataset(&data, mapping).unwrap(),
        &["s1", "s6", "s11", "s12"],
    );
    for strategy in [
        MultiStrategy::OneOutputPerTree,
        MultiStrategy::MultiOutputTree,
    ] {
        // Vector-leaf trees (multi_output_tree) need shallower trees on this smooth data.
        let params = HyperParameters {
            multi_strategy: strategy,
            max_depth: 3,
            ..HyperParameters::default()
        };
        let model = TrainedModel::fit(mapping, &train, &params).unwrap();
        let predicted = model.predict_features(test.features.view()).unwrap();
        for (j, name) in mapping.outputs.iter().enumerate() {
            let truth = test.outputs.column(j);
            let other = test.outputs.column(1 - j);
            let mean_abs = |a: ndarray::ArrayView1<f64>| {
                (&a - &predicted.column(j)).mapv(f64::abs).mean().unwrap()
            };
            let (own, swapped) = (mean_abs(truth), mean_abs(other));
            println!(
                "{strategy:?} {name}: mean |error| {own:.5}, against the other output {swapped:.5}"
            );
            assert!(own < 0.01, "{strategy:?}: {name} mean absolute error {own}");
            assert!(
                swapped > 10.0 * own,
                "{strategy:?}: {name} looks swapped ({own} vs {swapped})"
            );
        }
        let errors = model.evaluate(&test).unwrap();
        println!("{strategy:?}: relative L2 errors {errors:?}");
        assert!(
            errors.iter().all(|&e| e < 0.05),
            "{strategy:?}: relative L2 errors {errors:?}"
        );
    }
}

#[test]
fn json_round_trip_predicts_bitwise_identically() {
    let data = synthetic_dataset(8, 20, 3);
    for mapping in &MAPPINGS {
        let model = TrainedModel::train(mapping, &data, &HyperParameters::default()).unwrap();
        let dir = scratch_dir(&format!("round_trip_{}", mapping.name));
        model.save(&dir).unwrap();
        assert!(dir.join(format!("{}.json", mapping.name)).is_file());
        let loaded = TrainedModel::load(&dir, mapping.name).unwrap();
        assert_eq!(loaded.meta(), model.meta());
        let before = model.predict(&data).unwrap();
        let after = loaded.predict(&data).unwrap();
        let same_bits = before
            .iter()
            .zip(after.iter())
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(
            same_bits,
            "{}: predictions changed after save + load",
            mapping.name
        );
        assert_eq!(
            loaded.feature_importance().unwrap(),
            model.feature_importance().unwrap()
        );
    }
}

#[test]
fn sidecar_records_how_the_model_was_made() {
    let data = synthetic_dataset(4, 10, 4);
    let params = HyperParameters {
        n_estimators: 7,
        ..HyperParameters::default()
    };
    let model = TrainedModel::train(Mapping::by_name("dv").unwrap(), &data, &params).unwrap();
    let meta = model.meta();
    assert_eq!(meta.features, ["J", "Delta_v", "phi"]);
    assert_eq!(meta.outputs, ["phi_loc", "mu"]);
    assert_eq!(meta.hyper_parameters, params);
    assert_eq!(meta.training_data.rows, 40);
    assert_eq!(
        meta.training_data.fnv1a_64,
        format!("{:016x}", data.fingerprint())
    );
    assert_eq!(meta.xgboost_version, "3.2.0");
    let mu = data.column("mu").unwrap();
    let (lo, hi) = mu
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    assert_eq!(
        (meta.scaling.ranges[1].min, meta.scaling.ranges[1].max),
        (lo, hi)
    );
}

#[test]
fn gain_importance_ranks_the_dominant_feature_first() {
    // mu varies mostly with J; phi_loc - phi and phi move it far less.
    let data = synthetic_dataset(12, 25, 5);
    let model = TrainedModel::train(
        Mapping::by_name("mu").unwrap(),
        &data,
        &HyperParameters::default(),
    )
    .unwrap();
    let importance = model.feature_importance().unwrap();
    println!("gain importance: {importance:?}");
    assert_eq!(
        importance
            .iter()
            .map(|(name, _)| name.as_str())
            .collect::<Vec<_>>(),
        ["J", "phi_loc", "phi"]
    );
    assert!(
        importance[0].1 > importance[1].1 && importance[0].1 > importance[2].1,
        "{importance:?}"
    );
}

#[test]
fn training_three_mappings_on_300_rows_timing() {
    let data = synthetic_dataset(12, 25, 6);
    let params = HyperParameters::default();
    let started = Instant::now();
    let models: Vec<TrainedModel> = MAPPINGS
        .iter()
        .map(|mapping| TrainedModel::train(mapping, &data, &params).unwrap())
        .collect();
    let training = started.elapsed();
    let started = Instant::now();
    for model in &models {
        model.predict(&data).unwrap();
    }
    let prediction = started.elapsed();
    println!(
        "trained 3 mappings on {} rows ({} rounds, nthread {}) in {:.3} s; predicted in {:.4} s",
        data.n_rows(),
        params.n_estimators,
        params.nthread,
        training.as_secs_f64(),
        prediction.as_secs_f64()
    );
}
