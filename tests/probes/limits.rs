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
