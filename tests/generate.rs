//! End-to-end tests of `suspflow generate` and `suspflow merge` on grids of tiny scenes:
//! resume after a kill or Ctrl-C gives the same dataset, a failing scene is isolated, shards
//! merged equal the whole grid, and corrupt inputs to merge are refused naming the line;
//! replicas run apart and their ensemble table holds the means and between-replica errors.
mod common;

use common::{csv_column, numbers, root, scratch, stderr, suspflow};
use sim::run::batch::RunTableRow;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

fn generate(grid: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["generate", grid, "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    suspflow(&args)
}

/// The dataset of the tiny grid run once without interruption.
fn whole_tiny() -> &'static String {
    &whole_tiny_run().1
}

/// The dataset's path and text of the tiny grid run once without interruption.
fn whole_tiny_run() -> &'static (PathBuf, String) {
    static WHOLE: OnceLock<(PathBuf, String)> = OnceLock::new();
    WHOLE.get_or_init(|| {
        let out = scratch("whole").join("tiny.csv");
        let o = generate("tests/grids/tiny.toml", &out, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        // The run table reads back as the type that wrote it: every run done, in grid order.
        let table = RunTableRow::read_all(&out.with_extension("scenes.csv")).unwrap();
        assert_eq!(table.len(), 4);
        assert!(table
            .iter()
            .all(|r| r.status == "done" && r.steps.is_some()));
        assert_eq!((table[2].phi, table[2].seed), (0.5, 3));
        let text = std::fs::read_to_string(&out).unwrap();
        (out, text)
    })
}

/// `--check` brackets each run's particle-steps between its shortest warm-up and its
/// strain budget, and the shortest is what the tiny grid's runs take: their
/// `run.steady_chi2` of 1e9 passes the first steady test, after four windows of 0.2 strain
/// (and 0.8 of averaging: 1.6 strain of the budget's 5.8). Measured against the run table
/// of the runs themselves (steps x N), within 1 % for the rounding of windows to steps.
#[test]
fn check_brackets_the_particle_steps_the_runs_take() {
    let o = generate(
        "tests/grids/tiny.toml",
        &scratch("check-cost").join("tiny.csv"),
        &["--check"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    let rows: Vec<[f64; 2]> = text
        .lines()
        .filter(|l| l.starts_with("tiny_"))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            [f[8].parse().unwrap(), f[9].parse().unwrap()]
        })
        .collect();
    assert_eq!(rows.len(), 4, "{text}");
    let (out, _) = whole_tiny_run();
    let table = RunTableRow::read_all(&out.with_extension("scenes.csv")).unwrap();
    for ([least, most], run) in rows.iter().zip(&table) {
        // Printed to four digits.
        assert!(
            (most / least / (5.8 / 1.6) - 1.0).abs() < 1e-3,
            "{least} {most}"
        );
        let taken = run.steps.unwrap() as f64 * run.n_particles as f64;
        assert!(
            (taken / least - 1.0).abs() < 0.01,
            "{}: {taken:e} particle-steps taken, {least:e} estimated",
            run.scene_id
        );
    }
    assert!(text.contains("4 runs of 4 scenes"), "{text}");
}

#[test]
fn tiny_grid_gives_one_row_per_bin_per_scene_with_provenance() {
    let text = whole_tiny();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "scene_id",
        "profile",
        "L_y",
        "phi",
        "seed",
        "steady_strain",
        "momentum_residual",
        "code_version",
        "phi_loc",
        "phi_loc_se",
        "mu",
        "mu_se",
        "Theta",
        "Delta_v",
    ] {
        assert!(header.contains(&col), "dataset lacks `{col}`");
    }
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 4 * 6, "4 scenes x 6 bins");
    let ids: Vec<&str> = rows.iter().map(|r| r.split(',').next().unwrap()).collect();
    assert_eq!(ids[0], "tiny_000");
    assert_eq!(ids[23], "tiny_003");
    assert!(ids.windows(2).all(|w| w[0] <= w[1]), "scenes in grid order");
    // Scene 2 is phi = 0.5 with seed 3 (the last key of [vary], seed, varies fastest).
    let row = rows[12];
    assert!(
        row.starts_with("tiny_002,\"0.15*sin(2*pi*y/L)\",12,0.5,3,"),
        "{row}"
    );
}

