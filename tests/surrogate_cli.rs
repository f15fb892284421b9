//! End-to-end `train` and `predict` on a synthetic table with a known smooth law.
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::{Command, Output};

fn suspflow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_suspflow")).args(args).output().expect("runs suspflow")
}

/// 16 fake simulations of 40 bins: phi_loc, Theta, Delta_v and mu smooth in (J, phi).
fn synthetic_table(dir: &std::path::Path) -> PathBuf {
    let mut csv = String::from("scene_id,phi,J,phi_loc,Theta,Delta_v,mu\n");
    for s in 0..16 {
        let phi = 0.50 + 0.02 * (s % 4) as f64;
        for b in 0..40 {
            let j = 1e-3 * (1.0 + 0.1 * ((b * 7 + s * 3) % 97) as f64);
            let phi_loc = phi + 0.05 - 0.8 * j.sqrt() * 0.3;
            let theta = 0.02 + 2.0 * j;
            let dv = 0.3 + 5.0 * j;
            let mu = 0.3 + 0.5 * j.powf(0.4) + 0.2 * (phi - 0.5);
            let _ = writeln!(csv, "s{s},{phi},{j},{phi_loc},{theta},{dv},{mu}");
        }
    }
    let path = dir.join("train.csv");
    std::fs::write(&path, csv).unwrap();
    path
}

#[test]
fn train_then_predict_reproduces_a_smooth_law() {
    let dir = std::env::temp_dir().join(format!("suspflow-train-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let data = synthetic_table(&dir);
    let models = dir.join("models");
    let out = suspflow(&["train", "--data", data.to_str().unwrap(), "--out", models.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for m in ["mu", "theta", "dv"] {
        assert!(models.join(format!("{m}.json")).exists() && models.join(format!("{m}.meta.json")).exists());
    }
    let pred = dir.join("pred.csv");
    let out = suspflow(&["predict", "--model", models.join("mu").to_str().unwrap(), "--input", data.to_str().unwrap(),
                         "--out", pred.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&pred).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "J,phi_loc,phi,mu_pred");
    let input = std::fs::read_to_string(&data).unwrap();
    let truth: Vec<f64> = input.lines().skip(1).map(|l| l.rsplit(',').next().unwrap().parse().unwrap()).collect();
    let got: Vec<f64> = lines.map(|l| l.rsplit(',').next().unwrap().parse().unwrap()).collect();
    assert_eq!(got.len(), truth.len());
    let err = (got.iter().zip(&truth).map(|(a, b)| (a - b).powi(2)).sum::<f64>()
        / truth.iter().map(|b| b * b).sum::<f64>()).sqrt();
    assert!(err < 0.01, "in-sample relative error {err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_surrogate_inputs_give_clear_errors() {
    let dir = std::env::temp_dir().join(format!("suspflow-badtrain-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let data = synthetic_table(&dir);
    let out = suspflow(&["train", "--data", data.to_str().unwrap(), "--out", dir.join("m").to_str().unwrap(), "--mapping", "nope"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("nope") && err.contains("theta"), "{err}");
    let out = suspflow(&["train", "--data", data.to_str().unwrap(), "--out", dir.join("m").to_str().unwrap(), "--mapping", "mu"]);
    assert!(out.status.success());
    let missing = dir.join("missing.csv");
    std::fs::write(&missing, "scene_id,phi,J\ns0,0.5,0.001\n").unwrap();
    let out = suspflow(&["predict", "--model", dir.join("m/mu").to_str().unwrap(), "--input", missing.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("phi_loc"), "{err}");
    assert!(!err.contains("panicked"));
    std::fs::remove_dir_all(&dir).ok();
}
