//! The one lifecycle of every run (sim::run): a Green-Kubo run interrupted and resumed is
//! the uninterrupted run bit for bit, and a finished run extended (a longer span, more
//! snapshots, a larger strain budget) is the longer run bit for bit.
use sim::input::scene::Scene;
use sim::output::result_files::profile_rows;
use sim::run::green_kubo::{equilibrium_viscosity, GreenKuboRun};
use sim::run::{run, RunOptions};
use sim::SimError;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

fn test_scene(name: &str) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/scenes/good")
        .join(name);
    Scene::from_path(&path, false).unwrap()
}

/// A fresh folder for `name`'s checkpoint.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sim-lifecycle-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn on_one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(f)
}

/// A Green-Kubo run of the tiny Brownian scene: 1 tau_B of warm-up, `span` sampled.
fn plan(span: f64) -> GreenKuboRun {
    GreenKuboRun {
        warmup_tau_b: 0.2,
        span_tau_b: span,
        every: 5,
        max_lag_tau_b: 0.05,
        blocks: 4,
    }
}

/// The numbers of a Green-Kubo integral, to compare bit for bit.
fn numbers(gk: &sim::sampling::green_kubo::GreenKubo) -> (Vec<f64>, Vec<f64>, f64, f64) {
    (
        gk.correlation.clone(),
        gk.running.clone(),
        gk.viscosity,
        gk.viscosity_se,
    )
}

#[test]
fn green_kubo_resumes_bit_for_bit_and_extends_to_the_longer_run() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let scene = test_scene("tiny_brownian.toml");
    on_one_thread(|| {
        let plain = RunOptions::default();
        let whole = equilibrium_viscosity(&scene, plan(2.0), &plain, &mut |_, _| {}).unwrap();
        let longer = equilibrium_viscosity(&scene, plan(3.0), &plain, &mut |_, _| {}).unwrap();

        // Stopped in the warm-up and twice while sampling, resumed each time.
        let dir = folder("gk");
        let opts = RunOptions {
            checkpoint: Some(dir.join("checkpoint.json")),
            resume: true,
            interrupt: Some(&STOP),
            ..RunOptions::default()
        };
        for stop_at in [1, 40, 90] {
            STOP.store(false, Ordering::SeqCst);
            let mut seen = 0;
            let stopped = equilibrium_viscosity(&scene, plan(2.0), &opts, &mut |_, _| {
                seen += 1;
                if seen == stop_at {
                    STOP.store(true, Ordering::SeqCst);
                }
            });
            assert!(
                matches!(stopped, Err(SimError::Interrupted { .. })),
                "stop at sample {stop_at}: {:?}",
                stopped.map(|_| ())
            );
        }
        STOP.store(false, Ordering::SeqCst);
        let resumed = equilibrium_viscosity(&scene, plan(2.0), &opts, &mut |_, _| {}).unwrap();
        assert_eq!(numbers(&resumed), numbers(&whole));

        // The finished run, extended to the longer span.
        let extended = equilibrium_viscosity(&scene, plan(3.0), &opts, &mut |_, _| {}).unwrap();
        assert_eq!(numbers(&extended), numbers(&longer));
        // Another warm-up is another run.
        let other = GreenKuboRun {
            warmup_tau_b: 0.3,
            ..plan(3.0)
        };
        match equilibrium_viscosity(&scene, other, &opts, &mut |_, _| {}) {
            Err(SimError::CheckpointUnusable { message, .. }) => {
                assert!(message.contains("warm-up of 0.2 tau_B"), "{message}")
            }
            r => panic!("expected a refusal, got {:?}", r.map(|_| ())),
        }
        std::fs::remove_dir_all(&dir).ok();
    });
}

/// The tiny scene with `snapshots` in `blocks` blocks and the strain budget `max_strain`.
fn tiny(snapshots: usize, blocks: usize, max_strain: f64, steady_chi2: f64) -> Scene {
    let mut file = test_scene("tiny.toml").file;
    file.run.snapshots = snapshots;
    file.run.blocks = blocks;
    file.run.max_strain = max_strain;
    file.run.steady_chi2 = steady_chi2;
    Scene::from_file(file, false).unwrap()
}

fn rows(scene: &Scene, opts: &RunOptions) -> Result<String, SimError> {
    let out = run(scene, opts, &mut |_, _| {})?;
    Ok(profile_rows(scene, &out.profile, &out.summary))
}

#[test]
fn a_finished_run_extends_to_more_snapshots_and_a_larger_budget() {
    on_one_thread(|| {
        let plain = RunOptions::default();
        let dir = folder("steady");
        let opts = RunOptions {
            checkpoint: Some(dir.join("checkpoint.json")),
            resume: true,
            ..RunOptions::default()
        };
        // 40 snapshots in blocks of 10, extended to 80 in blocks of 10.
        rows(&tiny(40, 4, 5.0, 1e9), &opts).unwrap();
        let extended = rows(&tiny(80, 8, 5.0, 1e9), &opts).unwrap();
        assert_eq!(extended, rows(&tiny(80, 8, 5.0, 1e9), &plain).unwrap());
        // Another block length cannot be had from the blocks already summed.
        match rows(&tiny(160, 8, 5.0, 1e9), &opts) {
            Err(SimError::CheckpointUnusable { message, .. }) => {
                assert!(message.contains("blocks of 10"), "{message}")
            }
            r => panic!("expected a refusal, got {:?}", r.map(|_| ())),
        }
        std::fs::remove_dir_all(&dir).ok();

        // A run that never gets steady within its budget keeps its state, and a larger
        // budget continues it: the same run as one given that budget from the start.
        let dir = folder("budget");
        let opts = RunOptions {
            checkpoint: Some(dir.join("checkpoint.json")),
            resume: true,
            ..RunOptions::default()
        };
        let strict = 1e-9;
        assert!(matches!(
            rows(&tiny(40, 4, 1.0, strict), &opts),
            Err(SimError::NotSteady { .. })
        ));
        let continued = rows(&tiny(40, 4, 2.0, strict), &opts);
        let from_start = rows(&tiny(40, 4, 2.0, strict), &plain);
        match (continued, from_start) {
            (
                Err(SimError::NotSteady { detail: a, .. }),
                Err(SimError::NotSteady { detail: b, .. }),
            ) => {
                assert_eq!(a, b)
            }
            (a, b) => panic!(
                "expected two runs out of budget, got {:?} and {:?}",
                a.map(|_| ()),
                b.map(|_| ())
            ),
        }
        std::fs::remove_dir_all(&dir).ok();
    });
}
