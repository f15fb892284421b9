//! Class 7: one range-and-cost check for every option that sets work.
use crate::common::{s, scratch, stderr, suspflow};
use crate::refused_with;

/// `green-kubo` with absurd lengths or block counts is refused before anything runs, with a
/// message and no panic (before: `--span 1e300` and `--blocks 2^62` panicked; `--warmup
/// 1e300` would step for ever).
#[test]
fn green_kubo_lengths_beyond_any_run_are_refused_not_panicked_on() {
    let dir = scratch("gk-limits");
    let out = dir.join("gk");
    let cases: [(&[&str], &str); 5] = [
        (&["--span", "1e300"], "the run cannot finish"),
        (&["--warmup", "1e300"], "the run cannot finish"),
        (&["--span", "1e9"], "the run cannot finish"),
        (&["--blocks", "4611686018427387904"], "too few"),
        (&["--max-lag", "1e300"], "too few"),
    ];
    for (extra, text) in cases {
        let mut args = vec![
            "green-kubo",
            "tests/scenes/good/tiny_brownian.toml",
            "--out",
            s(&out),
        ];
        args.extend_from_slice(extra);
        let started = std::time::Instant::now();
        let ran = suspflow(&args);
        assert!(refused_with(&ran, text), "{extra:?}: {}", stderr(&ran));
        assert!(started.elapsed().as_secs_f64() < 10.0, "{extra:?}");
    }
    assert!(!out.join("checkpoint.json").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// `bench` and `bench --brownian` go through the same rule: windows that cannot finish are
/// refused before any particle is placed, the others start with their estimate (before:
/// `--window-tau-b 1e9` started a 36-year loop without a word, `--steps 2^64 - 1` one of
/// millions of years), and a large `--n` is judged by the bench's windows, not by the
/// default run of the scene it borrows (before: `--n 20000000` was refused as "no bench
/// box is valid ...: the skin is too large").
#[test]
fn bench_windows_go_through_the_range_and_cost_check() {
    let refusals: [&[&str]; 3] = [
        &["--brownian", "--window-tau-b", "1e9"],
        &["--brownian", "--warmup-tau-b", "1e9"],
        &["--steps", "18446744073709551615"],
    ];
    for extra in refusals {
        let mut args = vec!["bench", "--n", "1000", "--threads", "1"];
        args.extend_from_slice(extra);
        let ran = suspflow(&args);
        assert!(
            refused_with(&ran, "the run cannot finish") && stderr(&ran).contains("years here"),
            "{extra:?}: {}",
            stderr(&ran)
        );
    }
    let ran = suspflow(&[
        "bench",
        "--brownian",
        "--n",
        "300",
        "--threads",
        "1",
        "--integrator",
        "implicit",
        "--warmup-tau-b",
        "0.01",
        "--window-tau-b",
        "0.01",
    ]);
    crate::common::assert_ok(&ran);
    assert!(
        stderr(&ran).contains("1 measurement(s), estimated at most"),
        "{}",
        stderr(&ran)
    );
    // Too few for the Brownian box: named by the option (before: by `box.l_x` only).
    let ran = suspflow(&["bench", "--brownian", "--n", "1", "--threads", "1"]);
    assert!(
        refused_with(&ran, "--n 1: the Brownian bench box") && stderr(&ran).contains("box.l_x"),
        "{}",
        stderr(&ran)
    );
    // More particles than the machine holds: named as such, by the option.
    let ran = suspflow(&["bench", "--n", "100000000", "--threads", "1"]);
    assert!(
        refused_with(&ran, "--n 100000000: too many particles here")
            && stderr(&ran).contains("of memory"),
        "{}",
        stderr(&ran)
    );
}

/// `cross-validate --learning-curve` checks its counts and draws and times one fit before
/// any model is trained, then shows the estimate of every mapping's curve (before: none,
/// and `--draws 4096` ran 40 minutes without a word; a count or draws out of range for a
/// later mapping were refused after the earlier ones were done).
#[test]
fn a_learning_curve_is_checked_and_estimated_before_it_runs() {
    let dir = scratch("curve-limits");
    let base = [
        "cross-validate",
        "--data",
        "datasets/wide_plugs.ensemble.csv",
        "--models",
        "models",
        "--mapping",
        "mu",
        "--out",
        s(&dir),
        "--learning-curve",
        "2",
    ];
    for (draws, text) in [("0", "1 to 4096 draws"), ("4097", "1 to 4096 draws")] {
        let mut args = base.to_vec();
        args.extend(["--draws", draws]);
        let ran = suspflow(&args);
        assert!(refused_with(&ran, text), "{draws}: {}", stderr(&ran));
        assert!(!stderr(&ran).contains("cross-validate mu:"), "{draws}");
    }
    let mut args = base.to_vec();
    args.extend(["--learning-curve", "99"]);
    let ran = suspflow(&args);
    assert!(
        refused_with(&ran, "between 1 and 15") && !stderr(&ran).contains("cross-validate mu:"),
        "{}",
        stderr(&ran)
    );
    assert!(!dir.join("cv.json").exists());
    std::fs::remove_dir_all(&dir).ok();
}
