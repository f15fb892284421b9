//! Bad input gives the right error variant with a message that says what to fix.

mod common;

use common::{scratch_dir, synthetic_csv, synthetic_dataset};
use surrogate::{
    evaluate_baseline, Baseline, Dataset, HyperParameters, Mapping, Samples, SurrogateError,
    TrainedModel,
};

/// `synthetic_csv` with the cell of `column` in data row `row` (from 1) replaced by `text`.
fn with_cell(column: &str, row: usize, text: &str) -> String {
    let csv = synthetic_csv(2, 10, 7);
    let mut lines: Vec<String> = csv.lines().map(str::to_owned).collect();
    let index = lines[0].split(',').position(|name| name == column).unwrap();
    let mut cells: Vec<&str> = lines[row].split(',').collect();
    cells[index] = text;
    lines[row] = cells.join(",");
    lines.join("\n") + "\n"
}

#[test]
fn missing_column_is_named_with_the_available_ones() {
    let csv = synthetic_csv(2, 5, 1).replace("Theta,", "Theta_typo,");
    let data = Dataset::from_csv_bytes(csv.as_bytes(), "no_theta.csv").unwrap();
    let error = Samples::from_dataset(&data, Mapping::by_name("theta").unwrap()).unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(&error, SurrogateError::MissingColumn { name, .. } if name == "Theta"),
        "{error:?}"
    );
    assert!(
        message.contains("`Theta`")
            && message.contains("Theta_typo")
            && message.contains("no_theta.csv"),
        "{message}"
    );
}

#[test]
fn nan_names_its_data_row_and_column() {
    let data = Dataset::from_csv_bytes(with_cell("J", 7, "nan").as_bytes(), "bad.csv").unwrap();
    let error = Samples::from_dataset(&data, Mapping::by_name("mu").unwrap()).unwrap_err();
    assert!(
        matches!(&error, SurrogateError::NonFinite { row: 7, column, .. } if column == "J"),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("data row 7, column `J`"),
        "{error}"
    );
}

