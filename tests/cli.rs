//! End-to-end tests of the `suspflow` command on tiny scenes.
mod common;

use common::{assert_ok, read_csv, root, s, scratch, stderr, suspflow, suspflow_with_env};
use std::path::{Path, PathBuf};
use std::process::Command;

fn scenes_in(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

#[test]
fn bad_scenes_are_refused_naming_the_field() {
    let bad = scenes_in(&root().join("tests/scenes/bad"));
    assert!(bad.len() >= 10);
    let out_dir = scratch("bad");
    for scene in bad {
        let text = std::fs::read_to_string(&scene).unwrap();
        let expect = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# expect: "))
            .expect("first line names the expected message");
        // With RUST_BACKTRACE set, as on many developers' machines: the error is still a
        // message, not a stack backtrace.
        let out = suspflow_with_env(
            &["simulate", s(&scene), "--out", s(&out_dir)],
            &[("RUST_BACKTRACE", "1")],
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{} was accepted", scene.display());
        assert!(
            !stderr.to_lowercase().contains("backtrace"),
            "{} printed a backtrace:\n{stderr}",
            scene.display()
        );
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

/// `--version` names the commit the binary was built from, as every result records it.
#[test]
fn version_names_the_commit() {
    let out = suspflow(&["--version"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.starts_with("suspflow 0.1.0+"),
        "{text}"
    );
    assert!(!text.contains("unknown"), "{text}");
}

#[test]
fn shipped_scenes_are_valid() {
    let mut scenes = scenes_in(&root().join("scenes"));
    scenes.extend(scenes_in(&root().join("tests/scenes/good")));
    assert!(scenes.iter().any(|p| p.ends_with("quick.toml")));
    for scene in scenes {
        // --check writes nothing, so it needs no --out.
        let out = suspflow(&["simulate", scene.to_str().unwrap(), "--check"]);
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
        assert!(stdout.contains("memory: about "), "{stdout}");
    }
}

/// The bad scenes are refused by --check as well as by a run.
#[test]
fn check_refuses_what_a_run_would_refuse() {
    for (scene, expect) in [
        ("profile_zero.toml", "has no shear"),
        ("forces_all_off.toml", "all off"),
        (
            "box_too_large_for_memory.toml",
            "of memory, more than this machine's",
        ),
    ] {
        let path = root().join("tests/scenes/bad").join(scene);
        let out = suspflow(&["simulate", path.to_str().unwrap(), "--check"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains(expect),
            "{scene}: {stderr}"
        );
    }
}

#[test]
fn bench_refuses_bad_options_naming_them() {
    for (args, expect) in [
        (&["--steps", "0"][..], "--steps <STEPS>"),
        (&["--skin", "NaN"][..], "`NaN` is not a finite number >= 0"),
        (&["--skin=-1"][..], "`-1` is not a finite number >= 0"),
        (
            &["--n", "0"][..],
            "--n 0: too few particles for the bench box",
        ),
        (&["--n", "10"][..], "--n 10: too few particles"),
        (&["--n", "100"][..], "--n 100: too few particles"),
    ] {
        let mut all = vec!["bench", "--threads", "1", "--warmup", "0"];
        if args[0] != "--steps" {
            all.extend(["--steps", "1"]);
        }
        all.extend_from_slice(args);
        let out = suspflow(&all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} accepted");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("scene field"),
            "{args:?} names an internal field: {stderr}"
        );
    }
    // The smallest --n the message offers is accepted.
    let out = suspflow(&["bench", "--n", "100", "--steps", "1", "--warmup", "0"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let smallest = stderr
        .split("use --n ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .unwrap_or_else(|| panic!("{stderr}"));
    let out = suspflow(&[
        "bench",
        "--n",
        smallest,
        "--threads",
        "1",
        "--steps",
        "1",
        "--warmup",
        "0",
    ]);
    assert_ok(&out);
}

#[test]
fn golden_runs_match_and_write_every_output() {
    for (scene, golden, dt_limit) in [
        ("golden", "golden_profile.csv", "friction"),
        (
            "golden_explicit",
            "golden_explicit_profile.csv",
            "lubrication",
        ),
    ] {
        golden_run(scene, golden, dt_limit);
    }
}

/// Runs `tests/scenes/good/<scene>.toml` and compares its profile with `tests/golden/<golden>`
/// (`UPDATE_GOLDEN=1` rewrites it); its dt must be set by `dt_limit`.
fn golden_run(scene: &str, golden: &str, dt_limit: &str) {
    let out_dir = scratch(scene);
    let scene_path = format!("tests/scenes/good/{scene}.toml");
    let out = suspflow(&[
        "simulate",
        &scene_path,
        "--out",
        out_dir.to_str().unwrap(),
        "--threads",
        "1",
        "--snapshot",
        "4",
    ]);
    assert_ok(&out);
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
        "stress_checks",
    ] {
        assert!(!summary[key].is_null(), "summary.json lacks {key}");
    }
    assert_eq!(summary["observables"]["stress"], "pairs");
    assert_eq!(summary["observables"]["theta"], "local-window");
    assert_eq!(summary["dt_limit"], dt_limit);

    let frames = std::fs::read_to_string(out_dir.join("frames.xyz")).unwrap();
    let n = summary["n_particles"].as_u64().unwrap() as usize;
    let snapshots = 4 * 2 + 8; // 4 windows of 2 snapshots, then 8 averaged
    assert_eq!(frames.lines().count(), (snapshots / 4) * (n + 2));

    let produced = out_dir.join("profile.csv");
    let golden = root().join("tests/golden").join(golden);
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

    // The conventions table recomputes every option from the run's snapshot sums.
    let out = suspflow(&["conventions", out_dir.to_str().unwrap()]);
    assert_ok(&out);
    let table = String::from_utf8_lossy(&out.stdout);
    for option in [
        "stress = \"pairs+drag\"",
        "stress = \"pairs+drag+solvent\"",
        "theta = \"interpolated-rms\"",
        "delta_v = \"bin-centre\"",
        "gdot = \"centred\"",
        &format!("| {scene} | 8 |"),
    ] {
        assert!(table.contains(option), "no `{option}` in\n{table}");
    }
    // A directory without a finished run is named in the error.
    let empty = scratch("conventions-empty");
    std::fs::create_dir_all(&empty).unwrap();
    let out = suspflow(&["conventions", empty.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("a finished run?"),
        "{stderr}"
    );
    // `conventions WORK/*` of a work directory: a lock file and a folder without a run beside
    // the run are skipped with a note (issue 31, 16.17); a file alone is refused as a file.
    let lock = scratch("conventions-lock");
    std::fs::create_dir_all(&lock).unwrap();
    let lock_file = lock.join("generate.lock");
    std::fs::write(&lock_file, "").unwrap();
    let out = suspflow(&[
        "conventions",
        out_dir.to_str().unwrap(),
        lock_file.to_str().unwrap(),
        empty.to_str().unwrap(),
    ]);
    assert_ok(&out);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("skipping") && stderr.contains("generate.lock: a file, not a run folder"),
        "{stderr}"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains(&format!("| {scene} | 8 |")));
    let out = suspflow(&["conventions", lock_file.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("generate.lock is a file, not a run folder"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&lock).ok();
    std::fs::remove_dir_all(&empty).ok();
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
        "20",
        "--json",
    ]);
    assert_ok(&out);
    let records: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let r = &records[0];
    assert_eq!(r["threads"], 1);
    assert_eq!(r["lubrication"], true);
    assert!(r["n"].as_u64().unwrap().abs_diff(1000) <= 2);
    assert!(r["particle_steps_per_s"].as_f64().unwrap() > 0.0);
    // The stages are timed inside the loop: together they are most of it, never more.
    for r in records.as_array().unwrap() {
        let stages = &r["stages"];
        let staged: f64 = ["neighbours_s", "forces_s", "integration_s"]
            .iter()
            .map(|k| stages[k].as_f64().unwrap())
            .sum();
        let loop_s = r["loop_s"].as_f64().unwrap();
        assert!(staged > 0.5 * loop_s && staged <= loop_s, "{r}");
        // Only the implicit step has a solve to take apart.
        let explicit = r["integrator"] == "explicit";
        assert_eq!(r["solve_passes"].is_null(), explicit, "{r}");
    }
}

#[test]
fn bench_takes_the_solve_apart() {
    // Above the size at which the particles are split into one range per thread.
    let out = suspflow(&[
        "bench",
        "--n",
        "2400",
        "--threads",
        "1,2",
        "--integrator",
        "implicit",
        // About 10 implicit steps.
        "--steps",
        "1600",
        "--warmup",
        "20",
        "--json",
    ]);
    assert_ok(&out);
    let records: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for r in records.as_array().unwrap() {
        let passes = &r["solve_passes"];
        let [work, busiest, wall] =
            ["work_s", "longest_s", "wall_s"].map(|k| passes[k].as_f64().unwrap());
        // The passes are timed apart from the integration stage, inside it: they are most
        // of it and never more; a range's work lies inside its pass.
        let integration = r["stages"]["integration_s"].as_f64().unwrap();
        assert!(wall > 0.5 * integration && wall <= integration, "{r}");
        assert!(busiest > 0.0 && busiest <= wall, "{r}");
        match r["threads"].as_u64().unwrap() {
            1 => assert_eq!(work, busiest, "one range: {r}"),
            _ => assert!(work > busiest && busiest >= 0.5 * work, "two ranges: {r}"),
        }
    }
}

/// Number of extended-XYZ frames in `path`.
fn frames_in(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().filter(|l| l.starts_with("Lattice=")).count()
}

#[test]
fn simulate_keeps_earlier_runs_and_resume_appends_frames() {
    let dir = scratch("overwrite");
    std::fs::create_dir_all(&dir).unwrap();
    // The tiny scene with 200 averaged snapshots: long enough to interrupt (4 windows of
    // 10 snapshots, then 200).
    let scene = dir.join("long.toml");
    let tiny = std::fs::read_to_string(root().join("tests/scenes/good/tiny.toml")).unwrap();
    std::fs::write(&scene, tiny.replace("snapshots = 40", "snapshots = 200")).unwrap();
    let out = dir.join("run");
    let (scene_arg, out_arg) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let mut child = Command::new(env!("CARGO_BIN_EXE_suspflow"))
        .args([
            "simulate",
            scene_arg,
            "--out",
            out_arg,
            "--snapshot",
            "10",
            "--threads",
            "1",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while !out.join("frames.xyz").exists() || frames_in(&out.join("frames.xyz")) < 3 {
        assert!(started.elapsed().as_secs() < 60, "no frames written");
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before the interrupt"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(!child.wait().unwrap().success());
    assert!(out.join("checkpoint.json").exists());
    let before = std::fs::read_to_string(out.join("frames.xyz")).unwrap();

    // Without --resume or --force the checkpoint is not overwritten.
    let again = suspflow(&["simulate", scene_arg, "--out", out_arg]);
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(
        !again.status.success()
            && stderr.contains("checkpoint.json already exists")
            && stderr.contains("--resume continues it")
            && stderr.contains("--force"),
        "{stderr}"
    );

    // --resume appends the remaining frames to those written before the interrupt.
    let resumed = suspflow(&[
        "simulate",
        scene_arg,
        "--out",
        out_arg,
        "--snapshot",
        "10",
        "--resume",
        "--threads",
        "1",
    ]);
    assert_ok(&resumed);
    let after = std::fs::read_to_string(out.join("frames.xyz")).unwrap();
    assert!(
        after.starts_with(&before),
        "frames before the interrupt were lost"
    );
    assert_eq!(frames_in(&out.join("frames.xyz")), (40 + 200) / 10);

    // A finished run is not overwritten either, unless with --force.
    std::fs::remove_file(out.join("checkpoint.json")).ok();
    let again = suspflow(&["simulate", scene_arg, "--out", out_arg]);
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(
        stderr.contains("profile.csv already exists (the result of an earlier run)"),
        "{stderr}"
    );
    let forced = suspflow(&[
        "simulate",
        "tests/scenes/good/tiny.toml",
        "--out",
        out_arg,
        "--force",
    ]);
    assert_ok(&forced);

    // An --out that is a file is named as such.
    let file = dir.join("afile");
    std::fs::write(&file, "x").unwrap();
    let o = suspflow(&[
        "simulate",
        "tests/scenes/good/tiny.toml",
        "--out",
        file.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("is an existing file; give a directory"),
        "{stderr}"
    );
    // --snapshot 0 would never write a frame.
    let o = suspflow(&[
        "simulate",
        "tests/scenes/good/tiny.toml",
        "--check",
        "--snapshot",
        "0",
    ]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("--snapshot <N>"));
    std::fs::remove_dir_all(&dir).ok();
}

/// Runs `grid` with `generate` (two runs at a time) into `dir/runs`, its dataset at
/// `dir/bins.csv`; returns the work directory.
fn generate_grid(grid: &str, dir: &Path) -> PathBuf {
    let runs = dir.join("runs");
    assert_ok(&suspflow(&[
        "generate",
        grid,
        "--out",
        dir.join("bins.csv").to_str().unwrap(),
        "--work",
        runs.to_str().unwrap(),
        "--jobs",
        "2",
        "--threads",
        "1",
    ]));
    runs
}

/// `suspflow flow-curves GRID --runs RUNS --out OUT`.
fn flow_curves(grid: &str, runs: &Path, out: &Path) -> std::process::Output {
    suspflow(&[
        "flow-curves",
        grid,
        "--runs",
        runs.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn flow_curves_fit_a_generated_shear_grid_and_refuse_other_grids() {
    let dir = scratch("flow-curves");
    let runs = generate_grid("tests/grids/tiny_shear.toml", &dir);
    let out = dir.join("report");
    let flow_curves = |grid: &str| flow_curves(grid, &runs, &out);
    assert_ok(&flow_curves("tests/grids/tiny_shear.toml"));
    let (header, rows) = read_csv(&out.join("flow_curves.csv"));
    assert_eq!(rows.len(), 6);
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    for row in &rows {
        let eta_r: f64 = row[column("eta_r")].parse().unwrap();
        let bins: f64 = row[column("eta_r_bins")].parse().unwrap();
        // Under the default stress convention (pair stresslets) the bins' stress sums to
        // the box's (an identity of the two sums, checked to round-off).
        assert!(eta_r > 1.0, "{row:?}");
        assert!((bins - eta_r).abs() < 1e-9 * bins, "{row:?}");
    }
    let readme = std::fs::read_to_string(out.join("README.md")).unwrap();
    assert!(readme.contains("| pair stresslets (box) | 0.") && readme.contains("seed 2:"));
    for svg in ["eta_r.svg", "mu_J.svg"] {
        assert!(std::fs::read_to_string(out.join(svg))
            .unwrap()
            .contains("seeds&apos; law"));
    }
    let again = flow_curves("tests/grids/tiny_shear.toml");
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(
        !again.status.success()
            && stderr.contains("README.md already exists (an earlier flow-curve result)"),
        "{stderr}"
    );
    // Issue 31, class 13: the same grid at another shear rate is not fitted over these runs
    // (eta_r would be halved).
    let other_rate = dir.join("tiny_shear.toml");
    let grid = std::fs::read_to_string(root().join("tests/grids/tiny_shear.toml")).unwrap();
    std::fs::write(
        &other_rate,
        grid.replace("shear_rate = 0.02", "shear_rate = 0.01"),
    )
    .unwrap();
    let refused = flow_curves(other_rate.to_str().unwrap());
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success()
            && stderr.contains("the run there was not made for scene tiny_shear_000"),
        "{stderr}"
    );
    let refused = flow_curves("tests/grids/tiny.toml");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && stderr.contains("has no fluid.shear_rate"),
        "{stderr}"
    );
    // The grid run in two shards, each in its own work folder (as a SLURM array runs it):
    // the flow curves of both folders are those of the whole grid run at once, and a folder
    // given twice is refused (its runs would count twice).
    let shards: Vec<PathBuf> = (0..2)
        .map(|i| {
            let work = dir.join(format!("runs.s{i}"));
            assert_ok(&suspflow(&[
                "generate",
                "tests/grids/tiny_shear.toml",
                "--out",
                dir.join(format!("bins_{i}.csv")).to_str().unwrap(),
                "--work",
                work.to_str().unwrap(),
                "--shard",
                &format!("{i}/2"),
                "--jobs",
                "2",
                "--threads",
                "1",
            ]));
            work
        })
        .collect();
    let joined = dir.join("joined");
    let folders: Vec<&str> = shards.iter().map(|s| s.to_str().unwrap()).collect();
    let with_runs = |runs: &[&str]| {
        let mut a = vec!["flow-curves", "tests/grids/tiny_shear.toml", "--runs"];
        a.extend_from_slice(runs);
        a.extend_from_slice(&["--out", joined.to_str().unwrap(), "--force"]);
        suspflow(&a)
    };
    assert_ok(&with_runs(&folders));
    assert_eq!(
        std::fs::read_to_string(joined.join("flow_curves.csv")).unwrap(),
        std::fs::read_to_string(out.join("flow_curves.csv")).unwrap()
    );
    let readme = std::fs::read_to_string(joined.join("README.md")).unwrap();
    // It names the parts' work folders, not a shard numbering it cannot know.
    assert!(
        readme.contains("--shard I/N")
            && folders
                .iter()
                .all(|f| readme.contains(&format!("#   {f}\n"))),
        "{readme}"
    );
    let twice = with_runs(&[folders[0], folders[1], folders[0]]);
    let stderr = String::from_utf8_lossy(&twice.stderr);
    assert!(
        !twice.status.success() && stderr.contains("finished here and in"),
        "{stderr}"
    );
    // Part of the grid run again (the second shard) replaces the table's lines of its
    // scenes: marked "old" in an earlier table, only those lines take the runs' code
    // version; every line keeps its grid place and its numbers (the same code ran both).
    let (header, rows) = read_csv(&out.join("flow_curves.csv"));
    let version = header.iter().position(|h| h == "code_version").unwrap();
    let earlier = dir.join("earlier.csv");
    let mut text = header.join(",") + "\n";
    for row in &rows {
        let mut row = row.clone();
        row[version] = "old".into();
        text += &(row.join(",") + "\n");
    }
    std::fs::write(&earlier, text).unwrap();
    let updated = dir.join("updated");
    assert_ok(&suspflow(&[
        "flow-curves",
        "tests/grids/tiny_shear.toml",
        "--table",
        earlier.to_str().unwrap(),
        "--runs",
        folders[1],
        "--out",
        updated.to_str().unwrap(),
    ]));
    let rerun: Vec<String> = std::fs::read_dir(&shards[1])
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            name.split_once("_seed").map(|(id, _)| id.to_owned())
        })
        .collect();
    assert_eq!(rerun.len(), 3, "{rerun:?}");
    let (_, merged) = read_csv(&updated.join("flow_curves.csv"));
    assert_eq!(merged.len(), rows.len());
    for (line, row) in merged.iter().zip(&rows) {
        assert_eq!(line[0], row[0], "grid order");
        let again = rerun.contains(&line[0]);
        assert_eq!(line[version] != "old", again, "{line:?}");
        assert_eq!(line[..version], row[..version], "{line:?}");
    }
    let readme = std::fs::read_to_string(updated.join("README.md")).unwrap();
    assert!(
        readme.contains(&format!(
            "--table {} --runs {}",
            earlier.display(),
            folders[1]
        )) && readme.contains("in place of its lines of the same scenes"),
        "{readme}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 28: the Green-Kubo Brownian viscosity of an unsheared scene is positive, its running
/// integral starts at zero, and sheared scenes or spans too short for the lag are refused
/// before anything runs.
#[test]
fn green_kubo_integrates_an_equilibrium_run_and_refuses_what_it_cannot() {
    let dir = scratch("green-kubo");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("eq.toml");
    let text = "box = { l_x = 10.0, l_y = 10.0, l_z = 10.0 }\n\
                particles = { phi = 0.3, rho = 0.5 }\nfluid = { kT = 0.2 }\n";
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("gk");
    let args = |extra: &[&str]| {
        let mut a = vec![
            "green-kubo",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        a.extend_from_slice(extra);
        suspflow(&a)
    };
    let ran = args(&[
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
    let stdout = String::from_utf8_lossy(&ran.stdout);
    assert!(stdout.contains("eta_B / eta = "), "{stdout}");
    // The result reads back as the type that wrote it, beside the scene it ran.
    let result = rheometry::GreenKuboResult::read(&out).unwrap();
    let eta_b = result.eta_brownian_over_eta;
    assert!(eta_b > 0.0 && eta_b.is_finite(), "{result:?}");
    assert!(result.code_version.starts_with("0.1.0+") && out.join("scene.toml").exists());
    let (header, rows) = read_csv(&out.join("green_kubo.csv"));
    assert_eq!(header[3], "running_eta_over_eta");
    assert_eq!(rows[0][3].parse::<f64>().unwrap(), 0.0);
    let short = args(&["--span", "1", "--max-lag", "0.5", "--force"]);
    let stderr = String::from_utf8_lossy(&short.stderr);
    assert!(
        !short.status.success() && stderr.contains("too few"),
        "{stderr}"
    );
    let sheared = text.replace("kT = 0.2", "kT = 0.2, shear_rate = 0.01");
    std::fs::write(&scene, sheared).unwrap();
    let refused = args(&["--force"]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && stderr.contains("unsheared"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A flow-curves run of a generated grid: the scratch directory, the report directory and
/// the per-run table.
struct FlowCurvesRun {
    dir: PathBuf,
    out: PathBuf,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl FlowCurvesRun {
    /// Generates `grid` in scratch directory `name` and runs flow-curves on it.
    fn of(grid: &str, name: &str) -> Self {
        let dir = scratch(name);
        let runs = generate_grid(grid, &dir);
        let out = dir.join("report");
        assert_ok(&flow_curves(grid, &runs, &out));
        let (header, rows) = read_csv(&out.join("flow_curves.csv"));
        // The table reads back as the type that wrote it.
        let typed = rheometry::FlowCurveRow::read_all(&out.join("flow_curves.csv")).unwrap();
        assert_eq!(typed.len(), rows.len());
        FlowCurvesRun {
            dir,
            out,
            header,
            rows,
        }
    }

    /// The number in column `name` of `row`.
    fn value(&self, row: &[String], name: &str) -> f64 {
        let column = self.header.iter().position(|h| h == name).unwrap();
        row[column].parse().unwrap()
    }

    fn readme(&self) -> String {
        std::fs::read_to_string(self.out.join("README.md")).unwrap()
    }
}

/// Issue 28: a grid over the Peclet number gives the parts of `eta_r` per run, a fit per
/// Peclet number and a figure of `eta_r(Pe)` per volume fraction.
#[test]
fn flow_curves_over_the_peclet_number_split_the_viscosity() {
    let run = FlowCurvesRun::of("tests/grids/tiny_brownian_shear.toml", "flow-curves-pe");
    assert_eq!(run.rows.len(), 6);
    let value = |row: &Vec<String>, name: &str| run.value(row, name);
    for row in &run.rows {
        let pe = value(row, "peclet");
        assert!(pe == 10.0 || pe == 1000.0, "{row:?}");
        assert_eq!(value(row, "mu_p"), 0.0);
        // kT from Pe at gdot = 0.01: Pe = 6 pi eta a^3 gdot / kT.
        let kt = value(row, "kT");
        assert!((6.0 * std::f64::consts::PI * 0.01 / kt / pe - 1.0).abs() < 1e-9);
        // The grid's density and the inertia-diffusion ratio rho kT / (eta^2 a) it sets.
        assert_eq!(value(row, "rho"), 0.5);
        assert!((value(row, "tau_i_over_tau_b") / (0.5 * kt) - 1.0).abs() < 1e-9);
        // Each run's step and code version, from its summary.json.
        assert!(value(row, "dt") > 0.0, "{row:?}");
        let version = &row[run.header.iter().position(|h| h == "code_version").unwrap()];
        assert!(version.starts_with(env!("CARGO_PKG_VERSION")), "{version}");
        // The box's eta_r is the contact and lubrication parts (identity of the split);
        // the structural Brownian part is positive (a shear-thinning stress) and beside it.
        let parts = value(row, "eta_r_contact") + value(row, "eta_r_hydrodynamic");
        let eta_r = value(row, "eta_r");
        assert!((parts - eta_r).abs() < 1e-9 * eta_r.abs(), "{row:?}");
        assert!(value(row, "eta_r_brownian") > 0.0, "{row:?}");
        assert!(value(row, "eta_r_se") > 0.0, "{row:?}");
    }
    let readme = run.readme();
    assert!(
        readme.contains("| mu_p = 0, Pe = 1.000e1 | pair stresslets (box) |"),
        "{readme}"
    );
    // Without --green-kubo that stress is not measured: no row of failed fits for it.
    assert!(
        !readme.contains("not fitted") && readme.contains("have no row"),
        "{readme}"
    );
    for phi in ["0.400", "0.480", "0.550"] {
        let svg = std::fs::read_to_string(run.out.join(format!("eta_r_Pe_phi{phi}.svg"))).unwrap();
        assert!(svg.contains("structural Brownian"), "phi {phi}");
    }
    // With a Green-Kubo result per volume fraction (written by hand: eta_B / eta = 2 +- 0.2
    // extrapolated at each realised phi), the seeds' Pe -> 0 construction is fitted at the lowest Pe and
    // drawn within its errors.
    let mut args: Vec<String> = [
        "flow-curves",
        "tests/grids/tiny_brownian_shear.toml",
        "--runs",
    ]
    .map(String::from)
    .to_vec();
    args.push(run.dir.join("runs").to_str().unwrap().to_owned());
    let with_gk = run.dir.join("with_gk");
    args.extend(["--out".to_owned(), with_gk.to_str().unwrap().to_owned()]);
    let mut phis: Vec<f64> = run.rows.iter().map(|r| value(r, "phi_actual")).collect();
    phis.sort_by(f64::total_cmp);
    phis.dedup();
    for (k, phi) in phis.iter().enumerate() {
        let gk = run.dir.join(format!("gk{k}"));
        std::fs::create_dir_all(&gk).unwrap();
        // A result as `green-kubo` writes it, by the type that writes it.
        let result = rheometry::GreenKuboResult {
            scene: format!("eq{k}"),
            n_particles: 100,
            phi_actual: *phi,
            kt: 0.1,
            tau_b: 10.0,
            eta_brownian_over_eta: 1.0,
            eta_brownian_over_eta_se: 0.1,
            extrapolated_eta_brownian_over_eta: 2.0,
            extrapolated_eta_brownian_over_eta_se: 0.2,
            relaxation_tau_b: 0.5,
            blocks: 10,
            warmup_tau_b: 5.0,
            span_tau_b: 100.0,
            max_lag_tau_b: 5.0,
            every_steps: 5,
            code_version: "test".into(),
            warnings: Vec::new(),
        };
        std::fs::write(
            gk.join("green_kubo.json"),
            serde_json::to_string(&result).unwrap(),
        )
        .unwrap();
        args.extend(["--green-kubo".to_owned(), gk.to_str().unwrap().to_owned()]);
    }
    assert_ok(&suspflow(
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    ));
    let readme = std::fs::read_to_string(with_gk.join("README.md")).unwrap();
    let drawn = readme
        .lines()
        .find(|l| {
            l.starts_with("| mu_p = 0, Pe = 1.000e1 | ")
                && l.contains(" ± ")
                && l.contains(" at 0.")
        })
        .unwrap_or_else(|| panic!("no drawn Green-Kubo fit in\n{readme}"));
    assert_eq!(drawn.matches(" ± ").count(), 3, "{drawn}");
    // Its first point: the seeds' mean hydrodynamic + drag viscosity at the lowest phi and
    // Pe, plus the Green-Kubo 2.
    let lowest: Vec<f64> = run
        .rows
        .iter()
        .filter(|r| value(r, "peclet") == 10.0 && value(r, "phi_actual") == phis[0])
        .map(|r| value(r, "eta_r_hydrodynamic") + value(r, "eta_r_drag"))
        .collect();
    let expected = lowest.iter().sum::<f64>() / lowest.len() as f64 + 2.0;
    assert!(
        drawn.contains(&format!("| {expected:.2} ± ")),
        "{expected} in {drawn}"
    );
    // Only the lowest Pe carries the Green-Kubo viscosity.
    assert!(
        !readme.contains("| mu_p = 0, Pe = 1.000e3 | hydrodynamic + drag"),
        "{readme}"
    );
    // Issue 54: the figures drawn again from the table alone (no runs) are those drawn from
    // the runs, to the byte: the table reads back every number the figures and fits use;
    // so is the README from its command on (the state points, the fits, and with the
    // Green-Kubo runs the seeds' Pe -> 0 estimate).
    let redrawn = run.dir.join("redrawn");
    let table = with_gk.join("flow_curves.csv");
    let mut again: Vec<&str> = args.iter().map(String::as_str).collect();
    let runs_at = again.iter().position(|a| *a == "--runs").unwrap();
    again.splice(runs_at..runs_at + 2, ["--table", table.to_str().unwrap()]);
    let out_at = again.iter().position(|a| *a == "--out").unwrap();
    again[out_at + 1] = redrawn.to_str().unwrap();
    assert_ok(&suspflow(&again));
    let mut figures: Vec<String> = std::fs::read_dir(&redrawn)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name != "run.lock")
        .collect();
    figures.sort();
    // eta_r, mu_J and one eta_r(Pe) per volume fraction, each as SVG and CSV, the README and
    // the table.
    assert_eq!(figures.len(), 2 * (2 + phis.len()) + 2, "{figures:?}");
    let again_readme = std::fs::read_to_string(redrawn.join("README.md")).unwrap();
    assert!(
        again_readme.contains(&format!("--table {}", table.display())),
        "{again_readme}"
    );
    let after_command = |text: &str| {
        text.split_once("Per state and volume fraction")
            .unwrap()
            .1
            .to_owned()
    };
    assert_eq!(after_command(&again_readme), after_command(&readme));
    // The table itself is written again as it was: this version's table has nothing to fill.
    for name in figures.iter().filter(|name| *name != "README.md") {
        assert_eq!(
            std::fs::read(redrawn.join(name)).unwrap(),
            std::fs::read(with_gk.join(name)).unwrap(),
            "{name}"
        );
    }
    // A table written before the contacts were columns gets them from the grid (the scenes'
    // k_n and xi_min, here the defaults 1e4 and 1e-3 no line wrote), every other cell as it
    // was; a line whose volume fraction is no longer its scene's is refused.
    let written = std::fs::read_to_string(&table).unwrap();
    let without_contacts: String = written
        .lines()
        .map(|line| line.rsplitn(3, ',').last().unwrap().to_owned() + "\n")
        .collect();
    assert!(without_contacts.starts_with("scene_id,") && !without_contacts.contains("k_n"));
    let old_dir = run.dir.join("old");
    std::fs::create_dir_all(&old_dir).unwrap();
    let old_table = old_dir.join("flow_curves.csv");
    std::fs::write(&old_table, &without_contacts).unwrap();
    let upgraded = run.dir.join("upgraded");
    let table_at = again.iter().position(|a| *a == "--table").unwrap();
    again[table_at + 1] = old_table.to_str().unwrap();
    again[out_at + 1] = upgraded.to_str().unwrap();
    assert_ok(&suspflow(&again));
    assert_eq!(
        std::fs::read_to_string(upgraded.join("flow_curves.csv")).unwrap(),
        written
    );
    let phi_at = written
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == "phi")
        .unwrap();
    let edited: String = without_contacts
        .lines()
        .enumerate()
        .map(|(k, line)| {
            let mut cells: Vec<String> = line.split(',').map(String::from).collect();
            if k == 1 {
                cells[phi_at] = "0.6".into();
            }
            cells.join(",") + "\n"
        })
        .collect();
    std::fs::write(&old_table, edited).unwrap();
    let edited_out = run.dir.join("edited");
    again[out_at + 1] = edited_out.to_str().unwrap();
    let refused = suspflow(&again);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && stderr.contains("has phi 0.6, the grid's scene 0.4"),
        "{stderr}"
    );
    // The table of another grid is refused, naming the scene the grid lacks.
    let refused = suspflow(&[
        "flow-curves",
        "tests/grids/tiny_shear.toml",
        "--table",
        table.to_str().unwrap(),
        "--out",
        run.dir.join("other").to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && stderr.contains("which grid `tiny_shear` does not have"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&run.dir).ok();
}

/// Issue 29: the flow curves of colloid-grain mixtures carry their composition and both
/// Peclet numbers (grains only here, so that the runs are tiny).
#[test]
fn flow_curves_of_a_mixture_tabulate_its_composition_and_peclet_numbers() {
    let run = FlowCurvesRun::of("tests/grids/tiny_grain_mixture.toml", "flow-curves-mixture");
    assert_eq!(run.rows.len(), 4);
    let value = |row: &Vec<String>, name: &str| run.value(row, name);
    for row in &run.rows {
        assert_eq!(value(row, "alpha"), 1.0);
        assert_eq!(value(row, "alpha_actual"), 1.0);
        let pe_c = value(row, "peclet_c");
        assert_eq!(pe_c, value(row, "peclet"));
        // a_cg = a_g = 5 at alpha = 1: Pe_cg = 125 Pe_c; kT from Pe_c with a_c = 1.
        assert!(
            (value(row, "peclet_cg") / pe_c - 125.0).abs() < 1e-9,
            "{row:?}"
        );
        let kt = value(row, "kT");
        assert!((6.0 * std::f64::consts::PI * 0.01 / kt / pe_c - 1.0).abs() < 1e-9);
    }
    // Two volume fractions per Peclet number: one sentence instead of a table of failures,
    // each state named with its composition.
    let readme = run.readme();
    assert!(
        !readme.contains("Fit of `eta_r")
            && readme.contains(
                "Not fitted, fewer than 3 volume fractions: mu_p = 0, Pe = 1.000e-1, alpha = 1; \
                 mu_p = 0, Pe = 1.000e1, alpha = 1."
            ),
        "{readme}"
    );
    std::fs::remove_dir_all(&run.dir).ok();
}

#[test]
fn coverage_draws_both_planes_and_tabulates_the_ranges_of_the_data() {
    let dir = scratch("coverage");
    std::fs::create_dir_all(&dir).unwrap();
    let train = dir.join("a.csv");
    let validate = dir.join("b.csv");
    std::fs::write(
        &train,
        "scene_id,profile,J,phi_loc,Theta,mu\ns,\"sin\",0.01,0.6,0.02,0.5\ns,\"sin\",0.2,0.45,0.1,\ns,\"sin\",0.05,0.52,0.04,1.5\n",
    )
    .unwrap();
    std::fs::write(
        &validate,
        "scene_id,profile,J,phi_loc,Theta\nv,\"cos\",0.003,0.62,0.011\n",
    )
    .unwrap();
    let plots = dir.join("plots");
    let out = suspflow(&[
        "coverage",
        train.to_str().unwrap(),
        validate.to_str().unwrap(),
        "--out",
        plots.to_str().unwrap(),
    ]);
    assert_ok(&out);
    // The same again: refused unless --force, the files of the first run kept.
    let again = |force: &[&str]| {
        let mut args = vec![
            "coverage",
            train.to_str().unwrap(),
            "--out",
            plots.to_str().unwrap(),
        ];
        args.extend_from_slice(force);
        suspflow(&args)
    };
    let refused = again(&[]);
    assert!(!refused.status.success());
    assert!(
        stderr(&refused).contains("coverage.svg already exists"),
        "{}",
        stderr(&refused)
    );
    let svg = std::fs::read_to_string(plots.join("coverage.svg")).unwrap();
    assert!(
        svg.contains("b.csv (1 rows)"),
        "the first figure was replaced"
    );
    for label in ["a.csv (3 rows)", "b.csv (1 rows)", "phi_loc", "Theta"] {
        assert!(svg.contains(label), "coverage.svg lacks {label}");
    }
    // Four points per panel, one circle each, plus the legend's two markers per panel.
    assert_eq!(svg.matches("<circle").count(), 2 * (4 + 2), "{svg}");
    let table = std::fs::read_to_string(plots.join("coverage.md")).unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains(&table));
    assert_ok(&again(&["--force"]));
    let row = |column: &str| {
        table
            .lines()
            .find(|l| l.starts_with(&format!("| `{column}` |")))
            .unwrap_or_else(|| panic!("no row {column}:\n{table}"))
            .to_string()
    };
    assert!(table.starts_with("| column | a.csv | b.csv |\n"), "{table}");
    assert_eq!(row("J"), "| `J` | [0.01, 0.2] | [0.003, 0.003] |");
    assert_eq!(row("phi_loc"), "| `phi_loc` | [0.45, 0.6] | [0.62, 0.62] |");
    assert_eq!(row("Theta"), "| `Theta` | [0.02, 0.1] | [0.011, 0.011] |");
    // An empty cell is counted, a column one file lacks is `-`, text columns are left out.
    assert_eq!(row("mu"), "| `mu` | [0.5, 1.5], 1 empty | - |");
    assert!(!table.contains("`profile`") && !table.contains("`scene_id`"));
}

/// Option values beyond what a command can do are refused before anything runs, naming
/// the option and the limit; negative numbers are read as values, not as flags.
#[test]
fn option_values_beyond_their_limits_are_refused() {
    let tiny = "tests/scenes/good/tiny.toml";
    let out = scratch("limits").join("out");
    let out = out.to_str().unwrap();
    for (args, expect) in [
        (
            &["simulate", tiny, "--out", out, "--threads", "100000"][..],
            "invalid value '100000' for '--threads <THREADS>': 100000 threads on",
        ),
        (
            &["simulate", tiny, "--out", out, "--threads", "-1"][..],
            "`-1` is not a thread count",
        ),
        (&["bench", "--threads", "1,100000"][..], "100000 threads on"),
        (
            &[
                "generate",
                "tests/grids/tiny.toml",
                "--out",
                out,
                "--jobs",
                "100000",
            ][..],
            "invalid value '100000' for '--jobs <JOBS>'",
        ),
        (
            &["bench", "--steps", "-5"][..],
            "invalid value '-5' for '--steps <STEPS>'",
        ),
        (
            &["bench-predict", "--rows", "100000000"][..],
            "invalid value '100000000' for '--rows <ROWS>': 100000000 is not in 1..=1000000",
        ),
        (
            &["report", "--name", "../x", "--out", out][..],
            "invalid value '../x' for '--name <NAME>': `../x` starts with '.'",
        ),
    ] {
        let result = suspflow(args);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(
            !result.status.success() && stderr.contains(expect),
            "{args:?}: {stderr}"
        );
    }
    assert!(!Path::new(out).exists(), "nothing written");
}

/// SIGTERM (a batch scheduler's time limit) stops a run with a checkpoint, as Ctrl-C does,
/// with the exit status of an interrupted run (75); a second `simulate` on the same `--out`
/// is refused while the first runs; a resumed run that finishes keeps its final state, so
/// that a plain re-run calls it finished and a longer run of its scene continues it.
#[test]
fn sigterm_checkpoints_a_run_held_by_its_lock_and_a_finished_run_can_be_extended() {
    let dir = scratch("sigterm");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("long.toml");
    let text = std::fs::read_to_string(root().join("tests/scenes/good/tiny.toml")).unwrap();
    std::fs::write(&scene, text.replace("snapshots = 40", "snapshots = 2000")).unwrap();
    let out = dir.join("run");
    let (scene_s, out_s) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let first = Command::new(env!("CARGO_BIN_EXE_suspflow"))
        .args(["simulate", scene_s, "--out", out_s])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    while !out.join("run.lock").exists() {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let second = suspflow(&["simulate", scene_s, "--out", out_s, "--force"]);
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(
        !second.status.success() && stderr.contains("is in use by another `suspflow simulate`"),
        "{stderr}"
    );
    // Past the handler's installation (right after the lock), inside the run.
    std::thread::sleep(std::time::Duration::from_millis(700));
    let pid = first.id().to_string();
    assert!(Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .unwrap()
        .success());
    let stopped = first.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&stopped.stderr);
    assert!(
        stopped.status.code() == Some(75) && stderr.contains("continue with --resume"),
        "{:?}: {stderr}",
        stopped.status
    );
    assert!(out.join("checkpoint.json").exists());
    assert_ok(&suspflow(&[
        "simulate", scene_s, "--out", out_s, "--resume",
    ]));
    assert!(out.join("profile.csv").exists() && out.join("scene.toml").exists());
    let rerun = suspflow(&["simulate", scene_s, "--out", out_s]);
    let stderr = String::from_utf8_lossy(&rerun.stderr);
    assert!(
        stderr.contains("(the result of an earlier run)"),
        "{stderr}"
    );
    // Twice the snapshots in twice the blocks: the finished run goes on.
    let longer = text
        .replace("snapshots = 40", "snapshots = 4000")
        .replace("blocks = 4", "blocks = 8");
    std::fs::write(&scene, longer).unwrap();
    let extended = suspflow(&["simulate", scene_s, "--out", out_s, "--resume"]);
    assert_ok(&extended);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["snapshots"], 4000);
    std::fs::remove_dir_all(&dir).ok();
}

/// Green-Kubo at rest has the lifecycle of every run: SIGTERM stops it with its checkpoint
/// (exit status 75) and `--resume` finishes it with the uninterrupted run's numbers, bit
/// for bit.
#[test]
fn green_kubo_resumes_bit_for_bit_after_sigterm() {
    let dir = scratch("green-kubo-sigterm");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("eq.toml");
    std::fs::write(
        &scene,
        "box = { l_x = 10.0, l_y = 10.0, l_z = 10.0 }\n\
         particles = { phi = 0.3, rho = 0.5 }\nfluid = { kT = 0.2 }\n",
    )
    .unwrap();
    let args = |out: &Path| {
        vec![
            "green-kubo".to_string(),
            scene.to_str().unwrap().to_string(),
            "--out".into(),
            out.to_str().unwrap().to_string(),
            "--warmup".into(),
            "1".into(),
            "--span".into(),
            "400".into(),
            "--max-lag".into(),
            "0.5".into(),
            "--threads".into(),
            "1".into(),
        ]
    };
    let whole = dir.join("whole");
    let a = args(&whole);
    assert_ok(&suspflow(&a.iter().map(String::as_str).collect::<Vec<_>>()));
    let stopped = dir.join("stopped");
    let child = Command::new(env!("CARGO_BIN_EXE_suspflow"))
        .args(args(&stopped))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    while !stopped.join("run.lock").exists() {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(800));
    assert!(Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let ended = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&ended.stderr);
    assert!(
        ended.status.code() == Some(75) && stderr.contains("continue with --resume"),
        "{:?}: {stderr}",
        ended.status
    );
    assert!(stopped.join("checkpoint.json").exists() && !stopped.join("green_kubo.json").exists());
    let mut resume = args(&stopped);
    resume.push("--resume".into());
    assert_ok(&suspflow(
        &resume.iter().map(String::as_str).collect::<Vec<_>>(),
    ));
    let read = |d: &Path| std::fs::read_to_string(d.join("green_kubo.csv")).unwrap();
    assert_eq!(
        read(&stopped),
        read(&whole),
        "the resumed correlation differs"
    );
    std::fs::remove_dir_all(&dir).ok();
}
