//! Linear baselines: exact on data they can represent, and beaten by the booster otherwise.

mod common;

use common::synthetic_dataset;
use ndarray::Array2;
use surrogate::{evaluate_baseline, Baseline, HyperParameters, Mapping, Samples, TrainedModel};

/// Samples with features drawn from `features` and the single output `output(features)`.
fn samples_of(features: Array2<f64>, output: impl Fn(&[f64]) -> f64) -> Samples {
    let n = features.nrows();
    let outputs =
        Array2::from_shape_fn((n, 1), |(i, _)| output(features.row(i).as_slice().unwrap()));
    Samples {
        source_name: "exact".to_owned(),
        source_fingerprint: schema::Fingerprint(0),
        feature_names: vec!["a".to_owned(), "b".to_owned()],
        output_names: vec!["y".to_owned()],
        features,
        outputs,
        groups: vec!["g".to_owned(); n],
        families: None,
        data_rows: (1..=n).collect(),
        skipped_rows: 0,
    }
}

fn grid(n: usize) -> Array2<f64> {
    Array2::from_shape_fn((n, 2), |(i, j)| {
        0.1 + ((i * (3 + 4 * j)) % 17) as f64 / 10.0
    })
}

#[test]
fn each_baseline_is_exact_on_data_linear_in_its_features() {
    let linear = samples_of(grid(40), |x| 1.0 + 2.0 * x[0] - 0.5 * x[1]);
    let fit = |baseline, samples: &Samples| {
        evaluate_baseline(baseline, samples, samples)
            .unwrap()
            .per_output[0]
    };
    assert!(fit(Baseline::Linear, &linear) < 1e-9);
    let log_linear = samples_of(grid(40), |x| 0.2 + 0.7 * x[0].ln() - 0.3 * x[1].ln());
    assert!(fit(Baseline::LogLinear, &log_linear) < 1e-9);
    assert!(fit(Baseline::Linear, &log_linear) > 1e-3);
}

#[test]
fn booster_beats_both_baselines_on_held_out_simulations() {
    let data = synthetic_dataset(12, 25, 9);
    let mapping = Mapping::by_name("theta").unwrap();
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    let (test, train): (Vec<usize>, Vec<usize>) =
        (0..samples.n_rows()).partition(|&r| ["s3", "s8"].contains(&samples.groups[r].as_str()));
    let (train, test) = (
        samples.subset(&train).unwrap(),
        samples.subset(&test).unwrap(),
    );
    let model = TrainedModel::fit(mapping, &train, &HyperParameters::default()).unwrap();
    let booster = model.evaluate(&test).unwrap();
    for baseline in [Baseline::Linear, Baseline::LogLinear] {
        let score = evaluate_baseline(baseline, &train, &test).unwrap();
        println!(
            "{baseline:?}: {:?} in {:?}; booster {booster:?}",
            score.per_output, score.training_time
        );
        assert_eq!(score.per_output.len(), 2);
        // phi_loc is linear in log10(Theta): the log baseline gets it (nearly) exactly.
        if baseline == Baseline::Linear {
            assert!(
                booster.iter().zip(&score.per_output).all(|(b, s)| b < s),
                "{booster:?} vs {:?}",
                score.per_output
            );
        }
    }
}
