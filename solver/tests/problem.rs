//! A problem built from a shipped scene: its forcing at the bin centres and over the bins,
//! and the drag of its particle mix.
use std::f64::consts::PI;
use std::path::PathBuf;

use sim::Scene;
use solver::ProfileProblem;

fn scene(name: &str) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name);
    Scene::from_path(&path, false).unwrap()
}

#[test]
fn a_problem_samples_the_forcing_at_the_bin_centres_and_over_the_bins() {
    // scenes/quick.toml: u = 0.2 sin(2 pi y / 20), 10 bins of width 2, radii 1 and 1.4.
    let problem = ProfileProblem::from_scene(&scene("quick.toml")).unwrap();
    assert_eq!(problem.n_bins(), 10);
    let y = problem.bin_centres();
    assert_eq!((y[0], y[9]), (1.0, 19.0));
    for (&u, &y) in problem.u_inf.iter().zip(&y) {
        assert!(
            (u - 0.2 * (2.0 * PI * y / 20.0).sin()).abs() < 1e-12,
            "{u} at {y}"
        );
    }
    // Bin means: a sine of wavenumber k averaged over a bin of width w centred at y is
    // sin(k y) sin(k w / 2) / (k w / 2), 0.984 of the centre value here.
    let (k, w) = (2.0 * PI / 20.0, 2.0);
    for (&u, &y) in problem.u_inf_mean.iter().zip(&y) {
        let exact = 0.2 * (k * y).sin() * (k * w / 2.0).sin() / (k * w / 2.0);
        assert!((u - exact).abs() < 1e-9, "{u} at {y}: {exact}");
    }
    // 6 pi eta <a> / <V_p> lies between the two radii's own 6 pi eta a / V_p.
    let own = |a: f64| 6.0 * PI * a / (4.0 / 3.0 * PI * a.powi(3));
    let c = problem.drag_coefficient;
    assert!(own(1.4) < c && c < own(1.0), "{c}");
}

#[test]
fn homogeneous_shear_has_nothing_to_solve() {
    let err = ProfileProblem::from_scene(&scene("shear.toml")).unwrap_err();
    assert!(err.to_string().contains("fluid.shear_rate"), "{err}");
}
