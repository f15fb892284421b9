//! Class 2: one writer that cannot be redirected or collide (`schema::write_atomic`).
use crate::common::{assert_ok, s, scratch, stderr, suspflow};

/// A link left where a figure goes is replaced, never written through: `plot` draws its
/// SVG files with the one writer (before: plotters wrote to the path, following the link
/// and overwriting its target).
#[test]
fn a_figure_replaces_a_link_in_its_place_and_leaves_the_target_alone() {
    let dir = scratch("figure-link");
    let out = dir.join("plots");
    std::fs::create_dir_all(&out).unwrap();
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "kept").unwrap();
    // The first scene of the shipped validation set.
    let data = crate::common::root().join("datasets/validate.csv");
    let first = std::fs::read_to_string(&data).unwrap();
    let id = first
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .to_owned();
    let figure = out.join(format!("{id}.svg"));
    std::os::unix::fs::symlink(&victim, &figure).unwrap();
    // Without --force, a figure already there (the link) is refused, the target untouched.
    let refused = suspflow(&["plot", s(&data), "--out", s(&out)]);
    assert!(!refused.status.success() && stderr(&refused).contains("--force replaces it"));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "kept");
    assert_ok(&suspflow(&["plot", s(&data), "--out", s(&out), "--force"]));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "kept");
    let meta = std::fs::symlink_metadata(&figure).unwrap();
    assert!(!meta.is_symlink() && std::fs::read_to_string(&figure).unwrap().contains("<svg"));
    std::fs::remove_dir_all(&dir).ok();
}

/// `predict --out` onto a link (with --force) replaces the link (before: the table went
/// through it into the link's target).
#[test]
fn a_predicted_table_replaces_a_link_in_its_place() {
    let dir = scratch("predict-link");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "kept").unwrap();
    let out = dir.join("predicted.csv");
    std::os::unix::fs::symlink(&victim, &out).unwrap();
    assert_ok(&suspflow(&[
        "predict",
        "--model",
        "models/mu",
        "--input",
        "datasets/validate.csv",
        "--out",
        s(&out),
        "--force",
    ]));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "kept");
    assert!(!std::fs::symlink_metadata(&out).unwrap().is_symlink());
    std::fs::remove_dir_all(&dir).ok();
}

/// A solve whose summary cannot be written leaves no `profile.csv` behind, so the re-run is
/// not refused as "an earlier solution" (before: the profile was written first and stayed).
#[test]
fn a_solve_that_fails_to_write_leaves_nothing_that_blocks_its_rerun() {
    let dir = scratch("solve-write");
    let out = dir.join("solved");
    // A folder where the summary goes: its rename fails as a full disk would.
    std::fs::create_dir_all(out.join("summary.json/x")).unwrap();
    let args = ["solve", "tests/scenes/good/tiny.toml", "--out", s(&out)];
    let failed = suspflow(&args);
    assert!(!failed.status.success(), "{}", stderr(&failed));
    assert!(!out.join("profile.csv").exists(), "{}", stderr(&failed));
    std::fs::remove_dir_all(out.join("summary.json")).unwrap();
    assert_ok(&suspflow(&args));
    std::fs::remove_dir_all(&dir).ok();
}
