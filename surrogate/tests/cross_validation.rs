//! Grouped cross-validation (by simulation and by profile family) and grid search.

mod common;

use std::collections::BTreeSet;

use common::{scratch_dir, synthetic_csv_with_families, synthetic_dataset};
use surrogate::{
    cross_validate, family_names, grid_search, grouped_k_fold, leave_one_family_out,
    leave_one_group_out, standard_grid, tuning_folds, Fold, HyperParameterGrid, HyperParameters,
    LeftOut, Mapping, Samples, SurrogateError, Tuning,
};

/// Groups of uneven sizes: g0 x 5, g1 x 1, g2 x 3, ... interleaved.
fn uneven_groups() -> Vec<String> {
    let sizes = [5, 1, 3, 4, 2, 6, 2];
    let mut groups = Vec::new();
    for round in 0..6 {
        for (g, &size) in sizes.iter().enumerate() {
            if round < size {
                groups.push(format!("g{g}"));
            }
        }
    }
    groups
}

/// Every fold keeps each group on one side, and every row is tested exactly once.
fn assert_valid_grouped_folds(groups: &[String], folds: &[Fold]) {
    let mut tested = vec![0; groups.len()];
    for (k, fold) in folds.iter().enumerate() {
        let train_groups: BTreeSet<&String> = fold.train.iter().map(|&r| &groups[r]).collect();
        let test_groups: BTreeSet<&String> = fold.test.iter().map(|&r| &groups[r]).collect();
        assert!(
            train_groups.is_disjoint(&test_groups),
            "fold {k}: groups on both sides: {:?}",
            train_groups.intersection(&test_groups).collect::<Vec<_>>()
        );
        assert_eq!(
            fold.train.len() + fold.test.len(),
            groups.len(),
            "fold {k} loses or repeats rows"
        );
        assert!(
            !fold.test.is_empty() && !fold.train.is_empty(),
            "fold {k} has an empty side"
        );
        for &row in &fold.test {
            tested[row] += 1;
        }
    }
    assert!(
        tested.iter().all(|&n| n == 1),
        "rows tested other than once: {tested:?}"
    );
}

#[test]
fn k_fold_never_splits_a_group() {
    let groups = uneven_groups();
    for k in 2..=7 {
        let folds = grouped_k_fold(&groups, k).unwrap();
        assert_eq!(folds.len(), k);
        assert_valid_grouped_folds(&groups, &folds);
    }
}

#[test]
fn k_fold_balances_rows_among_folds() {
    // Sizes 6,5,4,3,2,2,1 into 3 folds, largest first to the emptiest fold: 8, 8, 7 rows.
    let folds = grouped_k_fold(&uneven_groups(), 3).unwrap();
    let mut sizes: Vec<usize> = folds.iter().map(|f| f.test.len()).collect();
    sizes.sort_unstable();
    assert_eq!(sizes, [7, 8, 8]);
}

#[test]
fn leave_one_group_out_tests_each_simulation_alone() {
    let data = synthetic_dataset(6, 5, 1);
    let groups = data.group_keys().unwrap();
    let folds = leave_one_group_out(groups).unwrap();
    assert_eq!(folds.len(), 6);
    assert_valid_grouped_folds(groups, &folds);
    for fold in &folds {
        let test_groups: BTreeSet<&String> = fold.test.iter().map(|&r| &groups[r]).collect();
        assert_eq!(test_groups.len(), 1);
        assert_eq!(fold.test.len(), 5);
    }
}

#[test]
fn impossible_fold_counts_are_errors() {
    let groups = uneven_groups();
    for k in [0, 1, 8] {
        let error = grouped_k_fold(&groups, k).unwrap_err();
        assert!(
            matches!(error, SurrogateError::InvalidArgument(_)),
            "{error:?}"
        );
        assert!(
            error.to_string().contains("between 2 and 7 folds"),
            "{error}"
        );
    }
}

#[test]
fn cross_validation_and_grid_search_are_deterministic_and_pick_the_minimum() {
    let data = synthetic_dataset(8, 20, 2);
    let mapping = Mapping::by_name("theta").unwrap();
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    let folds = grouped_k_fold(&samples.groups, 4).unwrap();
    let grid = HyperParameterGrid {
        base: HyperParameters::default(),
        n_estimators: vec![5, 60],
        max_depth: vec![2, 4],
        learning_rate: vec![0.3],
        min_child_weight: vec![],
        backbone: vec![],
    };
    let first = grid_search(mapping, &samples, &folds, &grid).unwrap();
    let second = grid_search(mapping, &samples, &folds, &grid).unwrap();
    assert_eq!(first, second);
    assert_eq!(first.scores.len(), 4);
    let minimum = first
        .scores
        .iter()
        .map(|s| s.mean)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(first.best.mean, minimum);
    // 5 rounds of eta 0.3 leave the outputs far from converged: never the best.
    assert_eq!(first.best.params.n_estimators, 60);
    for score in &first.scores {
        println!(
            "n_estimators {} max_depth {}: per output {:?}",
            score.params.n_estimators, score.params.max_depth, score.per_output
        );
    }
    let single = cross_validate(mapping, &samples, &folds, &first.best.params).unwrap();
    assert_eq!(single, first.best);
}

