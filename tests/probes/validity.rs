//! Class 5: one statement of a result's validity; nothing outside it written silently.
use crate::common::{assert_ok, csv_column, s, scratch, stderr, suspflow};
use crate::{refused_with, scene_file};

/// `solve` of a Brownian scene is refused (before: solved with the non-Brownian closures,
/// every bin marked in domain).
#[test]
fn solving_a_brownian_scene_is_refused() {
    let dir = scratch("solve-brownian");
    let tiny = std::fs::read_to_string("tests/scenes/good/tiny.toml").unwrap();
    let scene = scene_file(
        &dir,
        "brownian",
        &tiny.replace("[fluid]\n", "[fluid]\nkT = 0.01\n"),
    );
    let out = suspflow(&["solve", s(&scene), "--out", s(&dir.join("solved"))]);
    assert!(refused_with(&out, "Brownian forces"), "{}", stderr(&out));
    assert!(!dir.join("solved/profile.csv").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// The Green-Kubo result keeps the scene's warnings (before: printed, then dropped from
/// `green_kubo.json`), and the run's cost is estimated before it starts.
#[test]
fn a_green_kubo_result_keeps_the_scene_warnings() {
    let dir = scratch("gk-warnings");
    // tau_I / tau_B = rho kT / (eta^2 a) = 0.1: above the inertia-free limit, a warning.
    let scene = scene_file(
        &dir,
        "eq",
        "box = { l_x = 10.0, l_y = 10.0, l_z = 10.0 }\n\
         particles = { phi = 0.3, rho = 0.5 }\nfluid = { kT = 0.2 }\n",
    );
    let out = dir.join("gk");
    let ran = suspflow(&[
        "green-kubo",
        s(&scene),
        "--out",
        s(&out),
        "--warmup",
        "1",
        "--span",
        "20",
        "--max-lag",
        "0.5",
        "--blocks",
        "5",
    ]);
    assert_ok(&ran);
    assert!(
        stderr(&ran).contains("estimated at most"),
        "{}",
        stderr(&ran)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("green_kubo.json")).unwrap())
            .unwrap();
    let warnings = json["warnings"].as_array().cloned().unwrap_or_default();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains("tau_I/tau_B")),
        "{json}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A mixture whose alpha places no grain in the box is refused naming the field (before:
/// "valid", Pe_cg of the nominal alpha reported for a run of colloids only).
#[test]
fn a_mixture_that_places_no_grain_is_refused() {
    let dir = scratch("mixture-alpha");
    let scene = scene_file(
        &dir,
        "mix",
        "name = \"mix\"\nbox = { l_x = 36.0, l_y = 36.0, l_z = 36.0 }\n\
         [particles]\nphi = 0.4\nmixture = { alpha = 0.01 }\n\
         [fluid]\nprofile = \"0.1*sin(2*pi*y/L)\"\n",
    );
    let out = suspflow(&["simulate", "--check", s(&scene)]);
    assert!(
        refused_with(&out, "particles.mixture.alpha") && refused_with(&out, "places no grain"),
        "{}",
        stderr(&out)
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A run at rest writes J, mu, Theta and Delta_v as undefined (empty) with a warning saying
/// why (before: Delta_v of 1e3 and noise-only J, mu, Theta without a word).
#[test]
fn a_run_at_rest_leaves_the_shear_observables_undefined_and_says_so() {
    let dir = scratch("rest");
    let out = dir.join("run");
    let ran = suspflow(&[
        "simulate",
        "tests/scenes/good/tiny_brownian.toml",
        "--out",
        s(&out),
    ]);
    assert_ok(&ran);
    let profile = std::fs::read_to_string(out.join("profile.csv")).unwrap();
    for column in ["J", "mu", "Theta", "Delta_v", "J_se", "Delta_v_se"] {
        let cells = csv_column(&profile, column);
        assert!(cells.iter().all(String::is_empty), "{column}: {cells:?}");
    }
    assert!(!csv_column(&profile, "P").iter().any(String::is_empty));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("no flow: J, mu, Theta and Delta_v are undefined"));
    std::fs::remove_dir_all(&dir).ok();
}
