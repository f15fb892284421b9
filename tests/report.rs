//! `suspflow report`: the stability section on one swept parameter (6 dt multiples x 4
//! stiffnesses, a few seconds): the automatic dt is stable, a step 16x too large is caught
//! with its cause named, and no run ends in NaN unreported.
use std::path::PathBuf;
use std::process::Command;

#[test]
fn stability_sweep_catches_large_steps_and_keeps_the_automatic_one_stable() {
    let dir = std::env::temp_dir().join(format!("suspflow-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_suspflow"))
        .args(["report", "--name", "t", "--only", "k_n", "--out", dir.to_str().unwrap()])
        .current_dir(PathBuf::from(env!("CARGO_MANIFEST_DIR"))).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let md = std::fs::read_to_string(dir.join("t/report.md")).unwrap();
    assert!(dir.join("t/stability_map.svg").exists());
    let rows: Vec<Vec<&str>> = md.lines().filter(|l| l.starts_with("| k_n |"))
        .map(|l| l.split('|').map(str::trim).collect()).collect();
    assert_eq!(rows.len(), 4 * 6);
    for r in &rows {
        let (factor, outcome): (f64, &str) = (r[3].parse().unwrap(), r[4]);
        if factor <= 1.0 {
            assert_eq!(outcome, "stable", "automatic dt unstable: {r:?}");
            assert!(r[7].parse::<f64>().unwrap().is_finite() && r[8].parse::<f64>().unwrap() < 0.1, "{r:?}");
        }
        if factor == 16.0 {
            assert_eq!(outcome, "blow-up", "{r:?}");
            assert_eq!(r[9], "yes", "the failure must name its cause: {r:?}");
        }
        if matches!(outcome, "stable" | "inaccurate") {
            assert!(!r[8].contains("NaN"), "a finished run with NaN: {r:?}");
        }
    }
    assert!(md.contains("Likely cause"));
}
