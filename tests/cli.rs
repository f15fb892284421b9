//! End-to-end tests of the `suspflow` command on tiny scenes.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn suspflow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_suspflow"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("runs suspflow")
}

fn scenes_in(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("suspflow-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn bad_scenes_are_refused_naming_the_field() {
    let bad = scenes_in(&root().join("tests/scenes/bad"));
    assert!(bad.len() >= 10);
    let out_dir = temp_dir("bad");
    for scene in bad {
        let text = std::fs::read_to_string(&scene).unwrap();
        let expect = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# expect: "))
            .expect("first line names the expected message");
        let out = suspflow(&[
            "simulate",
            scene.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{} was accepted", scene.display());
        assert!(
            stderr.contains(expect),
            "{}: error does not mention `{expect}`:\n{stderr}",
            scene.display()
        );
        assert!(
            !stderr.contains("panicked"),
            "{} panicked:\n{stderr}",
            scene.display()
        );
    }
}

#[test]
fn shipped_scenes_are_valid() {
    let mut scenes = scenes_in(&root().join("scenes"));
    scenes.extend(scenes_in(&root().join("tests/scenes/good")));
    assert!(scenes.iter().any(|p| p.ends_with("quick.toml")));
    for scene in scenes {
        let out = suspflow(&[
            "simulate",
            scene.to_str().unwrap(),
            "--out",
            "unused",
            "--check",
        ]);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{}: {}",
            scene.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            stdout.contains("dt = ") && stdout.contains("set by"),
            "{stdout}"
        );
    }
}

/// Parses a CSV into its header and rows of fields.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    // The profile expression is quoted and holds no comma in these scenes.
    (
        header,
        lines
            .map(|l| l.split(',').map(String::from).collect())
            .collect(),
    )
}

#[test]
fn golden_run_matches_and_writes_every_output() {
    let out_dir = temp_dir("golden");
    let out = suspflow(&[
        "simulate",
        "tests/scenes/good/golden.toml",
        "--out",
        out_dir.to_str().unwrap(),
        "--threads",
        "1",
        "--snapshot",
        "4",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("profile.csv"),
        "must say where the profile went"
    );

    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out_dir.join("summary.json")).unwrap()).unwrap();
    for key in [
        "n_particles",
        "dt",
        "dt_limit",
        "steps",
        "strain_to_steady",
        "wall_s",
        "particle_steps_per_s",
        "momentum_residual",
        "mean_overlap",
        "max_overlap",
    ] {
        assert!(!summary[key].is_null(), "summary.json lacks {key}");
    }
    assert_eq!(summary["dt_limit"], "lubrication");

    let frames = std::fs::read_to_string(out_dir.join("frames.xyz")).unwrap();
    let n = summary["n_particles"].as_u64().unwrap() as usize;
    let snapshots = 4 * 2 + 8; // 4 windows of 2 snapshots, then 8 averaged
    assert_eq!(frames.lines().count(), (snapshots / 4) * (n + 2));

    let produced = out_dir.join("profile.csv");
    let golden = root().join("tests/golden/golden_profile.csv");
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::copy(&produced, &golden).unwrap();
    }
    let (h1, r1) = read_csv(&produced);
    let (h2, r2) = read_csv(&golden);
    assert_eq!(h1, h2, "profile columns changed");
    assert!(h1.iter().any(|c| c == "phi_loc_se") && h1.iter().any(|c| c == "Delta_v"));
    assert_eq!(r1.len(), 8, "one row per bin");
    assert_eq!(r1.len(), r2.len());
    for (row, (a, b)) in r1.iter().zip(&r2).enumerate() {
        for (c, (x, y)) in a.iter().zip(b).enumerate() {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => assert!(
                    (x - y).abs() <= 1e-6 * y.abs().max(1e-6),
                    "bin {row}, {}: {x} differs from the golden {y}",
                    h1[c]
                ),
                _ if h1[c] == "code_version" => {
                    assert!(x.starts_with(env!("CARGO_PKG_VERSION")), "code version {x}")
                }
                _ => assert_eq!(x, y, "bin {row}, {}", h1[c]),
            }
        }
    }
    std::fs::remove_dir_all(&out_dir).ok();
}

#[test]
fn bench_prints_json_records() {
    let out = suspflow(&[
        "bench",
        "--n",
        "1000",
        "--threads",
        "1",
        "--steps",
        "20",
        "--warmup",
        "0",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let records: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let r = &records[0];
    assert_eq!(r["threads"], 1);
    assert_eq!(r["lubrication"], true);
    assert!(r["n"].as_u64().unwrap().abs_diff(1000) <= 2);
    assert!(r["particle_steps_per_s"].as_f64().unwrap() > 0.0);
}
