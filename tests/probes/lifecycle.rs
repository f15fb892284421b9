//! Class 3: work neither lost nor repeated; checks that can be made first, made first.
use crate::common::{assert_ok, s, scratch, stderr, suspflow};
use crate::{refused_with, scene_file};

/// The `Step=` of every frame of an extended XYZ file.
fn frame_steps(text: &str) -> Vec<u64> {
    text.lines()
        .filter_map(|l| l.split(" Step=").nth(1))
        .map(|rest| rest.split(' ').next().unwrap().parse().unwrap())
        .collect()
}

/// A run killed after its last checkpoint had written frames the resumed run writes again:
/// the resumed run cuts them, so that time never runs backwards and no frame is there twice
/// (before: appended after them, steps 16..20 twice). The kill is mimicked by appending the
/// frames such a run leaves: copies of the last ones.
#[test]
fn frames_written_after_the_checkpoint_are_not_kept_twice_on_resume() {
    let dir = scratch("frames-resume");
    let tiny = std::fs::read_to_string("tests/scenes/good/tiny.toml").unwrap();
    let short = scene_file(&dir, "short", &tiny);
    let out = dir.join("run");
    let run = |scene: &std::path::Path, resume: bool| {
        let mut args = vec!["simulate", s(scene), "--out", s(&out), "--snapshot", "1"];
        if resume {
            args.push("--resume");
        }
        suspflow(&args)
    };
    assert_ok(&run(&short, false));
    let frames = out.join("frames.xyz");
    let text = std::fs::read_to_string(&frames).unwrap();
    let first = frame_steps(&text);
    // The last two frames again, as a run killed after its checkpoint would leave them.
    let lines: Vec<&str> = text.lines().collect();
    let per_frame = lines.len() / first.len();
    let tail = lines[lines.len() - 2 * per_frame..].join("\n") + "\n";
    std::fs::write(&frames, text.clone() + &tail).unwrap();
    // The same scene, twice the snapshots (blocks in proportion): continues the run.
    let longer = scene_file(
        &dir,
        "longer",
        &tiny
            .replace("snapshots = 40", "snapshots = 80")
            .replace("blocks = 4", "blocks = 8"),
    );
    assert_ok(&run(&longer, true));
    let steps = frame_steps(&std::fs::read_to_string(&frames).unwrap());
    assert!(steps.len() > first.len(), "{steps:?}");
    assert!(
        steps.windows(2).all(|w| w[0] < w[1]),
        "frames out of order after resume: {steps:?}"
    );
    assert_eq!(steps[..first.len()], first[..]);
    std::fs::remove_dir_all(&dir).ok();
}

/// `green-kubo` with an `--out` that cannot be made is refused before the run (it held
/// before this pass: the lock comes before the run).
#[test]
fn green_kubo_refuses_an_out_it_cannot_make_before_running() {
    let dir = scratch("gk-out");
    std::fs::write(dir.join("file"), "x").unwrap();
    let started = std::time::Instant::now();
    let out = suspflow(&[
        "green-kubo",
        "tests/scenes/good/tiny_brownian.toml",
        "--out",
        s(&dir.join("file/gk")),
        "--max-lag",
        "1",
    ]);
    assert!(refused_with(&out, "file/gk"), "{}", stderr(&out));
    assert!(started.elapsed().as_secs_f64() < 5.0);
    std::fs::remove_dir_all(&dir).ok();
}
