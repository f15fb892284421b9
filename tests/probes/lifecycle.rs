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

/// Resumes the run with `tiny`'s scene at twice the snapshots (blocks in proportion) and
/// checks that the frames, as `steps` reads them, continue `first` in order with none
/// twice; then removes `dir`.
fn resume_longer(
    dir: &std::path::Path,
    tiny: &str,
    run: &dyn Fn(&std::path::Path, bool) -> std::process::Output,
    first: &[u64],
    steps: impl Fn() -> Vec<u64>,
) {
    let longer = scene_file(
        dir,
        "longer",
        &tiny
            .replace("snapshots = 40", "snapshots = 80")
            .replace("blocks = 4", "blocks = 8"),
    );
    assert_ok(&run(&longer, true));
    let steps = steps();
    assert!(steps.len() > first.len(), "{steps:?}");
    assert!(
        steps.windows(2).all(|w| w[0] < w[1]),
        "frames out of order after resume: {steps:?}"
    );
    assert_eq!(steps[..first.len()], first[..]);
    std::fs::remove_dir_all(dir).ok();
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
    resume_longer(&dir, &tiny, &run, &first, || {
        frame_steps(&std::fs::read_to_string(&frames).unwrap())
    });
}

/// The `configuration/step` of every frame of a GSD file, read from its index (GSD file
/// layer 2: header words 1-4 are the index's place and room and the name list's place and
/// room; an index entry is frame u64, N u64, location i64, M u32, id u16, type, flags).
fn gsd_frame_steps(bytes: &[u8]) -> Vec<u64> {
    let word = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
    let (index, allocated, names) = (word(8) as usize, word(16) as usize, word(24) as usize);
    let step_id = bytes[names..names + 64 * word(32) as usize]
        .split(|&b| b == 0)
        .position(|name| name == b"configuration/step")
        .unwrap() as u16;
    (0..allocated)
        .map(|i| &bytes[index + 32 * i..index + 32 * (i + 1)])
        .take_while(|entry| entry[16..24] != [0; 8])
        .filter(|entry| u16::from_le_bytes([entry[28], entry[29]]) == step_id)
        .map(|entry| word(u64::from_le_bytes(entry[16..24].try_into().unwrap()) as usize))
        .collect()
}

/// The same for a GSD trajectory (before: the GSD file was not cut back, and the frames a
/// killed run wrote after its last checkpoint stayed, time running backwards). The kill is
/// mimicked by appending two frames of the scene's initial state (step 0) with the
/// simulator's own GSD writer.
#[test]
fn gsd_frames_written_after_the_checkpoint_are_not_kept_twice_on_resume() {
    let dir = scratch("gsd-resume");
    let tiny = std::fs::read_to_string("tests/scenes/good/tiny.toml").unwrap();
    let short = scene_file(&dir, "short", &tiny);
    let out = dir.join("run");
    let run = |scene: &std::path::Path, resume: bool| {
        let mut args = vec!["simulate", s(scene), "--out", s(&out), "--snapshot", "1"];
        args.extend(["--snapshot-format", "gsd"]);
        if resume {
            args.push("--resume");
        }
        suspflow(&args)
    };
    assert_ok(&run(&short, false));
    let frames = out.join("frames.gsd");
    let first = gsd_frame_steps(&std::fs::read(&frames).unwrap());
    assert!(
        first.len() > 2 && first.windows(2).all(|w| w[0] < w[1]),
        "{first:?}"
    );
    let scene = sim::Scene::from_path(&short, false).unwrap();
    let particles = sim::input::initial_state::initial_particles(&scene).unwrap();
    let stale = sim::integrate::simulation::Simulation::new(&scene, particles).unwrap();
    let file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&frames)
        .unwrap();
    for _ in 0..2 {
        sim::output::gsd::append_frame(&file, &stale).unwrap();
    }
    let killed = gsd_frame_steps(&std::fs::read(&frames).unwrap());
    assert_eq!(killed.len(), first.len() + 2);
    resume_longer(&dir, &tiny, &run, &first, || {
        gsd_frame_steps(&std::fs::read(&frames).unwrap())
    });
}

/// A resumed run whose `frames.gsd` is not a GSD file (overwritten, truncated) is refused
/// before it steps, naming the file (before: the whole run went, then "writing frames.gsd:
/// failed to fill whole buffer").
#[test]
fn a_resumed_run_refuses_a_gsd_file_it_cannot_continue_before_running() {
    let dir = scratch("gsd-junk");
    let tiny = std::fs::read_to_string("tests/scenes/good/tiny.toml").unwrap();
    let short = scene_file(&dir, "short", &tiny);
    let longer = scene_file(
        &dir,
        "longer",
        &tiny
            .replace("snapshots = 40", "snapshots = 80")
            .replace("blocks = 4", "blocks = 8"),
    );
    let out = dir.join("run");
    let run = |scene: &std::path::Path, resume: bool| {
        let mut args = vec!["simulate", s(scene), "--out", s(&out), "--snapshot", "5"];
        args.extend(["--snapshot-format", "gsd"]);
        if resume {
            args.push("--resume");
        }
        suspflow(&args)
    };
    assert_ok(&run(&short, false));
    let summary = std::fs::read(out.join("summary.json")).unwrap();
    std::fs::write(out.join("frames.gsd"), "junk").unwrap();
    let ran = run(&longer, true);
    assert!(
        refused_with(&ran, "frames.gsd: not a GSD file: 4 bytes")
            && stderr(&ran).contains("move it away"),
        "{}",
        stderr(&ran)
    );
    assert!(!stderr(&ran).contains("averaging"), "{}", stderr(&ran));
    assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), summary);
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

/// `cross-validate --level 1.5` is refused before any fold is fitted (before: after the
/// whole cross-validation of the first mapping, when its intervals came).
#[test]
fn cross_validate_refuses_a_bad_level_before_fitting() {
    let dir = scratch("cv-level");
    let ran = suspflow(&[
        "cross-validate",
        "--data",
        "datasets/wide_plugs.ensemble.csv",
        "--models",
        "models",
        "--mapping",
        "mu",
        "--out",
        s(&dir.join("cv")),
        "--level",
        "1.5",
    ]);
    assert!(
        refused_with(&ran, "strictly between 0 and 1, not 1.5")
            && !stderr(&ran).contains("left out"),
        "{}",
        stderr(&ran)
    );
    std::fs::remove_dir_all(&dir).ok();
}
