//! Training, prediction, persistence and timing on synthetic data with known relations.

mod common;

use std::time::Instant;

use common::{scratch_dir, synthetic_dataset};
use ndarray::{Array2, Axis};
use surrogate::{
    relative_l2_error, HyperParameters, Mapping, MultiStrategy, Predictor, Samples, SurrogateError,
    TrainedModel, MAPPINGS,
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

/// One row per split node of the saved model of `mapping` in `dir`: the first row of `data`
/// with the split's feature set exactly to its threshold, where `<` and `<=` part ways.
fn rows_on_split_thresholds(
    dir: &std::path::Path,
    mapping: &Mapping,
    data: &surrogate::Dataset,
) -> surrogate::Dataset {
    let path = dir.join(format!("{}.json", mapping.name));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    // The mapping's inputs as the model reads them (derived ones, `d_ext`, included).
    let base: Vec<f64> = Samples::from_dataset(data, mapping)
        .unwrap()
        .features
        .row(0)
        .to_vec();
    let mut csv = mapping.features.join(",") + "\n";
    let trees = json["learner"]["gradient_booster"]["model"]["trees"]
        .as_array()
        .unwrap();
    for tree in trees {
        let numbers = |key: &str| -> Vec<f64> {
            tree[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        };
        let (left, feature, threshold) = (
            numbers("left_children"),
            numbers("split_indices"),
            numbers("split_conditions"),
        );
        for node in (0..left.len()).filter(|&n| left[n] >= 0.0) {
            let mut row = base.clone();
            row[feature[node] as usize] = threshold[node];
            let cells: Vec<String> = row.iter().map(f64::to_string).collect();
            csv += &(cells.join(",") + "\n");
        }
    }
    surrogate::Dataset::from_csv_bytes(csv.as_bytes(), "thresholds").unwrap()
}

#[test]
fn predictor_reproduces_the_library_without_it() {
    // Training rows and unseen ones, including values beyond the training range.
    let data = synthetic_dataset(8, 30, 5);
    let unseen = synthetic_dataset(3, 40, 6);
    let deep = HyperParameters::default();
    let shallow = HyperParameters {
        n_estimators: 300,
        max_depth: 2,
        learning_rate: 0.05,
        min_child_weight: 5.0,
        ..HyperParameters::default()
    };
    for mapping in &MAPPINGS {
        for params in [&deep, &shallow] {
            let model = TrainedModel::train(mapping, &data, params).unwrap();
            let dir = scratch_dir(&format!("predictor_{}_{}", mapping.name, params.max_depth));
            model.save(&dir).unwrap();
            let predictor = Predictor::load(&dir, mapping.name).unwrap();
            assert_eq!(predictor.meta(), model.meta());
            let on_thresholds = rows_on_split_thresholds(&dir, mapping, &data);
            for table in [&data, &unseen, &on_thresholds] {
                let library = model.predict(table).unwrap();
                let own = predictor.predict(table).unwrap();
                assert_eq!(library.dim(), own.dim());
                // Both sum f32 leaves; the order of the sums may differ in the last bit.
                for (j, range) in model.meta().scaling.ranges.iter().enumerate() {
                    let tolerance = 1e-6 * (range.max - range.min);
                    let worst = library
                        .column(j)
                        .iter()
                        .zip(own.column(j))
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    assert!(
                        worst <= tolerance,
                        "{} depth {} output {j}: differs by {worst}",
                        mapping.name,
                        params.max_depth
                    );
                }
            }
        }
    }
}

#[test]
fn predictor_refuses_vector_leaves() {
    let data = synthetic_dataset(4, 20, 7);
    let params = HyperParameters {
        multi_strategy: MultiStrategy::MultiOutputTree,
        n_estimators: 5,
        ..HyperParameters::default()
    };
    let mapping = Mapping::by_name("theta").unwrap();
    let dir = scratch_dir("predictor_vector_leaves");
    TrainedModel::train(mapping, &data, &params)
        .unwrap()
        .save(&dir)
        .unwrap();
    let error = Predictor::load(&dir, "theta").unwrap_err();
    assert!(matches!(error, SurrogateError::ModelFormat(_)), "{error:?}");
    assert!(error.to_string().contains("multi_output_tree"), "{error}");
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
    assert_eq!(meta.training_data.fnv1a_64, data.fingerprint());
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