#[test]
fn tuning_leaves_one_simulation_out_and_compares_with_the_defaults() {
    let data = synthetic_dataset(5, 12, 3);
    let mapping = Mapping::by_name("dv").unwrap();
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    // A grid without XGBoost's defaults: their score is computed on the same folds.
    let grid = HyperParameterGrid {
        base: HyperParameters::default(),
        n_estimators: vec![20, 50],
        max_depth: vec![2],
        learning_rate: vec![0.1],
        min_child_weight: vec![],
        backbone: vec![],
    };
    let tuning = Tuning::run(mapping, &samples, &grid).unwrap();
    assert_eq!(tuning.folds, 5);
    assert_eq!((tuning.rows, tuning.skipped_rows), (60, 0));
    assert_eq!(tuning.scores.len(), 2);
    let minimum = tuning
        .scores
        .iter()
        .map(|s| s.mean)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(tuning.chosen.mean, minimum);
    assert_eq!(tuning.untuned.params, HyperParameters::default());
    let folds = leave_one_group_out(&samples.groups).unwrap();
    let defaults = cross_validate(mapping, &samples, &folds, &HyperParameters::default()).unwrap();
    assert_eq!(tuning.untuned, defaults);

    let dir = scratch_dir("tuning_record");
    tuning.save(&dir).unwrap();
    assert!(Tuning::path(&dir, "dv").ends_with("dv.tuning.json"));
    assert_eq!(Tuning::load(&dir, "dv").unwrap(), tuning);
}

#[test]
fn the_standard_grid_holds_the_defaults_and_stays_small() {
    let candidates = standard_grid().candidates();
    assert!(candidates.contains(&HyperParameters::default()));
    // Each setting costs one fit per simulation: 96 x 8 fits of 300 rows take ~10 s.
    assert!(candidates.len() <= 100, "{} settings", candidates.len());
    // Both kinds of model are searched: trees alone and trees on the backbone's residual.
    assert!(candidates.iter().any(|p| p.backbone) && candidates.iter().any(|p| !p.backbone));
    assert!(candidates.iter().all(|p| p.n_estimators <= 300));
}

#[test]
fn tuning_one_simulation_is_a_clear_error() {
    let data = synthetic_dataset(1, 12, 3);
    let mapping = Mapping::by_name("mu").unwrap();
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    let error = Tuning::run(mapping, &samples, &standard_grid()).unwrap_err();
    assert!(
        error.to_string().contains("at least 2 simulations"),
        "{error}"
    );
}

#[test]
fn tuning_leaves_out_the_backbone_where_its_laws_do_not_fit() {
    // phi_loc grows with J, so with sqrt(J / mu): no jamming law (eq 6.7) to fit.
    let mut csv = String::from("scene_id,J,Delta_v,phi,phi_loc,mu\n");
    for scene in 0..4 {
        for bin in 1..10 {
            let j = 0.01 * bin as f64 + 0.001 * scene as f64;
            csv += &format!("s{scene},{j},0.05,0.54,{},{}\n", 0.5 + j, 2.0 * j.sqrt());
        }
    }
    let data = surrogate::Dataset::from_csv_bytes(csv.as_bytes(), "rising").unwrap();
    let mapping = Mapping::by_name("dv").unwrap();
    let samples = Samples::from_dataset(&data, mapping).unwrap();
    let grid = HyperParameterGrid {
        base: HyperParameters::default(),
        n_estimators: vec![20],
        max_depth: vec![2],
        learning_rate: vec![0.1],
        min_child_weight: vec![],
        backbone: vec![false, true],
    };
    let tuning = Tuning::run(mapping, &samples, &grid).unwrap();
    let why = tuning.backbone_excluded.as_deref().unwrap();
    assert!(why.contains("eq 6.7"), "{why}");
    assert_eq!(tuning.scores.len(), 1);
    assert!(!tuning.chosen.params.backbone);
}

fn samples_with_families(n_scenes: usize, families: usize, mapping: &str) -> Samples {
    let csv = synthetic_csv_with_families(n_scenes, 6, 4, families);
    let data = surrogate::Dataset::from_csv_bytes(csv.as_bytes(), "families").unwrap();
    Samples::from_dataset(&data, Mapping::by_name(mapping).unwrap()).unwrap()
}