/// Starts `generate` of the tiny grid into `out` in the background, output discarded.
fn spawn_tiny_generate(out: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_suspflow"))
        .args([
            "generate",
            "tests/grids/tiny.toml",
            "--out",
            out.to_str().unwrap(),
        ])
        .current_dir(root())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// Starts generate, waits until a scene has written a checkpoint, then stops it with
/// `signal`; the re-run must finish with exactly the uninterrupted dataset.
fn interrupted_then_resumed(name: &str, signal: &str) {
    let dir = scratch(name);
    let out = dir.join("tiny.csv");
    let mut child = spawn_tiny_generate(&out);
    let work = dir.join("tiny.csv.work");
    let started = Instant::now();
    let has_checkpoint = || {
        std::fs::read_dir(&work)
            .into_iter()
            .flatten()
            .flatten()
            .any(|e| e.path().join("checkpoint.json").exists())
    };
    while !has_checkpoint() {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no checkpoint written"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before any checkpoint"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "an interrupted generate must not report success"
    );
    let partial = std::fs::read_to_string(&out).unwrap();
    assert!(
        partial.lines().count() < whole_tiny().lines().count(),
        "the stop came too late to test resuming"
    );
    let o = generate("tests/grids/tiny.toml", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("(resuming)"),
        "a scene must resume from its checkpoint:\n{}",
        stderr(&o)
    );
    assert_eq!(
        &std::fs::read_to_string(&out).unwrap(),
        whole_tiny(),
        "resumed dataset differs"
    );
}

#[test]
fn resume_after_kill_gives_the_identical_dataset() {
    interrupted_then_resumed("kill", "-KILL");
}

#[test]
fn resume_after_ctrl_c_gives_the_identical_dataset() {
    interrupted_then_resumed("int", "-INT");
}

#[test]
fn a_failing_scene_is_recorded_and_does_not_stop_the_others() {
    let dir = scratch("fails");
    let out = dir.join("fails.csv");
    let o = generate("tests/grids/one_fails.toml", &out, &[]);
    assert!(
        !o.status.success(),
        "a failed scene must make the exit status non-zero"
    );
    let err = stderr(&o);
    assert!(
        err.contains("fails_001") && err.contains("blow-up"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let data = std::fs::read_to_string(&out).unwrap();
    assert_eq!(data.lines().count(), 1 + 6, "only the good scene's 6 bins");
    assert!(data.lines().skip(1).all(|l| l.starts_with("fails_000,")));
    let table = std::fs::read_to_string(dir.join("fails.scenes.csv")).unwrap();
    let failed = table.lines().find(|l| l.starts_with("fails_001,")).unwrap();
    assert!(failed.starts_with("fails_001,failed,\"blow-up"), "{failed}");
    // Quoted as CSV: every record, the failure reason included, has the header's fields.
    let mut reader = csv::Reader::from_reader(table.as_bytes());
    let columns = reader.headers().unwrap().len();
    let records: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(records.len(), 2);
    assert!(records.iter().all(|r| r.len() == columns));
    assert!(
        records[1][2].starts_with("blow-up at step"),
        "{:?}",
        &records[1]
    );
    // A re-run does not retry it (the failure is deterministic) and keeps the dataset.
    let again = generate("tests/grids/one_fails.toml", &out, &[]);
    assert!(
        stderr(&again).contains("2 already finished or failed"),
        "{}",
        stderr(&again)
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), data);
}

#[test]
fn shards_merged_equal_the_whole_grid() {
    let dir = scratch("shards");
    let mut parts = Vec::new();
    for i in 0..3 {
        let out = dir.join(format!("part{i}.csv"));
        let o = generate(
            "tests/grids/tiny.toml",
            &out,
            &["--shard", &format!("{i}/3"), "--jobs", "1"],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        parts.push(out);
    }
    // Merge in an order other than the grid's: the result is in grid order anyway.
    let merged = dir.join("merged.csv");
    let mut args = vec!["merge"];
    args.extend(parts.iter().rev().map(|p| p.to_str().unwrap()));
    args.extend(["--out", merged.to_str().unwrap()]);
    let o = suspflow(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(&std::fs::read_to_string(&merged).unwrap(), whole_tiny());
    // The shards' run tables merge into the whole grid's, all but the wall times.
    let without_wall_time = |table: PathBuf| {
        RunTableRow::read_all(&table)
            .unwrap()
            .into_iter()
            .map(|r| RunTableRow { wall_s: None, ..r })
            .collect::<Vec<_>>()
    };
    assert_eq!(
        without_wall_time(merged.with_extension("scenes.csv")),
        without_wall_time(whole_tiny_run().0.with_extension("scenes.csv"))
    );
    // Disjoint datasets whose run tables share a run are refused, naming both tables.
    let odd = dir.join("odd.csv");
    std::fs::copy(&parts[1], &odd).unwrap();
    std::fs::copy(
        parts[0].with_extension("scenes.csv"),
        odd.with_extension("scenes.csv"),
    )
    .unwrap();
    let o = suspflow(&[
        "merge",
        parts[0].to_str().unwrap(),
        odd.to_str().unwrap(),
        "--out",
        dir.join("odd_merged.csv").to_str().unwrap(),
    ]);
    assert!(
        !o.status.success()
            && stderr(&o).contains("is also in the run table")
            && !dir.join("odd_merged.csv").exists(),
        "{}",
        stderr(&o)
    );
    // An earlier merge is replaced only with --force.
    let o = suspflow(&args);
    assert!(
        !o.status.success() && stderr(&o).contains("merged.csv already exists"),
        "{}",
        stderr(&o)
    );
    args.push("--force");
    let o = suspflow(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    // Replaced by parts without run tables, the earlier merge's run table goes with it:
    // left, it would describe runs the new dataset may not hold.
    let bare = dir.join("bare.csv");
    std::fs::copy(&parts[0], &bare).unwrap();
    let o = suspflow(&[
        "merge",
        bare.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
        "--force",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !merged.with_extension("scenes.csv").exists(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );

    // The same part twice overlaps.
    let o = suspflow(&[
        "merge",
        parts[0].to_str().unwrap(),
        parts[0].to_str().unwrap(),
        "--out",
        dir.join("x.csv").to_str().unwrap(),
    ]);
    assert!(
        !o.status.success() && stderr(&o).contains("also in an earlier file"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn merge_names_the_line_of_a_truncated_or_corrupt_part() {
    let dir = scratch("corrupt");
    let text = whole_tiny();
    let truncated = dir.join("truncated.csv");
    std::fs::write(&truncated, &text[..text.len() / 2]).unwrap();
    let line = text[..text.len() / 2].lines().count();
    let o = suspflow(&[
        "merge",
        truncated.to_str().unwrap(),
        "--out",
        dir.join("a.csv").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains(&format!("line {line}")) && stderr(&o).contains("truncated.csv"),
        "{}",
        stderr(&o)
    );

    let corrupt = dir.join("corrupt.csv");
    std::fs::write(&corrupt, text.replacen(",1e0,", ",1e0x,", 1)).unwrap();
    let o = suspflow(&[
        "merge",
        corrupt.to_str().unwrap(),
        "--out",
        dir.join("b.csv").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("line 2, column `y`"), "{}", stderr(&o));
    assert!(!dir.join("b.csv").exists(), "nothing written on error");
}

/// Issue 31, class 9: the runs of two grids that share a scene name are not averaged as
/// replicas, and the refused merge writes nothing.
#[test]
fn merge_refuses_runs_of_another_scene_under_one_name_and_writes_nothing() {
    let dir = scratch("two_grids");
    let part = |name: &str, phi: &str, seed: u32| {
        let path = dir.join(name);
        let rows: String = ["1", "3"]
            .iter()
            .map(|y| format!("g_000,4,{phi},{seed},{y}\n"))
            .collect();
        std::fs::write(&path, format!("scene_id,L_y,phi,seed,y\n{rows}")).unwrap();
        path.to_str().unwrap().to_string()
    };
    let (a, b) = (part("a.csv", "0.45", 1), part("b.csv", "0.44", 2));
    let out = dir.join("all.csv");
    let o = suspflow(&["merge", &a, &b, "--out", out.to_str().unwrap()]);
    assert!(
        !o.status.success()
            && stderr(&o).contains("has phi = `0.44` where seed 1 of an earlier file has `0.45`"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists() && !dir.join("all.ensemble.csv").exists());
}

#[test]
fn bad_grids_are_refused_naming_the_problem() {
    let dir = scratch("badgrid");
    let cases = [
        ("name = \"g\"\n[scene]\nbox = { l_x = 8.0, l_y = 12.0, l_z = 8.0 }\nfluid = { profile = \"0.1*sin(2*pi*y/L)\" }\n[vary]\n\"particles.phi\" = [0.5, 0.9]\n", "scene g_001: scene field `particles.phi`"),
        ("name = \"g\"\n[scene]\nbox = { l_x = 8.0, l_y = 12.0, l_z = 8.0 }\nparticles = { phi = 0.5 }\nfluid = { profile = \"0.1*sin(2*pi*y/L)\" }\n[vary]\n\"particles.phy\" = [0.5]\n", "unknown field `phy`"),
        ("name = \"g\"\n[vary]\nseed = 3\n", "vary.\"seed\" must be a non-empty list"),
        ("name = \"g\"\n[vary]\nseed = [1]\n[[cases]]\nseed = 2\n", "both in [vary] and in a [[cases]]"),
    ];
    for (k, (text, expected)) in cases.iter().enumerate() {
        let grid = dir.join(format!("g{k}.toml"));
        std::fs::write(&grid, text).unwrap();
        let o = generate(grid.to_str().unwrap(), &dir.join("x.csv"), &["--check"]);
        assert!(!o.status.success(), "grid {k} accepted");
        assert!(stderr(&o).contains(expected), "grid {k}: {}", stderr(&o));
    }
}

#[test]
fn plot_draws_one_figure_per_scene() {
    let dir = scratch("plot");
    let data = dir.join("tiny.csv");
    std::fs::write(&data, whole_tiny()).unwrap();
    let o = suspflow(&[
        "plot",
        data.to_str().unwrap(),
        "--out",
        dir.join("plots").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..4 {
        let svg = std::fs::read_to_string(dir.join(format!("plots/tiny_00{k}.svg"))).unwrap();
        for q in ["phi_loc", "Delta_v", "u_inf"] {
            assert!(svg.contains(q), "tiny_00{k}.svg lacks {q}");
        }
    }
    // Drawn again into the same folder: refused, naming a figure, unless --force.
    let plots = dir.join("plots");
    let rerun = |force: bool| {
        let mut args = vec![
            "plot",
            data.to_str().unwrap(),
            "--out",
            plots.to_str().unwrap(),
        ];
        if force {
            args.push("--force");
        }
        suspflow(&args)
    };
    let o = rerun(false);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("tiny_000.svg already exists") && stderr(&o).contains("--force"),
        "{}",
        stderr(&o)
    );
    let o = rerun(true);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn compare_finds_a_profile_agrees_with_itself_and_not_with_another_scene() {
    let dir = scratch("compare");
    let lines: Vec<&str> = whole_tiny().lines().collect();
    let (a, b) = (dir.join("a.csv"), dir.join("b.csv"));
    std::fs::write(&a, format!("{}\n{}\n", lines[0], lines[1..7].join("\n"))).unwrap();
    std::fs::write(&b, format!("{}\n{}\n", lines[0], lines[13..19].join("\n"))).unwrap();
    let z2 = |x: &Path, y: &Path| -> f64 {
        let o = suspflow(&[
            "compare",
            x.to_str().unwrap(),
            y.to_str().unwrap(),
            "--column",
            "phi_loc",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let line = out
            .lines()
            .find(|l| l.starts_with("phi_loc"))
            .unwrap()
            .to_string();
        line.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    assert_eq!(z2(&a, &a), 0.0);
    // phi = 0.45 against phi = 0.5: far beyond the noise.
    assert!(z2(&a, &b) > 10.0, "{}", z2(&a, &b));
}

#[test]
fn generate_keeps_a_dataset_it_did_not_write_unless_forced() {
    let dir = scratch("foreign");
    let out = dir.join("mine.csv");
    std::fs::write(&out, "precious,data\n1,2\n").unwrap();
    let o = generate("tests/grids/tiny.toml", &out, &["--shard", "0/4"]);
    let err = stderr(&o);
    assert!(
        !o.status.success()
            && err.contains("mine.csv already exists (not written by this grid")
            && err.contains("--force"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        "precious,data\n1,2\n"
    );
    let o = generate(
        "tests/grids/tiny.toml",
        &out,
        &["--shard", "0/4", "--force"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // Once the grid has written it, re-running needs no --force.
    let o = generate("tests/grids/tiny.toml", &out, &["--shard", "0/4"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A directory as --out is named as such.
    let o = generate("tests/grids/tiny.toml", &dir, &[]);
    assert!(
        stderr(&o).contains("is a directory; give a file name"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_second_generate_on_the_same_output_is_refused_naming_the_first() {
    let dir = scratch("lock");
    let out = dir.join("tiny.csv");
    let mut first = spawn_tiny_generate(&out);
    let lock = dir.join("tiny.csv.work/generate.lock");
    let started = Instant::now();
    while std::fs::read_to_string(&lock)
        .unwrap_or_default()
        .is_empty()
    {
        assert!(started.elapsed() < Duration::from_secs(60), "no lock taken");
        std::thread::sleep(Duration::from_millis(10));
    }
    let second = generate("tests/grids/tiny.toml", &out, &[]);
    Command::new("kill")
        .args(["-INT", &first.id().to_string()])
        .status()
        .unwrap();
    let finished_first = first.wait().unwrap().success();
    let err = stderr(&second);
    assert!(
        finished_first
            || (!second.status.success()
                && err.contains("work folder")
                && err.contains("is in use by another `suspflow generate`")
                && err.contains(&format!("process {}", first.id()))),
        "{err}"
    );
    assert!(!err.contains("No such file"), "{err}");
}

#[test]
fn plot_refuses_scattered_or_unsafe_scene_ids() {
    let dir = scratch("plot-bad");
    let lines: Vec<&str> = whole_tiny().lines().collect();
    let plot = |name: &str, text: String| {
        let data = dir.join(name);
        std::fs::write(&data, text).unwrap();
        let o = suspflow(&[
            "plot",
            data.to_str().unwrap(),
            "--out",
            dir.join("plots").to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{name} accepted");
        stderr(&o)
    };
    // Scene tiny_000 again after tiny_001: one SVG would overwrite the other.
    let scattered = format!(
        "{}\n{}\n{}\n{}\n",
        lines[0],
        lines[1..7].join("\n"),
        lines[7..13].join("\n"),
        lines[1..7].join("\n")
    );
    let err = plot("scattered.csv", scattered);
    assert!(
        err.contains("data row 13: scene `tiny_000` appears again after other scenes"),
        "{err}"
    );
    let escaping =
        format!("{}\n{}\n", lines[0], lines[1..7].join("\n")).replace("tiny_000", "../../x");
    let err = plot("escaping.csv", escaping);
    assert!(err.contains("`../../x` starts with '.'"), "{err}");
    let empty = format!("{}\n{}\n", lines[0], lines[1..7].join("\n")).replace("tiny_000", "");
    let err = plot("empty.csv", empty);
    assert!(
        err.contains("data row 1, column `scene_id` is empty"),
        "{err}"
    );
    assert!(!dir.join("x.svg").exists() && !dir.join("plots/.svg").exists());
    // A byte-order mark before the header is read as nothing.
    let marked = dir.join("marked.csv");
    std::fs::write(
        &marked,
        format!("\u{feff}{}\n{}\n", lines[0], lines[1..7].join("\n")),
    )
    .unwrap();
    let o = suspflow(&[
        "plot",
        marked.to_str().unwrap(),
        "--out",
        dir.join("plots").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("plots/tiny_000.svg").exists());
}

#[test]
fn compare_refuses_several_scenes_bad_cells_and_negative_errors() {
    let dir = scratch("compare-bad");
    let lines: Vec<&str> = whole_tiny().lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let column = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let one = dir.join("one.csv");
    std::fs::write(&one, format!("{}\n{}\n", lines[0], lines[1..7].join("\n"))).unwrap();
    let compare = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let o = suspflow(&["compare", path.to_str().unwrap(), one.to_str().unwrap()]);
        assert!(!o.status.success(), "{name} accepted");
        stderr(&o)
    };
    let err = compare("all.csv", whole_tiny().clone());
    assert!(
        err.contains("holds 4 scenes (tiny_000, tiny_001, ...)"),
        "{err}"
    );
    // One cell of scene tiny_000 replaced: row 3 (data rows from 1).
    let with_cell = |name: &str, value: &str| {
        let mut rows: Vec<String> = lines[1..7].iter().map(|l| l.to_string()).collect();
        let mut cells: Vec<&str> = rows[2].split(',').collect();
        cells[column(name)] = value;
        rows[2] = cells.join(",");
        format!("{}\n{}\n", lines[0], rows.join("\n"))
    };
    for (value, what) in [
        ("NaN", "is not a finite number"),
        ("inf", "is not a finite number"),
    ] {
        let err = compare("nan.csv", with_cell("mu", value));
        assert!(
            err.contains(&format!("row 3, column `mu`: `{value}` {what}")),
            "{err}"
        );
    }
    let err = compare("negative.csv", with_cell("phi_loc_se", "-1e-3"));
    assert!(
        err.contains("row 3, column `phi_loc_se`: `-1e-3` is negative; a standard error cannot be"),
        "{err}"
    );
    let err = compare(
        "long.csv",
        with_cell("mu", &"9".repeat(500_000).replace("99", "9x")),
    );
    assert!(
        err.contains("... (500000 bytes)` is not a number") && !err.contains(&"9x".repeat(100)),
        "{}",
        &err[..err.len().min(300)]
    );
    // merge refuses a negative standard error too, naming the line.
    let negative = dir.join("negative.csv");
    let o = suspflow(&[
        "merge",
        negative.to_str().unwrap(),
        "--out",
        dir.join("m.csv").to_str().unwrap(),
    ]);
    assert!(
        stderr(&o).contains("line 4, column `phi_loc_se`: a standard error cannot be negative"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn replicas_run_apart_and_the_ensemble_table_averages_them() {
    let dir = scratch("replicas");
    let out = dir.join("reps.csv");
    let o = generate("tests/grids/replicas.toml", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        stdout.contains("reps.ensemble.csv") && stdout.contains("phi_loc"),
        "{stdout}"
    );
    let data = std::fs::read_to_string(&out).unwrap();
    // One row per bin per run: scene reps_000 with seeds 3, 4, 5, then reps_001 (seed 1).
    let ids = csv_column(&data, "scene_id");
    let seeds = csv_column(&data, "seed");
    assert_eq!(ids.len(), 4 * 6);
    let runs: Vec<(String, String)> = (0..4)
        .map(|k| (ids[6 * k].clone(), seeds[6 * k].clone()))
        .collect();
    let expected = [
        ("reps_000", "3"),
        ("reps_000", "4"),
        ("reps_000", "5"),
        ("reps_001", "1"),
    ];
    assert_eq!(runs, expected.map(|(a, b)| (a.to_string(), b.to_string())));
    assert!(dir
        .join("reps.csv.work/reps_000_seed4/profile.csv")
        .exists());

    // The ensemble: the mean and between-replica standard error of each bin of reps_000,
    // recomputed here from the dataset; reps_001 keeps its own batch-means error.
    let ensemble = std::fs::read_to_string(dir.join("reps.ensemble.csv")).unwrap();
    assert_eq!(
        csv_column(&ensemble, "replicas"),
        [vec!["3"; 6], vec!["1"; 6]].concat()
    );
    assert_eq!(
        csv_column(&ensemble, "se_from"),
        [vec!["replicas"; 6], vec!["batch_means"; 6]].concat()
    );
    for name in ["phi_loc", "mu", "Theta"] {
        let (x, se) = (numbers(&data, name), numbers(&data, &format!("{name}_se")));
        let (mean, mean_se) = (
            numbers(&ensemble, name),
            numbers(&ensemble, &format!("{name}_se")),
        );
        for bin in 0..6 {
            let v: Vec<f64> = (0..3).map(|k| x[6 * k + bin]).collect();
            let m = (v[0] + v[1] + v[2]) / 3.0;
            let s2 = ((v[0] - m).powi(2) + (v[1] - m).powi(2) + (v[2] - m).powi(2)) / 2.0;
            assert!((mean[bin] - m).abs() <= 1e-12 * m.abs(), "{name} bin {bin}");
            assert!(
                (mean_se[bin] - (s2 / 3.0).sqrt()).abs() <= 1e-9 * mean_se[bin],
                "{name} bin {bin}: {} vs {}",
                mean_se[bin],
                (s2 / 3.0).sqrt()
            );
            assert_eq!(
                (mean[6 + bin], mean_se[6 + bin]),
                (x[18 + bin], se[18 + bin])
            );
        }
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("reps.ensemble.json")).unwrap())
            .unwrap();
    assert_eq!(summary["runs"], 4);
    assert_eq!(summary["observables"].as_array().unwrap().len(), 11);

    // A re-run finds every run done and rewrites the same bytes.
    let again = generate("tests/grids/replicas.toml", &out, &[]);
    assert!(
        stderr(&again).contains("4 runs of 2 scenes, 4 already finished"),
        "{}",
        stderr(&again)
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("reps.ensemble.csv")).unwrap(),
        ensemble
    );

    // Shards split the runs and write no ensemble; merging them writes the same one.
    let mut parts = Vec::new();
    for i in 0..2 {
        let part = dir.join(format!("part{i}.csv"));
        let o = generate(
            "tests/grids/replicas.toml",
            &part,
            &["--shard", &format!("{i}/2")],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!dir.join(format!("part{i}.ensemble.csv")).exists());
        parts.push(part.to_str().unwrap().to_string());
    }
    let merged = dir.join("merged.csv");
    let o = suspflow(&[
        "merge",
        &parts[1],
        &parts[0],
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&merged).unwrap(), data);
    assert_eq!(
        std::fs::read_to_string(dir.join("merged.ensemble.csv")).unwrap(),
        ensemble
    );

    // plot draws each replica as its own series; compare refuses several replicas in a file.
    let o = suspflow(&[
        "plot",
        out.to_str().unwrap(),
        "--out",
        dir.join("plots").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(dir.join("plots/reps_000.svg")).unwrap();
    assert!(
        svg.contains("seed 3") && svg.contains("seed 5"),
        "no series per seed"
    );
    let lines: Vec<&str> = data.lines().collect();
    let scene_0 = dir.join("reps_000_runs.csv");
    std::fs::write(&scene_0, format!("{}\n", lines[..19].join("\n"))).unwrap();
    let o = suspflow(&[
        "compare",
        scene_0.to_str().unwrap(),
        scene_0.to_str().unwrap(),
    ]);
    assert!(
        !o.status.success() && stderr(&o).contains("holds 3 runs (seeds 3, 4, ...)"),
        "{}",
        stderr(&o)
    );

    // Training and validation take either table, and say which one they read.
    let stdout_of = |args: &[&str]| {
        let o = suspflow(args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let [ensemble_path, models, plots, run_models] =
        ["reps.ensemble.csv", "models", "plots", "run_models"].map(|f| dir.join(f));
    let [ensemble_path, models, plots, run_models] =
        [&ensemble_path, &models, &plots, &run_models].map(|p| p.to_str().unwrap());
    let stdout = stdout_of(&[
        "train",
        "--data",
        ensemble_path,
        "--out",
        models,
        "--no-tune",
    ]);
    assert!(
        stdout.contains("ensemble table: 2 scenes, means over 1-3 replicas"),
        "{stdout}"
    );
    let stdout = stdout_of(&[
        "validate",
        "--models",
        models,
        "--data",
        ensemble_path,
        "--plots",
        plots,
    ]);
    assert!(
        stdout.contains("ensemble table") && stdout.contains("target noise"),
        "{stdout}"
    );
    // The per-run table trains too, its replicas grouped as one scene.
    let out = out.to_str().unwrap();
    let stdout = stdout_of(&[
        "train",
        "--data",
        out,
        "--out",
        run_models,
        "--no-tune",
        "--mapping",
        "mu",
    ]);
    assert!(
        stdout.contains("per-run table: 4 runs of 2 scenes"),
        "{stdout}"
    );
}

#[test]
fn generate_keeps_an_ensemble_table_it_did_not_write_unless_forced() {
    let dir = scratch("foreign-ensemble");
    let out = dir.join("reps.csv");
    let theirs = dir.join("reps.ensemble.csv");
    std::fs::write(&theirs, "precious\n").unwrap();
    let o = generate("tests/grids/replicas.toml", &out, &["--check"]);
    assert!(o.status.success(), "--check writes nothing: {}", stderr(&o));
    let o = generate("tests/grids/replicas.toml", &out, &[]);
    assert!(
        !o.status.success() && stderr(&o).contains("reps.ensemble.csv already exists"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&theirs).unwrap(), "precious\n");
}
