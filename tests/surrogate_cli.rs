//! End-to-end `train`, `predict`, `validate` and `bench-predict` on synthetic tables with the
//! simulator's column schema and known smooth laws.
mod common;

use common::{csv_column, numbers, s, scratch, stderr, suspflow};
use serde_json::Value;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Output;

/// Runs `suspflow args`, failing the test with its standard error if it fails.
fn suspflow_ok(args: &[&str]) -> Output {
    let out = suspflow(args);
    assert!(
        out.status.success(),
        "suspflow {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs `suspflow args`, expecting a clean failure; returns its standard error.
fn suspflow_err(args: &[&str]) -> String {
    let out = suspflow(args);
    let err = stderr(&out);
    assert!(!out.status.success(), "suspflow {args:?} should fail");
    assert!(
        !err.contains("panicked"),
        "suspflow {args:?} panicked:\n{err}"
    );
    err
}

/// The simulator's `profile.csv` columns (docs/physics.md section 8), in its order.
const HEADER: &str =
    "scene_id,profile,L_y,phi,seed,y,u_inf,u,u_se,gdot,gdot_se,sigma_xy,sigma_xy_se,P,P_se,\
phi_loc,phi_loc_se,J,J_se,mu,mu_se,Theta,Theta_se,Delta_v,Delta_v_se,f_x,f_x_se,count,count_se";

/// One simulation: its id, profile expression, u_inf(y) for L_y, L_y, phi, number of bins.
struct Scene {
    id: String,
    profile: &'static str,
    u_inf: fn(f64, f64) -> f64,
    l_y: f64,
    phi: f64,
    bins: usize,
}

const SIN: &str = "0.1*sin(2*pi*y/L)";
fn sin_profile(y: f64, l: f64) -> f64 {
    0.1 * (2.0 * std::f64::consts::PI * y / l).sin()
}
const SIN_COS: &str = "0.1*sin(2*pi*y/L)+0.2*cos(2*pi*y/L)";
fn sin_cos_profile(y: f64, l: f64) -> f64 {
    let x = 2.0 * std::f64::consts::PI * y / l;
    0.1 * x.sin() + 0.2 * x.cos()
}
const SIN3: &str = "0.1*sin(2*pi*y/L)^3";
fn sin3_profile(y: f64, l: f64) -> f64 {
    0.1 * (2.0 * std::f64::consts::PI * y / l).sin().powi(3)
}

/// The training grid of the seeds, scaled down: `n` simulations of the sine profile cycling
/// through phi in {0.50, 0.52, 0.54, 0.56} and L_y in {50, 100}.
fn training_scenes(n: usize, bins: usize) -> Vec<Scene> {
    (0..n)
        .map(|k| Scene {
            id: format!("train_{k}"),
            profile: SIN,
            u_inf: sin_profile,
            l_y: [50.0, 100.0][(k / 4) % 2],
            phi: [0.50, 0.52, 0.54, 0.56][k % 4],
            bins,
        })
        .collect()
}

/// The two validation profiles of docs/physics.md section 8.
fn validation_scenes(bins: usize) -> Vec<Scene> {
    vec![
        Scene {
            id: "val_a".into(),
            profile: SIN_COS,
            u_inf: sin_cos_profile,
            l_y: 80.0,
            phi: 0.54,
            bins,
        },
        Scene {
            id: "val_b".into(),
            profile: SIN3,
            u_inf: sin3_profile,
            l_y: 100.0,
            phi: 0.54,
            bins,
        },
    ]
}

/// CSV text of `scenes` with the simulator's schema. Local values follow smooth laws of the
/// local shear `|du_inf/dy|` and phi: `J` and `Theta` grow with the shear, `phi_loc =
/// phi + 0.04 (1 + log10 Theta)` falls, `mu = 0.3 + 0.5 J^0.4 + 0.3 (phi_loc - 0.5) + 0.1 phi`,
/// `Delta_v = 0.05 + 0.3 Theta`. In the data rows (from 1) listed in `no_pressure`, `J`, `mu`
/// and `Theta` are empty, as the simulator writes them where `P <= 0`; in those in
/// `no_theta`, `Theta` alone.
fn table(scenes: &[Scene], no_pressure: &[usize], no_theta: &[usize]) -> String {
    let mut csv = format!("{HEADER}\n");
    let mut row = 0;
    for (k, scene) in scenes.iter().enumerate() {
        let width = scene.l_y / scene.bins as f64;
        for bin in 0..scene.bins {
            row += 1;
            let y = (bin as f64 + 0.5) * width;
            let u_inf = (scene.u_inf)(y, scene.l_y);
            let slope =
                ((scene.u_inf)(y + 1e-3, scene.l_y) - (scene.u_inf)(y - 1e-3, scene.l_y)) / 2e-3;
            let shear = slope.abs() * scene.l_y / 0.6; // about 0..1 over these profiles
            let wobble = 0.05 * ((7 * bin + 3 * k) % 11) as f64 / 11.0;
            let j = 1e-3 + 0.05 * (shear + wobble);
            let theta = 0.01 + 0.3 * (shear + wobble);
            let phi_loc = scene.phi + 0.04 * (1.0 + theta.log10());
            let mu = 0.3 + 0.5 * j.powf(0.4) + 0.3 * (phi_loc - 0.5) + 0.1 * scene.phi;
            let delta_v = 0.05 + 0.3 * theta;
            let pressure = 0.2 + 0.1 * wobble;
            let u = u_inf * (1.0 - delta_v);
            let cell = |v: f64, hidden: bool| if hidden { String::new() } else { v.to_string() };
            let (p0, t0) = (
                no_pressure.contains(&row),
                no_pressure.contains(&row) || no_theta.contains(&row),
            );
            let values = [
                (u, false),
                (slope, false),
                (mu * pressure, false),
                (pressure, false),
                (phi_loc, false),
                (j, p0),
                (mu, p0),
                (theta, t0),
                (delta_v, false),
                (0.01 * u, false),
                (40.0, false),
            ];
            let cells: Vec<String> = values
                .iter()
                .flat_map(|&(v, hidden)| [cell(v, hidden), cell(0.02 * v.abs(), hidden)])
                .collect();
            writeln!(
                csv,
                "{},\"{}\",{},{},1,{y},{u_inf},{}",
                scene.id,
                scene.profile,
                scene.l_y,
                scene.phi,
                cells.join(",")
            )
            .unwrap();
        }
    }
    csv
}

/// `csv` (made by [`table`]: no comma inside a quoted field) with the cell of `column` in data
/// row `row` (from 1) replaced by `value`.
fn with_cell(csv: &str, column: &str, row: usize, value: &str) -> String {
    let index = HEADER.split(',').position(|c| c == column).unwrap();
    let mut lines: Vec<String> = csv.lines().map(str::to_owned).collect();
    let mut cells: Vec<&str> = lines[row].split(',').collect();
    cells[index] = value;
    lines[row] = cells.join(",");
    lines.join("\n") + "\n"
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Relative L2 error (eq 6.6) of `predicted` against `truth`, both scaled with `(min, max)`.
fn rel_l2(truth: &[f64], predicted: &[f64], (min, max): (f64, f64)) -> f64 {
    let scale = |v: f64| (v - min) / (max - min);
    let residual: f64 = truth
        .iter()
        .zip(predicted)
        .map(|(&t, &p)| (scale(t) - scale(p)).powi(2))
        .sum();
    let norm: f64 = truth.iter().map(|&t| scale(t).powi(2)).sum();
    (residual / norm).sqrt()
}

/// Trains untuned models of the given mappings (all when empty) on `data` into `models`,
/// replacing models of those mappings already there.
fn train_untuned(data: &Path, models: &Path, mappings: &[&str]) {
    let mut args = vec![
        "train",
        "--data",
        s(data),
        "--out",
        s(models),
        "--no-tune",
        "--force",
    ];
    for m in mappings {
        args.extend(["--mapping", m]);
    }
    suspflow_ok(&args);
}

#[test]
fn train_then_predict_reproduces_a_smooth_law() {
    let dir = scratch("smooth");
    let data = write(
        &dir,
        "train.csv",
        &table(&training_scenes(16, 40), &[], &[]),
    );
    let models = dir.join("models");
    train_untuned(&data, &models, &[]);
    for m in ["mu", "theta", "dv"] {
        assert!(
            models.join(format!("{m}.json")).exists()
                && models.join(format!("{m}.meta.json")).exists()
        );
    }
    let pred = dir.join("pred.csv");
    suspflow_ok(&[
        "predict",
        "--model",
        s(&models.join("mu")),
        "--input",
        s(&data),
        "--out",
        s(&pred),
    ]);
    // Neither an earlier table nor the input is replaced without being asked.
    let mu = models.join("mu");
    let model = s(&mu);
    for (out, expect) in [
        (
            &pred,
            "pred.csv already exists (an earlier table); --force replaces it",
        ),
        (&data, "is the --input; write the predictions to a new file"),
    ] {
        let err = suspflow_err(&[
            "predict",
            "--model",
            model,
            "--input",
            s(&data),
            "--out",
            s(out),
        ]);
        assert!(err.contains(expect), "{err}");
    }
    let text = std::fs::read_to_string(&pred).unwrap();
    // Every input column is kept, as --help says, then the prediction and
    // the training-domain columns.
    assert_eq!(
        text.lines().next().unwrap(),
        format!("{HEADER},mu_pred,mu_lower,mu_upper,in_domain,domain_distance")
    );
    let input = std::fs::read_to_string(&data).unwrap();
    for (out_line, in_line) in text.lines().zip(input.lines()).skip(1) {
        // (the writer quotes only cells that need it: the profile's quotes go)
        let in_line = in_line.replace('"', "");
        assert!(out_line.starts_with(&format!("{in_line},")), "{out_line}");
    }
    let got = numbers(&text, "mu_pred");
    let truth: Vec<f64> = std::fs::read_to_string(&data)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .nth(HEADER.split(',').position(|c| c == "mu").unwrap())
                .unwrap()
                .parse()
                .unwrap()
        })
        .collect();
    assert_eq!(got.len(), truth.len());
    let err = (got
        .iter()
        .zip(&truth)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        / truth.iter().map(|b| b * b).sum::<f64>())
    .sqrt();
    assert!(err < 0.01, "in-sample relative error {err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn rows_outside_the_training_domain_are_flagged_counted_and_scored_apart() {
    let dir = scratch("domain");
    let train = write(&dir, "train.csv", &table(&training_scenes(8, 20), &[], &[]));
    let models = dir.join("models");
    train_untuned(&train, &models, &["mu"]);
    // Two of the training profiles binned more coarsely (local states between the training
    // rows), except row 3 with a J far beyond the training maximum and row 5 with a phi of
    // 0.60 (training phi 0.50-0.56).
    let rows = table(&training_scenes(2, 10), &[], &[]);
    let rows = with_cell(&rows, "J", 3, "0.9");
    let rows = with_cell(&rows, "phi", 5, "0.6");
    let input = write(&dir, "validate.csv", &rows);
    let pred = dir.join("pred.csv");
    let out = suspflow_ok(&[
        "predict",
        "--model",
        s(&models.join("mu")),
        "--input",
        s(&input),
        "--out",
        s(&pred),
    ]);
    let text = std::fs::read_to_string(&pred).unwrap();
    let flags = csv_column(&text, "in_domain");
    let distance = numbers(&text, "domain_distance");
    assert_eq!(flags.len(), 20);
    assert_eq!(flags[2], "false", "J beyond the training range");
    assert_eq!(flags[4], "false", "phi beyond the training range");
    let outside = flags.iter().filter(|f| *f == "false").count();
    assert!(outside < 20, "every row outside: {flags:?} {distance:?}");
    for (flag, d) in flags.iter().zip(&distance) {
        // Inside means near enough: the flag and the distance agree wherever in range.
        if *flag == "true" {
            assert!(*d <= 1.0, "inside at distance {d}");
        }
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!(
            "{outside} of 20 rows lie outside the training domain"
        )),
        "{stderr}"
    );

    // validate: the errors of the rows inside and outside, each from predict's numbers.
    let out = suspflow_ok(&[
        "validate",
        "--models",
        s(&models),
        "--data",
        s(&input),
        "--mapping",
        "mu",
        "--json",
        "--plots",
        s(&dir.join("plots")),
    ]);
    let records: Value = serde_json::from_slice(&out.stdout).unwrap();
    let lookup = |profile: &str| {
        records
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["profile"] == profile)
            .map(|r| r["rel_l2"].as_f64().unwrap())
    };
    let meta = read_json(&models.join("mu.meta.json"));
    let range = &meta["scaling"]["ranges"][0];
    let training_range = (
        range["min"].as_f64().unwrap(),
        range["max"].as_f64().unwrap(),
    );
    let truth = numbers(&rows, "mu");
    let predicted = numbers(&text, "mu_pred");
    for (profile, inside) in [("in domain", "true"), ("out of domain", "false")] {
        let pick = |v: &[f64]| -> Vec<f64> {
            v.iter()
                .zip(&flags)
                .filter(|(_, f)| *f == inside)
                .map(|(&x, _)| x)
                .collect()
        };
        let expected = rel_l2(&pick(&truth), &pick(&predicted), training_range);
        let got = lookup(profile).unwrap_or_else(|| panic!("no `{profile}` record"));
        assert!(
            (got - expected).abs() <= 1e-4 * expected.max(1e-12),
            "{profile}: {got} vs {expected}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn validate_json_matches_an_independent_computation_with_the_training_ranges() {
    let dir = scratch("validate-json");
    let train = write(&dir, "train.csv", &table(&training_scenes(8, 20), &[], &[]));
    let validate = write(
        &dir,
        "validate.csv",
        &table(&validation_scenes(25), &[], &[]),
    );
    let models = dir.join("models");
    train_untuned(&train, &models, &[]);
    let out = suspflow_ok(&[
        "validate",
        "--models",
        s(&models),
        "--data",
        s(&validate),
        "--json",
    ]);
    let records: Vec<Value> = serde_json::from_slice(&out.stdout).expect("stdout is only JSON");
    let keys: BTreeSet<(String, String, String)> = records
        .iter()
        .map(|r| {
            let fields: BTreeSet<&str> =
                r.as_object().unwrap().keys().map(String::as_str).collect();
            assert_eq!(
                fields,
                BTreeSet::from([
                    "mapping",
                    "output",
                    "profile",
                    "rel_l2",
                    "beyond_noise",
                    "coverage",
                    "interval_width"
                ]),
                "{r}"
            );
            let e = r["rel_l2"].as_f64().unwrap();
            assert!(e.is_finite() && e >= 0.0, "{r}");
            let text = |k: &str| r[k].as_str().unwrap().to_owned();
            (text("mapping"), text("output"), text("profile"))
        })
        .collect();
    let mut expected = BTreeSet::new();
    for (m, o) in [
        ("mu", "mu"),
        ("theta", "phi_loc"),
        ("theta", "mu"),
        ("dv", "phi_loc"),
        ("dv", "mu"),
        ("ext", "phi_loc"),
        ("ext", "mu"),
    ] {
        for p in [SIN_COS, SIN3, "all"] {
            expected.insert((m.to_owned(), o.to_owned(), p.to_owned()));
        }
    }
    // Besides the profiles: the rows inside and outside the training domain, where there are any.
    let (domain, profiles): (BTreeSet<_>, BTreeSet<_>) = keys
        .into_iter()
        .partition(|(_, _, p)| p == "in domain" || p == "out of domain");
    assert_eq!(profiles, expected);
    assert!(!domain.is_empty());

    // The same errors from `predict` and the sidecar's training ranges.
    let lookup = |m: &str, o: &str, p: &str| {
        records
            .iter()
            .find(|r| r["mapping"] == m && r["output"] == o && r["profile"] == p)
            .unwrap()["rel_l2"]
            .as_f64()
            .unwrap()
    };
    let validation_text = std::fs::read_to_string(&validate).unwrap();
    let truth_of = |o: &str| -> Vec<f64> {
        let index = HEADER.split(',').position(|c| c == o).unwrap();
        // The quoted profile holds no comma, so splitting on commas is exact here.
        validation_text
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(index).unwrap().parse().unwrap())
            .collect()
    };
    let is_a: Vec<bool> = validation_text
        .lines()
        .skip(1)
        .map(|l| l.contains(SIN_COS))
        .collect();
    for m in ["mu", "theta", "dv", "ext"] {
        let pred = dir.join(format!("{m}.pred.csv"));
        suspflow_ok(&[
            "predict",
            "--model",
            s(&models.join(m)),
            "--input",
            s(&validate),
            "--out",
            s(&pred),
        ]);
        let predicted_text = std::fs::read_to_string(&pred).unwrap();
        let meta = read_json(&models.join(format!("{m}.meta.json")));
        for (j, o) in meta["outputs"].as_array().unwrap().iter().enumerate() {
            let o = o.as_str().unwrap();
            let range = &meta["scaling"]["ranges"][j];
            let training_range = (
                range["min"].as_f64().unwrap(),
                range["max"].as_f64().unwrap(),
            );
            let (truth, predicted) = (truth_of(o), numbers(&predicted_text, &format!("{o}_pred")));
            let part = |keep: bool| -> (Vec<f64>, Vec<f64>) {
                let pick = |v: &[f64]| {
                    v.iter()
                        .zip(&is_a)
                        .filter(|(_, &a)| a == keep)
                        .map(|(&x, _)| x)
                        .collect()
                };
                (pick(&truth), pick(&predicted))
            };
            let ((ta, pa), (tb, pb)) = (part(true), part(false));
            for (profile, t, p) in [
                (SIN_COS, &ta, &pa),
                (SIN3, &tb, &pb),
                ("all", &truth, &predicted),
            ] {
                let expected = rel_l2(t, p, training_range);
                let got = lookup(m, o, profile);
                assert!(
                    (got - expected).abs() <= 1e-9 * expected.max(1e-12),
                    "{m} {o} {profile}: {got} vs {expected}"
                );
            }
            // The intervals' coverage, from predict's bounds.
            let (lower, upper) = (
                numbers(&predicted_text, &format!("{o}_lower")),
                numbers(&predicted_text, &format!("{o}_upper")),
            );
            let inside = (0..truth.len())
                .filter(|&i| lower[i] <= truth[i] && truth[i] <= upper[i])
                .count();
            let coverage = records
                .iter()
                .find(|r| r["mapping"] == m && r["output"] == o && r["profile"] == "all")
                .unwrap()["coverage"]
                .as_f64()
                .unwrap();
            assert_eq!(coverage, inside as f64 / truth.len() as f64, "{m} {o}");
            assert!(lower.iter().zip(&predicted).all(|(l, p)| l <= p));
            assert!(upper.iter().zip(&predicted).all(|(u, p)| u >= p));
            // The validation set's own ranges would give another number.
            let (lo, hi) = truth
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            let own = rel_l2(&truth, &predicted, (lo, hi));
            assert!(
                (own - lookup(m, o, "all")).abs() > 1e-6 * own,
                "{m} {o}: ranges not told apart"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn validate_prints_every_section_and_draws_one_figure_per_profile() {
    let dir = scratch("validate-text");
    let train = write(&dir, "train.csv", &table(&training_scenes(8, 20), &[], &[]));
    let validate = write(
        &dir,
        "validate.csv",
        &table(&validation_scenes(25), &[], &[]),
    );
    let models = dir.join("models");
    train_untuned(&train, &models, &[]);
    let out = suspflow_ok(&["validate", "--models", s(&models), "--data", s(&validate)]);
    let text = String::from_utf8_lossy(&out.stdout);
    for section in [
        "mapping mu:",
        "mapping theta:",
        "mapping dv:",
        "seeds (thesis, all)",
        "xgboost, as trained",
        "linear (linfa)",
        "log-linear (linfa",
        "no tuning record",
        "theta vs dv",
        "feature importance",
        SIN_COS,
        SIN3,
    ] {
        assert!(text.contains(section), "no `{section}` in:\n{text}");
    }
    // Importance shares of each model add up to 100 %.
    let importance = text.split("feature importance").nth(1).unwrap();
    for line in importance
        .lines()
        .skip(1)
        .filter(|l| l.trim().starts_with(['m', 't', 'd']))
    {
        let total: f64 = line
            .split(", ")
            .map(|p| {
                p.trim_end_matches(" %")
                    .rsplit(' ')
                    .next()
                    .unwrap()
                    .parse::<f64>()
                    .unwrap()
            })
            .sum();
        assert!((total - 100.0).abs() < 0.2, "{line}");
    }
    let figures = models.join("validation_plots");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&figures)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 2, "{files:?}");
    for (file, profile) in files.iter().zip([SIN_COS, SIN3]) {
        // The figure's numbers beside it: one row per drawn point, every series named.
        let data = std::fs::read_to_string(file.with_extension("csv")).unwrap();
        assert!(data.starts_with("panel,series,x_quantity,x,x_se,y_quantity,y,y_se\n"));
        assert!(
            data.contains(",simulated,phi_loc,") && data.contains(",mapping dv,"),
            "{data}"
        );
        let svg = std::fs::read_to_string(file).unwrap();
        assert!(svg.starts_with("<svg"), "{}", file.display());
        for label in [
            "simulated",
            "mapping mu",
            "mapping theta",
            "mapping dv",
            "phi_loc",
            profile,
        ] {
            assert!(svg.contains(label), "{} lacks `{label}`", file.display());
        }
    }
    // --plots puts them elsewhere.
    let elsewhere = dir.join("figures");
    suspflow_ok(&[
        "validate",
        "--models",
        s(&models),
        "--data",
        s(&validate),
        "--plots",
        s(&elsewhere),
        "--mapping",
        "mu",
    ]);
    // Two figures, each with its CSV.
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 4);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn train_chooses_hyper_parameters_by_leaving_one_simulation_out() {
    let dir = scratch("tune");
    let train = write(&dir, "train.csv", &table(&training_scenes(5, 10), &[], &[]));
    let models = dir.join("models");
    let out = suspflow_ok(&[
        "train",
        "--data",
        s(&train),
        "--out",
        s(&models),
        "--mapping",
        "theta",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("over 5 simulations") && stdout.contains("XGBoost defaults"),
        "{stdout}"
    );
    let record = read_json(&models.join("theta.tuning.json"));
    assert_eq!(record["folds"], 5);
    let grid = &record["grid"];
    let size: usize = [
        "n_estimators",
        "max_depth",
        "learning_rate",
        "min_child_weight",
    ]
    .iter()
    .map(|k| grid[k].as_array().unwrap().len().max(1))
    .product();
    let scores = record["scores"].as_array().unwrap();
    assert_eq!(scores.len(), size);
    let means: Vec<f64> = scores.iter().map(|s| s["mean"].as_f64().unwrap()).collect();
    let best = means.iter().copied().fold(f64::INFINITY, f64::min);
    assert_eq!(record["chosen"]["mean"].as_f64().unwrap(), best);
    assert!(
        means.iter().any(|&m| m > best),
        "every setting scored the same: {means:?}"
    );
    for s in scores.iter().chain([&record["chosen"], &record["untuned"]]) {
        assert_eq!(s["per_output"].as_array().unwrap().len(), 2);
    }
    let untuned = &record["untuned"]["params"];
    assert_eq!(
        (
            untuned["n_estimators"].as_u64(),
            untuned["max_depth"].as_u64()
        ),
        (Some(100), Some(6))
    );
    assert_eq!(untuned["learning_rate"].as_f64(), Some(0.3));
    let meta = read_json(&models.join("theta.meta.json"));
    assert_eq!(meta["hyper_parameters"], record["chosen"]["params"]);

    // Untuned training drops the record that would no longer describe the model.
    train_untuned(&train, &models, &["theta"]);
    assert!(!models.join("theta.tuning.json").exists());
    assert_eq!(
        read_json(&models.join("theta.meta.json"))["hyper_parameters"],
        *untuned
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn empty_cells_are_skipped_and_counted_per_mapping() {
    let dir = scratch("holes");
    let scenes = training_scenes(6, 12);
    let rows = 6 * 12;
    let (no_pressure, no_theta) = ([3, 17, 40], [5, 6, 50, 71]);
    let train = write(&dir, "train.csv", &table(&scenes, &no_pressure, &no_theta));
    let models = dir.join("models");
    let out = suspflow_ok(&[
        "train",
        "--data",
        s(&train),
        "--out",
        s(&models),
        "--no-tune",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    for (mapping, skipped) in [("mu", 3), ("theta", 7), ("dv", 3)] {
        assert!(
            err.contains(&format!("{mapping}: {skipped} of {rows} rows")),
            "{mapping}: {err}"
        );
        let data = &read_json(&models.join(format!("{mapping}.meta.json")))["training_data"];
        assert_eq!(
            (data["rows"].as_u64(), data["skipped_rows"].as_u64()),
            (Some(rows - skipped), Some(skipped))
        );
    }
    let validate = write(
        &dir,
        "validate.csv",
        &table(&validation_scenes(20), &[2, 30], &[]),
    );
    let out = suspflow_ok(&[
        "validate",
        "--models",
        s(&models),
        "--data",
        s(&validate),
        "--json",
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("theta: 2 of 40 rows"));
    let records: Vec<Value> = serde_json::from_slice(&out.stdout).unwrap();
    let by_profile = records
        .iter()
        .filter(|r| !r["profile"].as_str().unwrap().contains("domain"))
        .count();
    // mu: one output on 2 profiles and all; theta, dv and ext: two each.
    assert_eq!(by_profile, 21);
    // A NaN written out is not an undefined value: it is refused, naming the row.
    let nan = write(
        &dir,
        "nan.csv",
        &with_cell(&table(&scenes, &[], &[]), "Theta", 9, "NaN"),
    );
    let err = suspflow_err(&[
        "train",
        "--data",
        s(&nan),
        "--out",
        s(&models),
        "--no-tune",
        "--force",
        "--mapping",
        "theta",
    ]);
    assert!(
        err.contains("data row 9, column `Theta`") && err.contains("NaN is not a finite number"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_surrogate_inputs_give_clear_errors() {
    let dir = scratch("bad");
    let train = write(&dir, "train.csv", &table(&training_scenes(4, 10), &[], &[]));
    let models = dir.join("models");
    let err = suspflow_err(&[
        "train",
        "--data",
        s(&train),
        "--out",
        s(&models),
        "--mapping",
        "nope",
    ]);
    assert!(
        err.contains("unknown mapping `nope`") && err.contains("theta"),
        "{err}"
    );
    train_untuned(&train, &models, &[]);
    let good = table(&validation_scenes(10), &[], &[]);
    let validate = |name: &str, text: &str| {
        let path = write(&dir, name, text);
        suspflow_err(&[
            "validate",
            "--models",
            s(&models),
            "--data",
            s(&path),
            "--plots",
            s(&dir.join("p")),
        ])
    };
    let err = validate("renamed.csv", &good.replacen("Theta,", "Temperature,", 1));
    assert!(
        err.contains("no column `Theta`") && err.contains("Temperature"),
        "{err}"
    );
    let err = validate("nan.csv", &with_cell(&good, "J", 4, "nan"));
    assert!(
        err.contains("data row 4, column `J`") && err.contains("not a finite number"),
        "{err}"
    );
    let err = validate("inf.csv", &with_cell(&good, "phi", 2, "inf"));
    assert!(err.contains("data row 2, column `phi`"), "{err}");
    let err = validate("text.csv", &with_cell(&good, "mu", 7, "n/a"));
    assert!(
        err.contains("data row 7, column `mu`") && err.contains("`n/a` is not a number"),
        "{err}"
    );
    let err = validate("empty.csv", &format!("{HEADER}\n"));
    assert!(err.contains("holds no data rows"), "{err}");
    let good_path = write(&dir, "good.csv", &good);
    let err = suspflow_err(&[
        "validate",
        "--models",
        s(&models),
        "--data",
        s(&good_path),
        "--mapping",
        "viscosity",
    ]);
    assert!(
        err.contains("unknown mapping `viscosity`") && err.contains("mu, theta, dv"),
        "{err}"
    );
    let err = suspflow_err(&[
        "validate",
        "--models",
        s(&dir.join("none")),
        "--data",
        s(&good_path),
    ]);
    assert!(
        err.contains("loading model `mu`") && err.contains("none/mu.meta.json"),
        "{err}"
    );
    // A model whose sidecar names other features than its mapping.
    let meta = models.join("dv.meta.json");
    std::fs::write(
        &meta,
        std::fs::read_to_string(&meta)
            .unwrap()
            .replacen("\"Delta_v\"", "\"Theta\"", 1),
    )
    .unwrap();
    let err = suspflow_err(&["validate", "--models", s(&models), "--data", s(&good_path)]);
    assert!(
        err.contains("dv.meta.json lists features [J, Theta, phi], mapping `dv` now has [J, Delta_v, phi]: missing Delta_v; extra Theta"),
        "{err}"
    );
    // --train that is not the training data.
    let err = suspflow_err(&[
        "validate",
        "--models",
        s(&models),
        "--data",
        s(&good_path),
        "--mapping",
        "mu",
        "--train",
        s(&good_path),
    ]);
    assert!(
        err.contains("--train") && err.contains("hash differs"),
        "{err}"
    );
    // predict: a feature missing, and an undefined feature value.
    let missing = write(&dir, "missing.csv", "scene_id,phi,J\ns0,0.5,0.001\n");
    let err = suspflow_err(&[
        "predict",
        "--model",
        s(&models.join("mu")),
        "--input",
        s(&missing),
    ]);
    assert!(err.contains("lacks column(s) phi_loc"), "{err}");
    let hole = write(&dir, "hole.csv", &table(&validation_scenes(10), &[6], &[]));
    let err = suspflow_err(&[
        "predict",
        "--model",
        s(&models.join("mu")),
        "--input",
        s(&hole),
    ]);
    assert!(err.contains("data row 6, column `J` is empty"), "{err}");
    // A value beyond f32 (the models' type) is named by column, line and value (issue 31,
    // 16.11), in predict and in validate.
    let big = write(
        &dir,
        "big.csv",
        "scene_id,phi,J,phi_loc\ns0,0.5,0.001,0.5\ns0,0.5,1e39,0.5\n",
    );
    let err = suspflow_err(&[
        "predict",
        "--model",
        s(&models.join("mu")),
        "--input",
        s(&big),
    ]);
    assert!(
        err.contains("big.csv: line 3 (data row 2), column `J`: 1e39 exceeds the f32 range"),
        "{err}"
    );
    // A tree file cut in half is named as such by both model readers, without XGBoost's
    // stack trace (16.14).
    let trees = models.join("mu.json");
    let whole = std::fs::read(&trees).unwrap();
    std::fs::write(&trees, &whole[..whole.len() / 2]).unwrap();
    for args in [
        vec![
            "predict",
            "--model",
            s(&models.join("mu")),
            "--input",
            s(&good_path),
        ],
        vec![
            "validate",
            "--models",
            s(&models),
            "--data",
            s(&good_path),
            "--mapping",
            "mu",
        ],
    ] {
        let err = suspflow_err(&args);
        assert!(
            err.contains("mu.json: ends in the middle of its JSON") && !err.contains("[bt]"),
            "{args:?}: {err}"
        );
    }
    std::fs::write(&trees, &whole).unwrap();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bench_predict_times_load_read_and_predict_of_a_50_bin_profile() {
    let dir = scratch("bench");
    let train = write(&dir, "train.csv", &table(&training_scenes(4, 10), &[], &[]));
    let models = dir.join("models");
    train_untuned(&train, &models, &["mu", "dv"]);
    let out = suspflow_ok(&[
        "bench-predict",
        "--models",
        s(&models),
        "--mapping",
        "mu",
        "--mapping",
        "dv",
        "--repeat",
        "3",
        "--json",
    ]);
    let records: Vec<Value> = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        records
            .iter()
            .map(|r| r["mapping"].as_str().unwrap())
            .collect::<Vec<_>>(),
        ["mu", "dv"]
    );
    for r in &records {
        assert_eq!(
            (r["rows"].as_u64(), r["runs"].as_u64()),
            (Some(50), Some(3)),
            "{r}"
        );
        let ms = |k: &str| r[k].as_f64().unwrap();
        assert!(
            ms("min_ms") > 0.0 && ms("min_ms") <= ms("median_ms") && ms("min_ms") <= ms("first_ms"),
            "{r}"
        );
        for stage in ["load_ms", "read_ms", "predict_ms"] {
            assert!(
                ms(stage) > 0.0 && ms(stage) <= ms("median_ms") * 3.0,
                "{stage}: {r}"
            );
        }
    }
    let out = suspflow_ok(&[
        "bench-predict",
        "--models",
        s(&models),
        "--mapping",
        "mu",
        "--repeat",
        "2",
        "--rows",
        "7",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("mu: 7 rows, load + read + predict: median") && text.contains(" ms"),
        "{text}"
    );
    let err = suspflow_err(&[
        "bench-predict",
        "--models",
        s(&models),
        "--mapping",
        "theta",
    ]);
    assert!(err.contains("theta.meta.json"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn train_keeps_existing_models_and_validate_warns_on_training_rows() {
    let dir = scratch("overlap");
    let train = write(&dir, "train.csv", &table(&training_scenes(4, 10), &[], &[]));
    let models = dir.join("models");
    train_untuned(&train, &models, &["mu"]);
    let trees = std::fs::read(models.join("mu.json")).unwrap();
    let args = [
        "train",
        "--data",
        s(&train),
        "--out",
        s(&models),
        "--no-tune",
        "--mapping",
        "mu",
    ];
    let err = suspflow_err(&args);
    assert!(
        err.contains("mu.json already exists (a trained `mu` model); --force replaces it"),
        "{err}"
    );
    assert_eq!(std::fs::read(models.join("mu.json")).unwrap(), trees);
    // A lone sidecar is a user's file too.
    let lone = models.join("lone");
    std::fs::create_dir_all(&lone).unwrap();
    std::fs::copy(models.join("mu.meta.json"), lone.join("mu.meta.json")).unwrap();
    let mut into_lone = args.to_vec();
    into_lone[4] = s(&lone);
    let err = suspflow_err(&into_lone);
    assert!(err.contains("mu.meta.json already exists"), "{err}");
    let mut forced = args.to_vec();
    forced.push("--force");
    suspflow_ok(&forced);

    let validate = |data: &Path| {
        let out = suspflow_ok(&[
            "validate",
            "--models",
            s(&models),
            "--data",
            s(data),
            "--mapping",
            "mu",
            "--json",
        ]);
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let err = validate(&train);
    assert!(
        err.contains("holds the very bytes model `mu` was trained on"),
        "{err}"
    );
    let unseen = table(&validation_scenes(10), &[], &[]);
    let training_text = std::fs::read_to_string(&train).unwrap();
    let training_rows: Vec<&str> = training_text.lines().skip(1).take(5).collect();
    let mixed = write(
        &dir,
        "mixed.csv",
        &format!("{unseen}{}\n", training_rows.join("\n")),
    );
    let err = validate(&mixed);
    let rows = unseen.lines().count() - 1 + 5;
    assert!(
        err.contains(&format!(
            "5 of the {rows} validation rows of model `mu` are also training rows"
        )),
        "{err}"
    );
    let clean = write(&dir, "clean.csv", &unseen);
    assert!(
        !validate(&clean).contains("training"),
        "no overlap, no warning"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Rows of the dv mapping in four profile families (amplitudes 0.05-0.4), two scenes each
/// (phi 0.50 and 0.56), that follow a local rheology exactly: `mu = 3.6 J^0.44` and eq 6.7
/// `phi_loc = 0.66 - sqrt(J / (2 mu))`. Family `k` spans J in `[1, 10] x 1e-3 x 2.5^k`, so
/// the strongest one lies mostly beyond the others' range of J.
fn power_law_families() -> String {
    let mut csv = String::from("scene_id,profile,phi,seed,J,Delta_v,phi_loc,mu\n");
    for (k, amplitude) in ["0.05", "0.1", "0.2", "0.4"].iter().enumerate() {
        for (s, phi) in [0.50, 0.56].iter().enumerate() {
            for b in 0..20 {
                let t = (b as f64 + 0.5 * s as f64) / 20.0;
                let j = 1e-3 * 2.5f64.powi(k as i32) * 10f64.powf(t);
                let mu = 3.6 * j.powf(0.44);
                let phi_loc = 0.66 - (j / (2.0 * mu)).sqrt();
                let delta_v = 0.02 + 0.5 * j + 0.01 * ((3 * b) % 7) as f64;
                writeln!(
                    csv,
                    "f{k}_{s},\"{amplitude}*sin(2*pi*y/L)\",{phi},1,{j},{delta_v},{phi_loc},{mu}"
                )
                .unwrap();
            }
        }
    }
    csv
}

#[test]
fn cross_validate_compares_trees_backbone_and_both_on_held_out_families() {
    let dir = scratch("family_cv");
    let data = write(&dir, "families.csv", &power_law_families());
    let models = dir.join("models");
    train_untuned(&data, &models, &["dv"]);
    let out = dir.join("cv");
    let args = [
        "cross-validate",
        "--data",
        s(&data),
        "--mapping",
        "dv",
        "--models",
        s(&models),
        "--out",
        s(&out),
    ];
    let run = suspflow_ok(&args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("4 profile families") && stderr.contains("[4/4]"),
        "{stderr}"
    );
    let record = read_json(&out.join("cv.json"));
    let cv = &record["mappings"][0];
    assert_eq!(cv["mapping"], "dv");
    let folds = cv["folds"].as_array().unwrap();
    // Every family held out exactly once, with all its rows, split into in and out of domain.
    let held_out: BTreeSet<&str> = folds
        .iter()
        .map(|f| f["family"].as_str().unwrap())
        .collect();
    assert_eq!(held_out.len(), 4);
    for fold in folds {
        assert_eq!(fold["train_rows"], 120);
        for v in fold["variants"].as_array().unwrap() {
            let rows = |class: &str| v[class]["rows"].as_u64().unwrap();
            assert_eq!(rows("all"), 40);
            assert_eq!(rows("in_domain") + rows("out_of_domain"), 40);
        }
    }
    // The strongest family: mostly beyond the training J. The backbone alone follows the
    // law it was fitted on; the trees alone stay at the edge of their range.
    let strongest = folds
        .iter()
        .find(|f| f["family"] == "0.4*sin(2*pi*y/L)")
        .unwrap();
    let errors = |variant: &str, class: &str| -> Vec<f64> {
        let v = strongest["variants"]
            .as_array()
            .unwrap()
            .iter()
            .find(|v| v["variant"] == variant)
            .unwrap();
        v[class]["per_output"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e.as_f64().unwrap())
            .collect()
    };
    // Its J exceeds the others' largest (2.5^2 x 1e-2) in the upper 40 % of its log range:
    // 16 of its 40 rows at least lie outside the training domain.
    assert!(
        strongest["variants"][0]["out_of_domain"]["rows"]
            .as_u64()
            .unwrap()
            >= 16,
        "{strongest}"
    );
    let (trees, law, both) = (
        errors("trees", "all"),
        errors("backbone", "all"),
        errors("backbone_trees", "all"),
    );
    for k in 0..2 {
        assert!(law[k] < 0.01, "backbone alone, output {k}: {law:?}");
        assert!(
            trees[k] > 0.05 && trees[k] > 5.0 * law[k],
            "trees alone, output {k}: {trees:?} vs backbone {law:?}"
        );
        assert!(
            both[k] < 0.5 * trees[k],
            "backbone + trees {both:?} vs trees {trees:?}"
        );
    }
    // The summary averages the families' errors.
    let summary = &cv["summary"][0];
    assert_eq!(summary["variant"], "trees");
    assert_eq!(summary["all"]["families"], 4);
    let mean: f64 = folds
        .iter()
        .map(|f| f["variants"][0]["all"]["per_output"][1].as_f64().unwrap())
        .sum::<f64>()
        / 4.0;
    let reported = summary["all"]["per_output"][1].as_f64().unwrap();
    assert!((reported - mean).abs() < 1e-12, "{reported} vs {mean}");
    // The absolute errors (output units) rank the variants as the relative ones do where
    // the law is exact, and their summary is the mean over the families too.
    let absolute = |variant: usize, output: usize| {
        strongest["variants"][variant]["all"]["mean_absolute"][output]
            .as_f64()
            .unwrap()
    };
    for k in 0..2 {
        assert!(
            absolute(1, k) < 0.2 * absolute(0, k),
            "output {k}: {strongest}"
        );
    }
    let mean_absolute: f64 = folds
        .iter()
        .map(|f| {
            f["variants"][0]["all"]["mean_absolute"][1]
                .as_f64()
                .unwrap()
        })
        .sum::<f64>()
        / 4.0;
    let reported = summary["all"]["mean_absolute"][1].as_f64().unwrap();
    assert!(
        (reported - mean_absolute).abs() < 1e-12,
        "{reported} vs {mean_absolute}"
    );
    // A table without standard errors has no noise to report, and the report says none.
    assert!(cv["target_noise"].is_null(), "{}", cv["target_noise"]);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(!report.contains("own noise"), "{report}");
    for needle in [
        "## Mapping `dv`",
        "| phi_loc | backbone alone |",
        "### `mu` by held-out family",
        "| `0.4*sin(2*pi*y/L)` | 40 (",
        "| out of domain | abs, all |",
    ] {
        assert!(report.contains(needle), "no `{needle}` in\n{report}");
    }
    // An existing report is kept unless --force.
    let err = suspflow_err(&args);
    assert!(
        err.contains("already exists") && err.contains("--force"),
        "{err}"
    );
    let mut forced = args.to_vec();
    forced.push("--force");
    suspflow_ok(&forced);
    // The learning curve. Its last point, all three other families, is the trees' error of
    // the summary, computed along a separate path; one family (of one amplitude)
    // extrapolates to the held-out amplitudes and must do worse.
    let mut curve_args = forced.clone();
    curve_args.extend(["--learning-curve", "1,2", "--draws", "2"]);
    let ran = suspflow_ok(&curve_args);
    // Estimated before it runs: 4 held-out families x (2 draws at 1 and at 2, 1 at 3).
    let stderr = String::from_utf8_lossy(&ran.stderr);
    assert!(
        stderr.contains("learning curve of 20 fits of at most")
            && stderr.contains("learning curves estimated at most"),
        "{stderr}"
    );
    let record = read_json(&out.join("cv.json"));
    let points = record["learning_curves"][0]["points"].as_array().unwrap();
    let counts: Vec<u64> = points
        .iter()
        .map(|p| p["families"].as_u64().unwrap())
        .collect();
    assert_eq!(counts, [1, 2, 3]);
    let error = |p: usize, k: usize| points[p]["per_output"][k].as_f64().unwrap();
    // The summary entry of the variant the curve used (that of the models).
    let curve = &record["learning_curves"][0];
    let variant = if curve["backbone"].as_bool().unwrap() {
        "backbone_trees"
    } else {
        "trees"
    };
    let summary = record["mappings"][0]["summary"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["variant"] == variant)
        .unwrap();
    for k in 0..2 {
        let summary = summary["all"]["per_output"][k].as_f64().unwrap();
        assert!(
            (error(2, k) - summary).abs() < 1e-12,
            "{} vs {summary}",
            error(2, k)
        );
        assert!(error(0, k) > error(2, k), "output {k}: {points:?}");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("error against the number of families"),
        "{report}"
    );
    // --draws without --learning-curve is refused by the parser.
    let mut stray = forced.clone();
    stray.extend(["--draws", "2"]);
    let err = suspflow_err(&stray);
    assert!(err.contains("--learning-curve"), "{err}");
    let mut too_many = forced.clone();
    too_many.extend(["--learning-curve", "4"]);
    let err = suspflow_err(&too_many);
    assert!(err.contains("between 1 and 3"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn cross_validate_refuses_tables_without_two_families_and_models() {
    let dir = scratch("family_cv_errors");
    let csv = power_law_families();
    let data = write(&dir, "families.csv", &csv);
    let models = dir.join("models");
    train_untuned(&data, &models, &["dv"]);
    let run = |data: &Path, models: &Path| {
        suspflow_err(&[
            "cross-validate",
            "--data",
            s(data),
            "--mapping",
            "dv",
            "--models",
            s(models),
            "--out",
            s(&dir.join("cv")),
        ])
    };
    let one: String = csv
        .lines()
        .filter(|l| !l.starts_with("f3") && !l.starts_with("f1") && !l.starts_with("f2"))
        .map(|l| format!("{l}\n"))
        .collect();
    let err = run(&write(&dir, "one.csv", &one), &models);
    assert!(
        err.contains("at least 2 families") && err.contains("has 1"),
        "{err}"
    );
    let no_profile = csv.replace("scene_id,profile,", "scene_id,forcing,");
    let err = run(&write(&dir, "no_profile.csv", &no_profile), &models);
    assert!(err.contains("no column `profile`"), "{err}");
    let err = run(&data, &dir.join("nowhere"));
    assert!(
        err.contains("hyper-parameters of `dv`") && err.contains("train first"),
        "{err}"
    );
    assert!(!dir.join("cv").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn predict_counts_the_values_clipped_into_the_physical_range() {
    let dir = scratch("clip");
    let data = write(&dir, "families.csv", &power_law_families());
    let models = dir.join("models");
    // Trees on the backbone's residual: beyond the training J, eq 6.7 drives phi_loc below 0.
    let out = suspflow_ok(&[
        "train",
        "--data",
        s(&data),
        "--out",
        s(&models),
        "--mapping",
        "dv",
    ]);
    let meta = read_json(&models.join("dv.meta.json"));
    assert_eq!(
        meta["hyper_parameters"]["backbone"],
        true,
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let input = write(
        &dir,
        "far.csv",
        "J,Delta_v,phi\n0.01,0.03,0.5\n100,0.03,0.5\n1000,0.03,0.5\n",
    );
    let run = suspflow_ok(&[
        "predict",
        "--model",
        s(&models.join("dv")),
        "--input",
        s(&input),
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    let predicted = String::from_utf8_lossy(&run.stdout);
    let phi_loc = numbers(&predicted, "phi_loc_pred");
    assert!(phi_loc.iter().all(|&p| p > 0.0 && p < 0.74), "{phi_loc:?}");
    assert!(numbers(&predicted, "mu_pred").iter().all(|&m| m >= 0.0));
    assert!(
        stderr.contains("2 predicted values of `dv` left their physical range"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 31, class 12: a table no flow can give (negative J, phi = 2, negative phi_loc) is
/// refused by every command that trains or scores on it, naming row and column; `coverage`
/// and `plot` refuse a literal NaN as the others do (only an empty cell is undefined).
#[test]
fn unphysical_tables_are_refused_by_every_reader() {
    let dir = scratch("unphysical");
    let good = table(&training_scenes(4, 10), &[], &[]);
    let models = dir.join("models");
    train_untuned(&write(&dir, "train.csv", &good), &models, &["dv"]);
    let cases = [
        ("J", 3, "-0.01", "J = eta |gdot| / P >= 0"),
        ("phi", 5, "2", "a volume fraction lies in [0, 0.74]"),
        ("phi_loc", 8, "-0.1", "a volume fraction lies in [0, 0.74]"),
    ];
    for (column, row, value, reason) in cases {
        let bad = write(&dir, "bad.csv", &with_cell(&good, column, row, value));
        let expected =
            format!("data row {row}, column `{column}`: {value} is not physical ({reason}");
        for args in [
            vec![
                "train",
                "--data",
                s(&bad),
                "--out",
                s(&dir.join("m2")),
                "--mapping",
                "dv",
                "--no-tune",
            ],
            vec![
                "validate",
                "--models",
                s(&models),
                "--data",
                s(&bad),
                "--mapping",
                "dv",
                "--plots",
                s(&dir.join("p")),
            ],
            vec![
                "cross-validate",
                "--data",
                s(&bad),
                "--models",
                s(&models),
                "--mapping",
                "dv",
                "--out",
                s(&dir.join("cv")),
            ],
        ] {
            let err = suspflow_err(&args);
            assert!(
                err.contains(&expected),
                "{} on {column} = {value}: {err}",
                args[0]
            );
        }
    }
    let nan = write(&dir, "nan.csv", &with_cell(&good, "mu", 4, "NaN"));
    for command in ["coverage", "plot"] {
        let err = suspflow_err(&[command, s(&nan), "--out", s(&dir.join(command))]);
        assert!(
            err.contains("data row 4, column `mu`: NaN is not a finite number"),
            "{command}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 31, class 11: a bundle whose parts disagree, or that holds impossible values, is
/// refused on load by `predict` (and by every loader: one check), saying what disagrees.
#[test]
fn a_model_bundle_whose_parts_disagree_is_refused_on_load() {
    let dir = scratch("bundle");
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let input = write(
        &dir,
        "in.csv",
        "scene_id,J,phi_loc,phi,Delta_v\ns0,0.01,0.55,0.54,0.05\n",
    );
    type Damage = fn(&Path);
    fn edit_json(path: &Path, f: impl Fn(&mut Value)) {
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        f(&mut v);
        std::fs::write(path, serde_json::to_string(&v).unwrap()).unwrap();
    }
    let cases: [(&str, Damage, &str); 9] = [
        (
            "dv",
            |m| std::fs::copy(m.join("mu.json"), m.join("dv.json")).map(drop).unwrap(),
            "has 1 output (learner_model_param.num_target) where mapping `dv` has 2 (phi_loc, mu)",
        ),
        (
            "dv",
            |m| edit_json(&m.join("dv.json"), |v| {
                v["learner"]["learner_model_param"]["num_feature"] = "4".into()
            }),
            "has 4 features (learner_model_param.num_feature) where mapping `dv` has 3 (J, Delta_v, phi)",
        ),
        (
            "dv",
            |m| std::fs::copy(m.join("mu.domain.json"), m.join("dv.domain.json")).map(drop).unwrap(),
            "its training domain is of features [J, phi_loc, phi], the model's are [J, Delta_v, phi]",
        ),
        (
            "mu",
            |m| edit_json(&m.join("mu.meta.json"), |v| drop(v.as_object_mut().unwrap().remove("backbone"))),
            "the trees learn the residual of a backbone, but it holds none",
        ),
        (
            "mu",
            |m| edit_json(&m.join("mu.meta.json"), |v| {
                v["scaling"]["ranges"][0]["max"] = v["scaling"]["ranges"][0]["min"].clone()
            }),
            "of zero width",
        ),
        (
            "mu",
            |m| edit_json(&m.join("mu.meta.json"), |v| {
                v["scaling"]["ranges"][0] = serde_json::json!({"min": 2.0, "max": 0.1})
            }),
            "the range of `mu` is [2, 0.1], not a range",
        ),
        (
            "mu",
            |m| edit_json(&m.join("mu.meta.json"), |v| v["backbone"]["law"]["phi_j"] = (-5.0).into()),
            "phi_J = -5 (eq 6.7), outside (0, 0.74]",
        ),
        (
            "mu",
            |m| edit_json(&m.join("mu.meta.json"), |v| v["hyper_parameters"]["n_estimators"] = 1000.into()),
            "the sidecar's 1000 rounds of 1 output(s) make 1000",
        ),
        (
            "mu",
            |m| edit_json(&m.join("mu.domain.json"), |v| v["training_fnv1a_64"] = "0123456789abcdef".into()),
            "rows of data 0123456789abcdef, the model was trained on",
        ),
    ];
    for (mapping, damage, expected) in cases {
        let models = dir.join("models");
        let _ = std::fs::remove_dir_all(&models);
        std::fs::create_dir_all(&models).unwrap();
        for entry in std::fs::read_dir(&shipped).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                std::fs::copy(&path, models.join(path.file_name().unwrap())).unwrap();
            }
        }
        let predicted = dir.join("predicted.csv");
        suspflow_ok(&[
            "predict",
            "--model",
            s(&models.join(mapping)),
            "--input",
            s(&input),
            "--out",
            s(&predicted),
            "--force",
        ]);
        // Issue 31, class 15: predict on its own output would repeat its column names.
        let err = suspflow_err(&[
            "predict",
            "--model",
            s(&models.join(mapping)),
            "--input",
            s(&predicted),
        ]);
        let first_output = if mapping == "mu" { "mu" } else { "phi_loc" };
        assert!(
            err.contains(&format!("already has a column `{first_output}_pred`")),
            "{err}"
        );
        damage(&models);
        let err = suspflow_err(&[
            "predict",
            "--model",
            s(&models.join(mapping)),
            "--input",
            s(&input),
        ]);
        assert!(
            err.contains(expected),
            "{mapping}: {err} should say {expected}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
