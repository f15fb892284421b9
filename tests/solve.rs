//! End-to-end `suspflow solve`: a scene's profile from its forcing alone, with the shipped
//! models.
mod common;

use common::{numbers, s, scratch, suspflow};
use std::path::Path;
use std::process::Command;

/// A scene like the training scenes (phi 0.54, L_y 50, `0.1 sin(2 pi y / L)`), 25 bins.
const TRAINING_LIKE: &str = "name = \"like_train\"\n[box]\nl_x = 17.0\nl_y = 50.0\nl_z = 17.0\n\
     [particles]\nphi = 0.54\n[fluid]\nprofile = \"0.1*sin(2*pi*y/L)\"\n";

#[test]
fn solve_writes_a_profile_whose_phi_loc_averages_to_phi_and_keeps_earlier_ones() {
    let out = scratch("like-train");
    std::fs::create_dir_all(&out).unwrap();
    let scene = out.join("scene.toml");
    std::fs::write(&scene, TRAINING_LIKE).unwrap();
    let solution = out.join("solution");
    for closure in ["learned", "local"] {
        let result = suspflow(&[
            "solve",
            s(&scene),
            "--models",
            "models",
            "--closure",
            closure,
            "--out",
            s(&solution),
            "--force",
        ]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(result.status.success(), "{closure}: {stderr}");
        let text = std::fs::read_to_string(solution.join("profile.csv")).unwrap();
        let phi_loc = numbers(&text, "phi_loc");
        assert_eq!(phi_loc.len(), 25);
        let mean = phi_loc.iter().sum::<f64>() / phi_loc.len() as f64;
        assert!((mean - 0.54).abs() < 1e-6, "{closure}: mean phi_loc {mean}");
        // The drag on the particles sums to zero over the period (the balance telescopes).
        let f_x = numbers(&text, "f_x");
        let total: f64 = f_x.iter().sum();
        let scale: f64 = f_x.iter().map(|f| f.abs()).sum();
        assert!(
            total.abs() < 1e-6 * scale,
            "{closure}: net drag {total} of {scale}"
        );
        // The summary reads back as the type that wrote it, beside the scene it solved.
        let summary = solver::SolveSummary::read(&solution).unwrap();
        assert_eq!(summary.closure, closure);
        assert!(summary.residual <= 1e-9);
        assert!(solution.join("scene.toml").exists());
    }
    // Without --force an earlier solution stays.
    let again = suspflow(&["solve", s(&scene), "--out", s(&solution)]);
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn compare_needs_the_scene_in_the_simulated_file() {
    let out = scratch("compare");
    let result = suspflow(&[
        "solve",
        "scenes/quick.toml",
        "--closure",
        "local",
        "--out",
        s(&out),
        "--compare",
        "datasets/validate.csv",
    ]);
    assert!(!result.status.success());
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("holds 0 rows of scene `quick`"), "{stderr}");
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn a_stalled_solve_is_continued_from_the_local_law_and_says_so() {
    // plugs_dense_003 of grids/plugs_dense.toml (phi 0.58, sin^5 forcing, a box 100 high):
    // with the shipped theta trees and Theta balance, Newton's method from the local law's
    // solution stalls on the trees' facets, and so does Newton from u = u_inf (the second
    // attempt); the solve follows the continuation from the local law, converges, and
    // records that it did (the solver's own test uses the same scene). A solve that stalls
    // every way is an error and writes nothing: solver's tests.
    let out = scratch("plugs_dense_003");
    std::fs::create_dir_all(&out).unwrap();
    let scene = out.join("plugs_dense_003.toml");
    std::fs::write(
        &scene,
        "name = \"plugs_dense_003\"\n\
         [box]\nl_x = 17.0\nl_y = 100.0\nl_z = 17.0\n\
         [particles]\nphi = 0.58\nstokes = 0.09\n\
         [fluid]\nprofile = \"0.2*sin(8*pi*y/L)^5\"\n",
    )
    .unwrap();
    let solution = out.join("solution");
    let result = suspflow(&[
        "solve",
        s(&scene),
        "--closure",
        "nonlocal",
        "--out",
        s(&solution),
    ]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(solution.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(
        summary["continued"],
        serde_json::Value::Bool(true),
        "{summary}"
    );
    assert_eq!(summary["closure"], "nonlocal", "{summary}");
    assert!(summary["residual"].as_f64().unwrap() <= 1e-9, "{summary}");
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn homogeneous_shear_is_refused_naming_the_field() {
    let out = scratch("shear");
    let result = suspflow(&["solve", "scenes/shear.toml", "--out", s(&out)]);
    assert!(!result.status.success());
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("fluid.shear_rate"), "{stderr}");
    assert!(!out.join("profile.csv").exists());
}

/// Issue 31, class 10: a solve beyond the closure's training data says so per bin
/// (`in_domain`, `domain_distance` in profile.csv), in the summary and in a warning. The
/// training rows have phi 0.48-0.60 (datasets/wide_plugs.ensemble.csv): at phi 0.40 and 0.62 every
/// bin is out of range whatever its local state, while the training-like scene stays in.
#[test]
fn a_solve_beyond_the_training_data_flags_its_bins() {
    let out = scratch("extrapolated");
    std::fs::create_dir_all(&out).unwrap();
    for (phi, closure, all_out) in [
        ("0.54", "learned", false),
        ("0.40", "learned", true),
        ("0.62", "local", true),
    ] {
        let scene = out.join(format!("phi{phi}.toml"));
        std::fs::write(
            &scene,
            TRAINING_LIKE.replace("phi = 0.54", &format!("phi = {phi}")),
        )
        .unwrap();
        let solution = out.join(format!("solution{phi}"));
        let result = suspflow(&[
            "solve",
            s(&scene),
            "--closure",
            closure,
            "--out",
            s(&solution),
        ]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(result.status.success(), "phi {phi}: {stderr}");
        let text = std::fs::read_to_string(solution.join("profile.csv")).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let at = header.iter().position(|&c| c == "in_domain").unwrap();
        let inside: Vec<bool> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(at).unwrap() == "true")
            .collect();
        let outside = inside.iter().filter(|&&i| !i).count();
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(solution.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(summary["bins_outside_domain"], outside, "phi {phi}");
        if all_out {
            assert_eq!(outside, 25, "phi {phi}");
            assert!(
                stderr.contains("25 of 25 bins lie outside the training domain"),
                "{stderr}"
            );
        } else {
            assert!(outside < 25 / 2, "phi {phi}: {outside} of 25 bins outside");
        }
    }
    std::fs::remove_dir_all(&out).ok();
}

/// The learned closure finds the training file its sidecar names from the models' folder,
/// whatever the current directory (issue 31, 16.16: it was read from the current one).
#[test]
fn solve_finds_the_training_data_from_any_directory() {
    let out = scratch("any-dir");
    std::fs::create_dir_all(&out).unwrap();
    let scene = out.join("scene.toml");
    std::fs::write(&scene, TRAINING_LIKE).unwrap();
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    for (cwd, models_arg) in [(models.as_path(), "."), (out.as_path(), s(&models))] {
        let result = Command::new(env!("CARGO_BIN_EXE_suspflow"))
            .args(["solve", s(&scene), "--models", models_arg, "--out"])
            .arg(out.join("solution"))
            .arg("--force")
            .current_dir(cwd)
            .output()
            .unwrap();
        assert!(
            result.status.success(),
            "from {}: {}",
            cwd.display(),
            String::from_utf8_lossy(&result.stderr)
        );
    }
    std::fs::remove_dir_all(&out).ok();
}