#[test]
fn infinity_and_text_are_refused_too() {
    let data = Dataset::from_csv_bytes(with_cell("mu", 3, "inf").as_bytes(), "bad.csv").unwrap();
    let error = TrainedModel::train(
        Mapping::by_name("mu").unwrap(),
        &data,
        &HyperParameters::default(),
    )
    .unwrap_err();
    assert!(
        matches!(&error, SurrogateError::NonFinite { row: 3, column, .. } if column == "mu"),
        "{error:?}"
    );

    let data = Dataset::from_csv_bytes(with_cell("phi", 4, "0.5x").as_bytes(), "bad.csv").unwrap();
    let error = Samples::from_dataset(&data, Mapping::by_name("dv").unwrap()).unwrap_err();
    assert!(
        matches!(&error, SurrogateError::NotANumber { row: 4, .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("`0.5x`"), "{error}");
}

#[test]
fn empty_cells_skip_the_row_only_for_the_mappings_that_read_them() {
    let csv = with_cell("Theta", 3, "");
    let csv = {
        let mut lines: Vec<String> = csv.lines().map(str::to_owned).collect();
        let index = lines[0].split(',').position(|name| name == "mu").unwrap();
        let mut cells: Vec<&str> = lines[5].split(',').collect();
        cells[index] = "";
        lines[5] = cells.join(",");
        lines.join("\n") + "\n"
    };
    let data = Dataset::from_csv_bytes(csv.as_bytes(), "holes.csv").unwrap();
    for (name, skipped) in [("mu", vec![5]), ("theta", vec![3, 5]), ("dv", vec![5])] {
        let samples = Samples::from_dataset(&data, Mapping::by_name(name).unwrap()).unwrap();
        assert_eq!(samples.skipped_rows, skipped.len(), "{name}");
        assert_eq!(samples.n_rows(), data.n_rows() - skipped.len(), "{name}");
        assert!(
            skipped.iter().all(|row| !samples.data_rows.contains(row)),
            "{name}: {:?}",
            samples.data_rows
        );
        let model = TrainedModel::fit(
            Mapping::by_name(name).unwrap(),
            &samples,
            &HyperParameters::default(),
        )
        .unwrap();
        assert_eq!(model.meta().training_data.skipped_rows, skipped.len());
    }
    // Predicting needs every feature: the empty cell is named.
    let error = data.matrix(&["J", "Theta"]).unwrap_err();
    assert!(
        matches!(&error, SurrogateError::EmptyCell { row: 3, column, .. } if column == "Theta"),
        "{error:?}"
    );
}

#[test]
fn a_mapping_left_without_rows_by_empty_cells_is_an_empty_dataset() {
    let csv = "scene_id,J,phi_loc,phi,mu\ns1,0.1,0.5,0.5,\ns2,,0.5,0.5,0.3\n";
    let data = Dataset::from_csv_bytes(csv.as_bytes(), "holes.csv").unwrap();
    let error = Samples::from_dataset(&data, Mapping::by_name("mu").unwrap()).unwrap_err();
    assert!(
        matches!(error, SurrogateError::EmptyDataset { .. }),
        "{error:?}"
    );
    assert!(
        error
            .to_string()
            .contains("holes.csv (every row has an empty cell"),
        "{error}"
    );
}

#[test]
fn empty_dataset_is_refused() {
    let header_only = synthetic_csv(1, 1, 1).lines().next().unwrap().to_owned() + "\n";
    for csv in [header_only.as_str(), ""] {
        let error = Dataset::from_csv_bytes(csv.as_bytes(), "empty.csv").unwrap_err();
        assert!(
            matches!(error, SurrogateError::EmptyDataset { .. }),
            "{error:?}"
        );
        assert!(
            error.to_string().contains("empty.csv holds no data rows"),
            "{error}"
        );
    }
}

#[test]
fn missing_file_names_its_path() {
    let error = Dataset::read_csv("/nonexistent/dataset.csv").unwrap_err();
    assert!(matches!(error, SurrogateError::Io { .. }), "{error:?}");
    assert!(
        error.to_string().contains("/nonexistent/dataset.csv"),
        "{error}"
    );
}

#[test]
fn model_whose_sidecar_disagrees_is_refused_on_load() {
    let data = synthetic_dataset(2, 10, 2);
    let dir = scratch_dir("tampered_sidecar");
    TrainedModel::train(
        Mapping::by_name("mu").unwrap(),
        &data,
        &HyperParameters::default(),
    )
    .unwrap()
    .save(&dir)
    .unwrap();
    let meta_path = dir.join("mu.meta.json");
    let meta = std::fs::read_to_string(&meta_path).unwrap();
    std::fs::write(&meta_path, meta.replacen("\"phi_loc\"", "\"Theta\"", 1)).unwrap();
    let error = TrainedModel::load(&dir, "mu").unwrap_err();
    assert!(
        matches!(error, SurrogateError::FeatureMismatch { .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("Theta"), "{error}");
}

/// A scratch directory `dir_name` with default models of `mappings` trained and saved.
fn saved_models(dir_name: &str, mappings: &[&str]) -> std::path::PathBuf {
    let data = synthetic_dataset(2, 10, 3);
    let dir = scratch_dir(dir_name);
    for &name in mappings {
        TrainedModel::train(
            Mapping::by_name(name).unwrap(),
            &data,
            &HyperParameters::default(),
        )
        .unwrap()
        .save(&dir)
        .unwrap();
    }
    dir
}

#[test]
fn model_whose_booster_disagrees_is_refused_on_load() {
    let dir = saved_models("swapped_booster", &["mu", "theta"]);
    // The two-output booster of `theta` under the one-output sidecar of `mu`.
    std::fs::copy(dir.join("theta.json"), dir.join("mu.json")).unwrap();
    let error = TrainedModel::load(&dir, "mu").unwrap_err();
    assert!(
        matches!(error, SurrogateError::FeatureMismatch { .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("2 outputs"), "{error}");
}

#[test]
fn trees_of_another_mapping_with_the_same_shape_are_refused_by_feature_name() {
    let dir = saved_models("dv_as_theta", &["theta", "dv"]);
    // dv's trees (J, Delta_v, phi) -> (phi_loc, mu) have theta's shape exactly.
    std::fs::copy(dir.join("dv.json"), dir.join("theta.json")).unwrap();
    let refusals = [
        TrainedModel::load(&dir, "theta").unwrap_err(),
        surrogate::Predictor::load(&dir, "theta").unwrap_err(),
    ];
    for error in refusals {
        assert!(
            matches!(error, SurrogateError::FeatureMismatch { .. }),
            "{error:?}"
        );
        assert!(
            error
                .to_string()
                .contains("trained on features [J, Delta_v, phi]"),
            "{error}"
        );
    }
    assert!(TrainedModel::load(&dir, "dv").is_ok());
}

#[test]
fn input_lacking_a_model_feature_is_refused_on_predict() {
    let data = synthetic_dataset(2, 10, 4);
    let dir = scratch_dir("predict_mismatch");
    TrainedModel::train(
        Mapping::by_name("theta").unwrap(),
        &data,
        &HyperParameters::default(),
    )
    .unwrap()
    .save(&dir)
    .unwrap();
    let model = TrainedModel::load(&dir, "theta").unwrap();
    let csv = synthetic_csv(1, 5, 5).replace("Theta,", "Temperature,");
    let input = Dataset::from_csv_bytes(csv.as_bytes(), "new.csv").unwrap();
    let error = model.predict(&input).unwrap_err();
    assert!(
        matches!(error, SurrogateError::FeatureMismatch { .. }),
        "{error:?}"
    );
    let message = error.to_string();
    assert!(
        message.contains("new.csv lacks column(s) Theta") && message.contains("Temperature"),
        "{message}"
    );
}

#[test]
fn unknown_mapping_lists_the_known_ones() {
    let error = Mapping::by_name("viscosity").unwrap_err();
    assert!(
        matches!(&error, SurrogateError::UnknownMapping { name, .. } if name == "viscosity"),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("known mappings: mu, theta, dv"),
        "{error}"
    );
    let error = TrainedModel::load(&scratch_dir("unknown_mapping"), "viscosity").unwrap_err();
    assert!(
        matches!(error, SurrogateError::UnknownMapping { .. }),
        "{error:?}"
    );
}

#[test]
fn log_baseline_refuses_a_non_positive_feature_naming_its_row() {
    let data = Dataset::from_csv_bytes(with_cell("J", 5, "0").as_bytes(), "zero.csv").unwrap();
    let samples = Samples::from_dataset(&data, Mapping::by_name("mu").unwrap()).unwrap();
    let error = evaluate_baseline(Baseline::LogLinear, &samples, &samples).unwrap_err();
    assert!(
        matches!(&error, SurrogateError::NonPositive { row: 5, column, .. } if column == "J"),
        "{error:?}"
    );
    assert!(evaluate_baseline(Baseline::Linear, &samples, &samples).is_ok());
}

#[test]
fn xgboost_refusal_carries_the_library_message() {
    let data = synthetic_dataset(2, 10, 6);
    let params = HyperParameters {
        subsample: 1.5,
        ..HyperParameters::default()
    };
    let error = TrainedModel::train(Mapping::by_name("mu").unwrap(), &data, &params).unwrap_err();
    assert!(matches!(error, SurrogateError::Xgboost(_)), "{error:?}");
    assert!(
        error.to_string().starts_with("XGBoost: ") && error.to_string().contains("subsample"),
        "{error}"
    );
}

#[test]
fn a_value_beyond_f32_names_its_line_column_and_value_in_every_reader() {
    // J of data row 3 (line 4) is finite in f64 but an infinity in f32, the models' type.
    let csv = with_cell("J", 3, "1e39");
    let data = Dataset::from_csv_bytes(csv.as_bytes(), "big.csv").unwrap();
    let expected = "big.csv: line 4 (data row 3), column `J`: 1e39 exceeds the f32 range of the \
                    models' inputs (|x| <= 3.4e38)";
    // Training, validation and cross-validation read their rows as samples.
    let error = Samples::from_dataset(&data, Mapping::by_name("mu").unwrap()).unwrap_err();
    assert_eq!(error.to_string(), expected);
    // Prediction reads the model's feature columns.
    let dir = saved_models("beyond_f32", &["mu"]);
    let model = TrainedModel::load(&dir, "mu").unwrap();
    assert_eq!(model.predict(&data).unwrap_err().to_string(), expected);
    let predictor = surrogate::Predictor::load(&dir, "mu").unwrap();
    assert_eq!(predictor.predict(&data).unwrap_err().to_string(), expected);
    // A matrix handed to the models directly is refused by its feature's name.
    let features = ndarray::array![[0.01, 0.5, 0.5], [0.01, -4e38, 0.5]];
    for error in [
        model.predict_features(features.view()).unwrap_err(),
        predictor.predict_features(features.view()).unwrap_err(),
    ] {
        assert_eq!(
            error.to_string(),
            "prediction input: row 2, column `phi_loc`: -4e38 exceeds the f32 range of the \
             models' inputs (|x| <= 3.4e38)"
        );
    }
}

#[test]
fn a_model_file_with_another_output_count_says_so_before_its_base_score() {
    let dir = saved_models("output_count", &["theta"]);
    let path = dir.join("theta.json");
    let json = std::fs::read_to_string(&path).unwrap();
    assert!(json.contains(r#""num_target":"2""#), "{json:.300}");
    std::fs::write(
        &path,
        json.replace(r#""num_target":"2""#, r#""num_target":"3""#),
    )
    .unwrap();
    let refusals = [
        TrainedModel::load(&dir, "theta").unwrap_err(),
        surrogate::Predictor::load(&dir, "theta").unwrap_err(),
    ];
    for error in refusals {
        let message = error.to_string();
        assert!(
            message.contains(
                "theta.json has 3 outputs (learner_model_param.num_target) where \
                              mapping `theta` has 2 (phi_loc, mu)"
            ) && !message.contains("base_score"),
            "{message}"
        );
    }
}

/// The refusal of every loader of the model in `dir` whose trees file holds `bytes`.
fn load_errors(dir: &std::path::Path, bytes: &[u8]) -> Vec<String> {
    std::fs::write(dir.join("mu.json"), bytes).unwrap();
    vec![
        TrainedModel::load(dir, "mu").unwrap_err().to_string(),
        surrogate::Predictor::load(dir, "mu")
            .unwrap_err()
            .to_string(),
    ]
}

#[test]
fn a_corrupt_tree_file_is_named_with_what_is_wrong_by_every_loader() {
    let dir = saved_models("corrupt_trees", &["mu"]);
    let good = std::fs::read(dir.join("mu.json")).unwrap();
    let model: serde_json::Value = serde_json::from_slice(&good).unwrap();
    let edited = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut m = model.clone();
        edit(&mut m);
        serde_json::to_vec(&m).unwrap()
    };
    let trees = "/learner/gradient_booster/model/trees";
    let cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        (
            "empty",
            Vec::new(),
            &["is empty, where an XGBoost JSON model belongs"],
        ),
        (
            "truncated",
            good[..good.len() / 2].to_vec(),
            &["ends in the middle of its JSON", "a truncated copy"],
        ),
        (
            "not JSON",
            b"<html>not a model</html>".to_vec(),
            &["is not JSON (expected value at line 1 column 1)"],
        ),
        (
            "trees removed",
            edited(&|m| {
                m.pointer_mut("/learner/gradient_booster/model")
                    .unwrap()
                    .as_object_mut()
                    .unwrap()
                    .remove("trees");
            }),
            &["is JSON but not an XGBoost JSON model: missing field `trees`"],
        ),
        (
            "a tree's children removed",
            edited(&|m| {
                m.pointer_mut(&format!("{trees}/3"))
                    .unwrap()
                    .as_object_mut()
                    .unwrap()
                    .remove("left_children");
            }),
            &["missing field `left_children`"],
        ),
        (
            "a whole array",
            b"[1, 2, 3]".to_vec(),
            &["is JSON but not an XGBoost JSON model"],
        ),
    ];
    for (what, bytes, expected) in cases {
        for message in load_errors(&dir, &bytes) {
            assert!(
                message.contains("mu.json")
                    && expected.iter().all(|e| message.contains(e))
                    && !message.contains("Stack trace")
                    && !message.contains("Json {"),
                "{what}: {message}"
            );
        }
    }
    // A node array cut short: each loader names the tree and the array.
    let short = edited(&|m| {
        m.pointer_mut(&format!("{trees}/2/left_children"))
            .unwrap()
            .as_array_mut()
            .unwrap()
            .pop();
    });
    for message in load_errors(&dir, &short) {
        assert!(
            message.contains("mu.json") && message.contains("tree 2") && !message.contains("[bt]"),
            "{message}"
        );
    }
    // A tree list shorter than num_trees (the XGBoost loader's own count).
    let fewer = edited(&|m| {
        m.pointer_mut(trees).unwrap().as_array_mut().unwrap().pop();
        m.pointer_mut("/learner/gradient_booster/model/tree_info")
            .unwrap()
            .as_array_mut()
            .unwrap()
            .pop();
    });
    let messages = load_errors(&dir, &fewer);
    assert!(
        messages[0].contains("gbtree_model_param.num_trees = `100`, but it holds 99 trees"),
        "{}",
        messages[0]
    );
    assert!(
        messages[1].contains("its trees number 99"),
        "{}",
        messages[1]
    );
    // The sidecar and the domain are named the same way.
    std::fs::write(dir.join("mu.json"), &good).unwrap();
    std::fs::write(dir.join("mu.meta.json"), b"").unwrap();
    let message = TrainedModel::load(&dir, "mu").unwrap_err().to_string();
    assert!(
        message.contains("mu.meta.json: is empty, where a model sidecar belongs"),
        "{message}"
    );
}

#[test]
fn both_tree_kinds_pass_the_check_before_xgboost() {
    let data = synthetic_dataset(2, 10, 5);
    for strategy in [
        surrogate::MultiStrategy::OneOutputPerTree,
        surrogate::MultiStrategy::MultiOutputTree,
    ] {
        let dir = scratch_dir(&format!("tree_kind_{strategy:?}"));
        let params = HyperParameters {
            n_estimators: 5,
            multi_strategy: strategy,
            ..HyperParameters::default()
        };
        let model =
            TrainedModel::train(Mapping::by_name("theta").unwrap(), &data, &params).unwrap();
        model.save(&dir).unwrap();
        let loaded = TrainedModel::load(&dir, "theta").unwrap();
        assert_eq!(
            loaded.predict(&data).unwrap(),
            model.predict(&data).unwrap(),
            "{strategy:?}"
        );
    }
}
