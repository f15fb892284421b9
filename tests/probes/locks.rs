//! Class 4: one lock for every writer of an output folder (`run.lock`).
use crate::common::{s, scratch, stderr, suspflow};
use crate::refused_with;
use sim::output::file_lock::FileLock;

/// While another writer holds an output folder, each writer of one is refused naming the
/// holder's process (before: cross-validate, flow-curves, solve and train went on and
/// replaced each other's files; here they failed later, on their inputs, instead).
#[test]
fn every_writer_of_an_output_folder_is_refused_while_another_holds_it() {
    let dir = scratch("locks");
    let out = dir.join("out");
    let _held = FileLock::folder(&out, "`suspflow simulate`").unwrap();
    let no_models = dir.join("no-models");
    std::fs::write(out.join("mu.json"), "{}").unwrap();
    let commands: [Vec<&str>; 5] = [
        vec![
            "cross-validate",
            "--data",
            "datasets/validate.csv",
            "--models",
            s(&no_models),
        ],
        vec![
            "flow-curves",
            "tests/grids/tiny_shear.toml",
            "--runs",
            s(&dir),
        ],
        vec![
            "solve",
            "tests/scenes/good/tiny.toml",
            "--models",
            s(&no_models),
        ],
        // (An earlier model there: the command stops at once whichever check comes first.)
        vec![
            "train",
            "--data",
            "datasets/validate.csv",
            "--mapping",
            "mu",
        ],
        vec![
            "green-kubo",
            "tests/scenes/good/tiny_brownian.toml",
            "--max-lag",
            "1",
        ],
    ];
    for mut args in commands {
        args.extend(["--out", s(&out)]);
        let ran = suspflow(&args);
        assert!(
            refused_with(&ran, "is in use by another")
                && refused_with(&ran, &format!("process {}", std::process::id())),
            "{}: {}",
            args[0],
            stderr(&ran)
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
