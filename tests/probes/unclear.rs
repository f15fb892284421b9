//! Class 8: errors that say what is wrong.
use crate::common::{assert_ok, s, scratch, stderr, suspflow};
use crate::{refused_with, scene_file};

/// A scene at rest with the drag off has no profile flow to drive and is not refused for
/// one (before: "the drag is what drives a profile flow").
#[test]
fn a_scene_at_rest_without_drag_is_not_refused_for_a_flow_it_does_not_have() {
    let dir = scratch("rest-no-drag");
    let tiny = std::fs::read_to_string("tests/scenes/good/tiny_brownian.toml").unwrap();
    let scene = scene_file(&dir, "no_drag", &(tiny + "\n[forces]\ndrag = false\n"));
    assert_ok(&suspflow(&["simulate", "--check", s(&scene)]));
    std::fs::remove_dir_all(&dir).ok();
}

/// `report --scenes` of a Brownian grid is refused before any run, naming the scene (before:
/// 85 s of runs, then an error on a file the report had written itself).
#[test]
fn a_report_of_brownian_scenes_is_refused_before_it_runs() {
    let started = std::time::Instant::now();
    let dir = scratch("report-brownian");
    let ran = suspflow(&[
        "report",
        "--scenes",
        "tests/grids/tiny_brownian_shear.toml",
        "--out",
        s(&dir),
    ]);
    assert!(refused_with(&ran, "is Brownian"), "{}", stderr(&ran));
    assert!(started.elapsed().as_secs_f64() < 10.0);
    std::fs::remove_dir_all(&dir).ok();
}
