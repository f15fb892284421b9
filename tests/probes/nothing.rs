//! Class 6: success on nothing is an error.
use crate::common::{assert_ok, s, scratch, stderr, suspflow};
use crate::refused_with;
use std::path::Path;

/// `flow-curves` of `runs` into `out` with Green-Kubo folders `gk`.
fn flow_curves(runs: &Path, out: &Path, gk: &[&Path]) -> std::process::Output {
    let mut args = vec![
        "flow-curves",
        "tests/grids/tiny_shear.toml",
        "--runs",
        s(runs),
        "--out",
        s(out),
    ];
    for g in gk {
        args.extend(["--green-kubo", s(g)]);
    }
    suspflow(&args)
}

/// A Green-Kubo result at volume fraction `phi`, as `green-kubo` writes it, in `dir`.
fn green_kubo_at(dir: &Path, phi: f64, scene: &str) {
    std::fs::create_dir_all(dir).unwrap();
    let result = rheometry::GreenKuboResult {
        scene: scene.into(),
        n_particles: 100,
        phi_actual: phi,
        kt: 0.1,
        tau_b: 10.0,
        eta_brownian_over_eta: 1.0,
        eta_brownian_over_eta_se: 0.1,
        extrapolated_eta_brownian_over_eta: 2.0,
        extrapolated_eta_brownian_over_eta_se: 0.2,
        relaxation_tau_b: 0.5,
        blocks: 10,
        warmup_tau_b: 5.0,
        span_tau_b: 100.0,
        max_lag_tau_b: 5.0,
        every_steps: 5,
        code_version: "test".into(),
        warnings: Vec::new(),
    };
    std::fs::write(
        dir.join("green_kubo.json"),
        serde_json::to_string(&result).unwrap(),
    )
    .unwrap();
}

/// A missing, an empty and a foreign `--runs` fail saying so, and write no table (before:
/// exit 0 with an empty table, three times).
#[test]
fn flow_curves_of_no_finished_run_fail() {
    let dir = scratch("fc-nothing");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    // Another grid's folder: runs of other labels.
    let foreign = dir.join("foreign");
    std::fs::create_dir_all(foreign.join("other_000_s1")).unwrap();
    for (runs, text) in [
        (dir.join("missing"), "is not a folder of runs"),
        (empty, "holds no finished run"),
        (foreign, "holds no finished run"),
    ] {
        let out = dir.join("out");
        let ran = flow_curves(&runs, &out, &[]);
        assert!(refused_with(&ran, text), "{}", stderr(&ran));
        assert!(!out.join("flow_curves.csv").exists());
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Green-Kubo inputs that no run would use are named, and one folder given twice (or a copy
/// of it) is refused (before: dropped without a word; counted as two replicas, their spread
/// of zero the error).
#[test]
fn green_kubo_inputs_matching_no_run_or_repeated_are_refused() {
    let dir = scratch("fc-gk");
    let runs = dir.join("runs");
    assert_ok(&suspflow(&[
        "generate",
        "tests/grids/tiny_shear.toml",
        "--out",
        s(&dir.join("bins.csv")),
        "--work",
        s(&runs),
        "--jobs",
        "2",
        "--threads",
        "1",
    ]));
    // The realised volume fraction of one run.
    let first = std::fs::read_dir(&runs)
        .unwrap()
        .filter_map(|e| std::fs::read_to_string(e.ok()?.path().join("summary.json")).ok())
        .next()
        .unwrap();
    let phi = serde_json::from_str::<serde_json::Value>(&first).unwrap()["phi_actual"]
        .as_f64()
        .unwrap();
    let (here, copy, nowhere) = (dir.join("gk"), dir.join("gk_copy"), dir.join("gk_far"));
    green_kubo_at(&here, phi, "eq");
    green_kubo_at(&copy, phi, "eq");
    green_kubo_at(&nowhere, 0.2, "eq_far");
    let out = dir.join("out");
    let ran = flow_curves(&runs, &out, &[&here, &nowhere]);
    assert!(
        refused_with(&ran, "gk_far") && refused_with(&ran, "is that of no finished run"),
        "{}",
        stderr(&ran)
    );
    for twice in [&here, &copy] {
        let ran = flow_curves(&runs, &out, &[&here, twice]);
        assert!(refused_with(&ran, "are the same run"), "{}", stderr(&ran));
    }
    assert!(!out.join("flow_curves.csv").exists());
    assert_ok(&flow_curves(&runs, &out, &[&here]));
    std::fs::remove_dir_all(&dir).ok();
}