#[test]
fn leave_one_family_out_holds_whole_families_and_leaves_each_out_once() {
    // 10 scenes over 4 families: families of 3, 3, 2 and 2 scenes, interleaved.
    let samples = samples_with_families(10, 4, "mu");
    let families = samples.families.clone().unwrap();
    let folds = leave_one_family_out(&samples).unwrap();
    assert_valid_grouped_folds(
        &families,
        &folds.iter().map(|f| f.fold.clone()).collect::<Vec<_>>(),
    );
    let left_out: Vec<&str> = folds.iter().map(|f| f.family.as_str()).collect();
    assert_eq!(left_out, family_names(&samples).unwrap());
    assert_eq!(
        left_out,
        [
            "0.1*sin(2*pi*y/L)",
            "0.2*sin(2*pi*y/L)",
            "0.3*sin(2*pi*y/L)",
            "0.4*sin(2*pi*y/L)"
        ]
    );
    for fold in &folds {
        // Every row of the family is tested, and only those; simulations stay whole.
        let expected: Vec<usize> = (0..samples.n_rows())
            .filter(|&r| families[r] == fold.family)
            .collect();
        assert_eq!(fold.fold.test, expected);
        let scenes: BTreeSet<&String> =
            fold.fold.test.iter().map(|&r| &samples.groups[r]).collect();
        assert_eq!(fold.fold.test.len(), 6 * scenes.len());
    }
}

#[test]
fn leave_one_family_out_needs_two_families_and_a_profile_column() {
    let one = samples_with_families(4, 1, "mu");
    let error = leave_one_family_out(&one).unwrap_err().to_string();
    assert!(
        error.contains("at least 2 families") && error.contains("has 1"),
        "{error}"
    );
    let mut none = one.clone();
    none.families = None;
    let error = leave_one_family_out(&none).unwrap_err().to_string();
    assert!(error.contains("no `profile` column"), "{error}");
}

#[test]
fn tuning_leaves_families_out_from_three_families_and_simulations_below() {
    let grid = HyperParameterGrid {
        base: HyperParameters::default(),
        n_estimators: vec![20],
        max_depth: vec![2],
        learning_rate: vec![0.3],
        min_child_weight: vec![],
        backbone: vec![],
    };
    let mapping = Mapping::by_name("theta").unwrap();
    // 6 scenes over 3 families: one fold per family; over 2 families: one per simulation.
    let three = samples_with_families(6, 3, "theta");
    let (left_out, folds) = tuning_folds(&three).unwrap();
    assert_eq!((left_out, folds.len()), (LeftOut::Family, 3));
    for (families, left_out, folds, words) in [
        (3, LeftOut::Family, 3, ["profile families", "`profile`"]),
        (2, LeftOut::Simulation, 6, ["simulations", "`scene_id`"]),
    ] {
        let samples = samples_with_families(6, families, "theta");
        let tuning = Tuning::run(mapping, &samples, &grid).unwrap();
        assert_eq!((tuning.left_out, tuning.folds), (left_out, folds));
        let text = &tuning.cross_validation;
        assert!(words.iter().all(|w| text.contains(w)), "{text}");
    }
    // Without a profile column there are no families either.
    let mut none = three.clone();
    none.families = None;
    assert_eq!(tuning_folds(&none).unwrap().0, LeftOut::Simulation);
}

#[test]
fn families_come_from_the_profile_column_of_either_table_kind() {
    let runs = "scene_id,profile,seed,J,Theta,phi,phi_loc,mu\n\
                a,\"0.1*sin(2*pi*y/L)\",1,0.01,0.1,0.5,0.6,0.3\n\
                a,\"0.1*sin(2*pi*y/L)\",2,0.02,0.2,0.5,0.6,0.3\n\
                b,\"0.2*sin(2*pi*y/L) + 0.1*cos(4*pi*y/L)\",1,0.03,0.3,0.5,0.6,0.3\n";
    let ensemble = "scene_id,profile,replicas,se_from,J,Theta,phi,phi_loc,mu\n\
                    a,\"0.1*sin(2*pi*y/L)\",2,replicas,0.01,0.1,0.5,0.6,0.3\n\
                    b,\"0.2*sin(2*pi*y/L) + 0.1*cos(4*pi*y/L)\",1,batch_means,0.03,0.3,0.5,0.6,0.3\n";
    for (csv, rows, ensemble) in [(runs, vec![0, 0, 1], false), (ensemble, vec![0, 1], true)] {
        let data = surrogate::Dataset::from_csv_bytes(csv.as_bytes(), "t").unwrap();
        let kind = surrogate::TableKind::of(&data).unwrap();
        assert_eq!(
            matches!(kind, surrogate::TableKind::Ensemble { .. }),
            ensemble
        );
        let samples = Samples::from_dataset(&data, Mapping::by_name("theta").unwrap()).unwrap();
        let names = family_names(&samples).unwrap();
        assert_eq!(
            names,
            ["0.1*sin(2*pi*y/L)", "0.2*sin(2*pi*y/L) + 0.1*cos(4*pi*y/L)"]
        );
        let families: Vec<&String> = rows.iter().map(|&k| &names[k]).collect();
        assert_eq!(
            samples
                .families
                .as_ref()
                .unwrap()
                .iter()
                .collect::<Vec<_>>(),
            families
        );
        // A subset keeps each row's family.
        let last = samples.subset(&[samples.n_rows() - 1]).unwrap();
        assert_eq!(last.families.unwrap(), [names[1].clone()]);
    }
}
