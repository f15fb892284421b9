//! The physics backbone: trees on the residual of a fitted local rheology extrapolate along
//! the law, where trees alone stay flat at the edge of their training range.
use surrogate::{
    Dataset, HyperParameters, LocalRheology, Mapping, Predictor, Samples, TrainedModel,
};

const LAW: LocalRheology = LocalRheology {
    mu_prefactor: 3.6,
    mu_exponent: 0.44,
    phi_j: 0.66,
    alpha: 2.0,
};

/// Rows of the dv mapping (J, Delta_v, phi -> phi_loc, mu) following `LAW` with a small
/// Delta_v-dependent correction, for J log-spaced in [j_min, j_max], `scenes` simulations.
fn table(j_min: f64, j_max: f64, scenes: usize, bins: usize) -> String {
    let mut csv = String::from("scene_id,profile,J,Delta_v,phi,phi_loc,mu\n");
    for s in 0..scenes {
        for b in 0..bins {
            let t = (b as f64 + 0.37 * s as f64 / scenes as f64) / bins as f64;
            let j = j_min * (j_max / j_min).powf(t);
            let dv = 0.01 + 0.05 * ((3 * b + s) % 7) as f64 / 7.0;
            let mu = LAW.mu(j) * (1.0 + 0.2 * dv);
            let phi_loc = LAW.phi_loc(j) - 0.1 * dv;
            csv += &format!("s{s},p,{j},{dv},0.54,{phi_loc},{mu}\n");
        }
    }
    csv
}

fn samples(csv: &str, mapping: &Mapping) -> Samples {
    let data = Dataset::from_csv_bytes(csv.as_bytes(), "inline").unwrap();
    Samples::from_dataset(&data, mapping).unwrap()
}

#[test]
fn backbone_extrapolates_beyond_the_training_range_where_trees_alone_do_not() {
    let mapping = Mapping::by_name("dv").unwrap();
    let train = samples(&table(1e-3, 0.05, 6, 30), mapping);
    // Stronger shear than any training row: J up to 6 times the training maximum.
    let test = samples(&table(0.06, 0.3, 2, 20), mapping);
    let params = |backbone| HyperParameters {
        backbone,
        ..HyperParameters::default()
    };
    let trees = TrainedModel::fit(mapping, &train, &params(false)).unwrap();
    let backed = TrainedModel::fit(mapping, &train, &params(true)).unwrap();
    let law = backed.meta().backbone.as_ref().unwrap().law;
    assert!((law.mu_exponent - 0.44).abs() < 0.05, "{law:?}");
    let (e_trees, e_backed) = (
        trees.evaluate(&test).unwrap(),
        backed.evaluate(&test).unwrap(),
    );
    for k in 0..2 {
        assert!(
            e_backed[k] < 0.5 * e_trees[k],
            "output {k}: backbone {:?} vs trees alone {:?}",
            e_backed,
            e_trees
        );
    }
    // Inside the training range both are accurate.
    let inside = samples(&table(2e-3, 0.04, 2, 20), mapping);
    for e in backed.evaluate(&inside).unwrap() {
        assert!(e < 0.02, "in range: {e}");
    }
}

#[test]
fn saved_backbone_model_predicts_the_same_without_the_library() {
    let mapping = Mapping::by_name("theta").unwrap();
    let csv = table(1e-3, 0.05, 6, 30).replace("Delta_v", "Theta");
    let train = samples(&csv, mapping);
    let params = HyperParameters {
        backbone: true,
        ..HyperParameters::default()
    };
    let model = TrainedModel::fit(mapping, &train, &params).unwrap();
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("backbone_round_trip");
    let _ = std::fs::remove_dir_all(&dir);
    model.save(&dir).unwrap();
    let predictor = Predictor::load(&dir, "theta").unwrap();
    assert_eq!(predictor.meta(), model.meta());
    let a = model.predict_features(train.features.view()).unwrap();
    let b = predictor.predict_features(train.features.view()).unwrap();
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-5 * x.abs().max(1e-3), "{x} vs {y}");
    }
}

#[test]
fn extrapolated_predictions_stay_in_their_physical_range() {
    // Far beyond the training J, eq 6.7 with mu = A J^b (b < 1) drives phi_loc below 0: the
    // law itself leaves the physical range, so only the clip can keep the prediction in it.
    let j_far = 1e3;
    assert!(LAW.phi_loc(j_far) < 0.0, "{}", LAW.phi_loc(j_far));
    let mapping = Mapping::by_name("dv").unwrap();
    let train = samples(&table(1e-3, 0.05, 6, 30), mapping);
    let params = HyperParameters {
        backbone: true,
        ..HyperParameters::default()
    };
    let model = TrainedModel::fit(mapping, &train, &params).unwrap();
    let law = model.meta().backbone.as_ref().unwrap().law;
    assert!(law.phi_loc(j_far) < 0.0, "{law:?}");
    // Rows (J, Delta_v, phi) from the training range to far beyond it, and J = 0.
    let rows = ndarray::array![
        [1e-2, 0.03, 0.54],
        [10.0, 0.03, 0.54],
        [j_far, 0.03, 0.54],
        [0.0, 0.06, 0.54]
    ];
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("physical_range");
    let _ = std::fs::remove_dir_all(&dir);
    model.save(&dir).unwrap();
    let predictor = Predictor::load(&dir, "dv").unwrap();
    for predicted in [
        model.predict_features(rows.view()).unwrap(),
        predictor.predict_features(rows.view()).unwrap(),
    ] {
        for row in predicted.rows() {
            let (phi_loc, mu) = (row[0], row[1]);
            assert!(phi_loc > 0.0 && phi_loc < 0.74, "phi_loc {phi_loc}");
            assert!(mu >= 0.0, "mu {mu}");
        }
        // Inside the training range nothing is clipped: the law's value to within the trees.
        assert!((predicted[[0, 0]] - (LAW.phi_loc(1e-2) - 0.003)).abs() < 0.01);
    }
}
