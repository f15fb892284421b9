//! The training domain: which rows a model has seen the like of.
mod common;

use ndarray::array;
use surrogate::{
    HyperParameters, Mapping, Predictor, Samples, SurrogateError, TrainedModel, TrainingDomain,
};

fn samples(csv: &str) -> Samples {
    let dataset = surrogate::Dataset::from_csv_bytes(csv.as_bytes(), "inline").unwrap();
    Samples::from_dataset(&dataset, Mapping::by_name("theta").unwrap()).unwrap()
}

/// Theta-mapping rows `(scene, J, Theta, phi)`; the outputs are filler.
fn csv(rows: &[(&str, f64, f64, f64)]) -> String {
    let mut text = String::from("scene_id,J,Theta,phi,phi_loc,mu\n");
    for (scene, j, theta, phi) in rows {
        text += &format!("{scene},{j},{theta},{phi},0.5,1.0\n");
    }
    text
}

#[test]
fn threshold_is_the_distance_between_simulations_not_between_neighbouring_bins() {
    // Three simulations with bins 0.001 apart in Theta, the simulations 0.1 apart
    // (Theta spans 0.1-0.302: linear axis; J and phi constant).
    let mut rows = Vec::new();
    for (s, scene) in ["a", "b", "c"].iter().enumerate() {
        for bin in 0..3 {
            rows.push((
                *scene,
                0.05,
                0.1 + 0.1 * s as f64 + 0.001 * bin as f64,
                0.54,
            ));
        }
    }
    let domain = TrainingDomain::fit(&samples(&csv(&rows))).unwrap();
    assert!(domain.axes.iter().all(|a| !a.log));
    // Nearest other-simulation rows lie 0.098-0.1 apart in Theta (span 0.202); the 95 %
    // quantile of the nine distances (0.098 x4, 0.099 x3, 0.1 x2) is 0.1.
    let expected = 0.1 / 0.202;
    assert!(
        (domain.threshold - expected).abs() < 1e-9 * expected,
        "threshold {} expected {expected}",
        domain.threshold
    );
}

#[test]
fn rows_beyond_the_range_or_far_from_every_simulation_are_outside() {
    // Two clusters of simulations in J (log axis: J spans 1e-3..1), none in between.
    let rows = [
        ("a", 1e-3, 0.05, 0.54),
        ("a", 1.2e-3, 0.06, 0.54),
        ("b", 1.1e-3, 0.055, 0.54),
        ("b", 1.3e-3, 0.065, 0.54),
        ("c", 0.9, 0.05, 0.54),
        ("c", 1.0, 0.06, 0.54),
        ("d", 0.95, 0.055, 0.54),
        ("d", 0.8, 0.065, 0.54),
    ];
    let domain = TrainingDomain::fit(&samples(&csv(&rows))).unwrap();
    assert!(domain.axes[0].log, "J spans 1000x: log axis");
    let checks = domain
        .check(
            array![
                [1.15e-3, 0.058, 0.54], // among the first cluster
                [0.03, 0.058, 0.54],    // in range, in the gap between the clusters
                [2.0, 0.058, 0.54],     // J beyond the range
                [1e-3, 0.058, 0.60],    // phi beyond the range
                [0.0, 0.058, 0.54],     // J = 0 on a log axis
            ]
            .view(),
        )
        .unwrap();
    let inside: Vec<bool> = checks.iter().map(|c| c.inside()).collect();
    assert_eq!(inside, [true, false, false, false, false], "{checks:?}");
    assert!(checks[1].in_range && checks[1].distance > 1.0);
    assert!(!checks[2].in_range && !checks[3].in_range);
    assert!(checks[4].distance.is_infinite());
}

#[test]
fn a_scene_level_feature_is_checked_by_range_only() {
    // Phi at two levels, 0.50 and 0.58, two simulations per level; J and Theta vary within
    // each simulation, the simulations' Theta 0.001 apart (span 0.015).
    let mut rows = Vec::new();
    let scenes = [
        ("a", 0.50, 0.0),
        ("b", 0.58, 0.001),
        ("c", 0.50, 0.002),
        ("d", 0.58, 0.003),
    ];
    for (scene, phi, offset) in scenes {
        for bin in 0..4 {
            let x = bin as f64;
            rows.push((scene, 0.01 * (1.0 + x), 0.05 + offset + 0.004 * x, phi));
        }
    }
    let domain = TrainingDomain::fit(&samples(&csv(&rows))).unwrap();
    assert_eq!(
        domain
            .axes
            .iter()
            .map(|a| a.scene_level)
            .collect::<Vec<_>>(),
        [false, false, true],
        "phi is the same in every row of a simulation, J and Theta are not"
    );
    let checks = domain
        .check(
            array![
                [0.02, 0.054, 0.54], // a local state the training rows hold, between phi levels
                [0.02, 0.054, 0.60], // phi beyond its range
                [0.02, 0.2, 0.54],   // Theta beyond its range
            ]
            .view(),
        )
        .unwrap();
    let inside: Vec<bool> = checks.iter().map(|c| c.inside()).collect();
    assert_eq!(inside, [true, false, false], "{checks:?}");
    // With phi in the distance, the first row would lie half the phi span from every
    // training row, far beyond the threshold (the other simulations' rows lie at most
    // 0.005/0.016 apart in Theta).
    assert!(
        0.5 > 2.0 * domain.threshold,
        "threshold {}",
        domain.threshold
    );
}

#[test]
fn one_simulation_has_no_domain() {
    let rows = [("a", 0.01, 0.05, 0.54), ("a", 0.02, 0.06, 0.54)];
    let err = TrainingDomain::fit(&samples(&csv(&rows))).unwrap_err();
    assert!(
        err.to_string().contains("at least two simulations"),
        "{err}"
    );
}

#[test]
fn saved_model_carries_its_domain_and_refuses_a_foreign_one() {
    let dataset = common::synthetic_dataset(8, 20, 7);
    let mapping = Mapping::by_name("theta").unwrap();
    let model = TrainedModel::train(mapping, &dataset, &HyperParameters::default()).unwrap();
    let dir = common::scratch_dir("domain_round_trip");
    model.save(&dir).unwrap();
    let predictor = Predictor::load(&dir, "theta").unwrap();
    assert_eq!(predictor.domain(), model.domain());
    // Every training row is inside its own domain.
    assert!(predictor
        .check_domain(&dataset)
        .unwrap()
        .iter()
        .all(|c| c.inside()));

    // The mu mapping's domain has 3 axes too, but a domain of 2 axes must be refused.
    let mut foreign = model.domain().clone();
    foreign.axes.pop();
    std::fs::write(
        dir.join("theta.domain.json"),
        serde_json::to_vec(&foreign).unwrap(),
    )
    .unwrap();
    match Predictor::load(&dir, "theta") {
        Err(SurrogateError::FeatureMismatch { detail, .. }) => {
            assert!(detail.contains("theta.domain.json"), "{detail}")
        }
        other => panic!("expected a feature mismatch, got {other:?}"),
    }
    std::fs::remove_file(dir.join("theta.domain.json")).unwrap();
    let err = Predictor::load(&dir, "theta").unwrap_err();
    assert!(err.to_string().contains("theta.domain.json"), "{err}");
}
