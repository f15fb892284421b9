//! `suspflow report` in quick mode on tiny scenes (tests/grids/tiny.toml, about 50 particles)
//! and one swept stability parameter (6 dt multiples x 4 stiffnesses), with the shipped
//! datasets and models: every section and figure is produced, errors fall with averaging,
//! the tuned trees fit better than a few, the automatic dt is stable, and a step 16x too large is caught
//! with its cause named instead of ending in NaN.
mod common;

use common::{s, scratch, suspflow};
use std::path::Path;
use std::process::Output;

fn report(dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["report", "--name", "t", "--out", s(dir)];
    args.extend_from_slice(extra);
    suspflow(&args)
}

/// Cells of the markdown table rows of `md` that start with `prefix`.
fn rows<'a>(md: &'a str, prefix: &str) -> Vec<Vec<&'a str>> {
    md.lines()
        .filter(|l| l.starts_with(prefix))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect()
}

fn percent(cell: &str) -> f64 {
    cell.trim_end_matches(" %")
        .parse()
        .unwrap_or_else(|_| panic!("not a percentage: {cell}"))
}

#[test]
fn quick_report_on_tiny_scenes_has_every_section_and_names_failures() {
    let dir = scratch("quick");
    let out = report(
        &dir,
        &[
            "--scenes",
            "tests/grids/tiny.toml",
            "--partial",
            "32",
            "--reference",
            "40",
            "--only",
            "k_n",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let md = std::fs::read_to_string(dir.join("t/report.md")).unwrap();
    for heading in ["## 1. ", "## 2. ", "## 3. ", "## 4. ", "## 5. "] {
        assert!(md.contains(heading), "section {heading} missing");
    }
    for figure in [
        "sim_error_vs_strain.svg",
        "sim_error_vs_wall.svg",
        "surrogate_error_vs_training_time.svg",
        "stability_map.svg",
        "descriptors_along_y.svg",
    ] {
        let svg = std::fs::read_to_string(dir.join("t").join(figure))
            .unwrap_or_else(|e| panic!("{figure}: {e}"));
        assert!(
            svg.contains("<svg") && svg.len() > 1000,
            "{figure} is empty"
        );
        assert!(
            md.contains(&format!("({figure})")),
            "{figure} not linked from the report"
        );
    }

    // Section 1: partial averages of 8, 16, 32 snapshots for each of the 4 scenes; the
    // phi_loc error summed over scenes falls from 8 to 32 snapshots.
    let sim = rows(&md, "| 8 |")
        .into_iter()
        .chain(rows(&md, "| 32 |"))
        .collect::<Vec<_>>();
    assert_eq!(sim.len(), 8, "{md}");
    let (short, long): (f64, f64) = (
        sim[..4].iter().map(|r| percent(r[4])).sum(),
        sim[4..].iter().map(|r| percent(r[4])).sum(),
    );
    assert!(
        long < short,
        "phi_loc error does not fall with averaging: {short} -> {long}"
    );

    // Section 2: the tuned number of trees fits the validation set better than 3 trees, for
    // every output (with the physics backbone, more trees than the tuned number need not
    // help: at eta 0.3 they start to fit the training runs' noise).
    for mapping in ["mu", "theta", "dv"] {
        let few = rows(&md, &format!("| {mapping} | 3 |"));
        let tuned: Vec<Vec<&str>> = rows(&md, &format!("| {mapping} | "))
            .into_iter()
            .filter(|row| row[2].ends_with("(tuned)"))
            .collect();
        assert_eq!(
            (few.len(), tuned.len()),
            (1, 1),
            "{mapping}: rows of 3 and of the tuned trees"
        );
        // `mu 22.44 % (22.20 %), ...`: each output's error, its part beyond noise in brackets.
        let errors = |cell: &str| -> Vec<f64> {
            cell.split(", ")
                .map(|p| {
                    let error = p.split_once(' ').unwrap().1;
                    percent(error.split(" (").next().unwrap())
                })
                .collect()
        };
        for (a, b) in errors(few[0][4]).iter().zip(errors(tuned[0][4])) {
            assert!(
                b < *a,
                "{mapping}: the tuned trees' {b} % not better than 3 trees' {a} %"
            );
        }
    }

    // Section 3: one row per scene and mapping output (mu: mu; theta, dv and ext: phi_loc
    // and mu), each with a finite surrogate error.
    let side = rows(&md, "| tiny_");
    assert_eq!(side.len(), 4 * 7);
    assert!(side.iter().all(|r| percent(r[3]).is_finite()));

    // Section 4.
    let stability = rows(&md, "| k_n |");
    assert_eq!(stability.len(), 4 * 6);
    for r in &stability {
        let (factor, outcome): (f64, &str) = (r[3].parse().unwrap(), r[4]);
        if factor <= 1.0 {
            assert_eq!(outcome, "stable", "automatic dt unstable: {r:?}");
            assert!(
                r[7].parse::<f64>().unwrap().is_finite() && r[8].parse::<f64>().unwrap() < 0.1,
                "{r:?}"
            );
        }
        if factor == 1.0 {
            let gain: f64 = r[6]
                .split(", ")
                .nth(1)
                .and_then(|g| g.strip_suffix("x explicit"))
                .unwrap()
                .parse()
                .unwrap();
            assert!(gain >= 10.0, "implicit step gains only {gain}x: {r:?}");
        }
        if outcome == "blow-up" {
            assert_eq!(r[9], "yes", "the failure must name its cause: {r:?}");
        }
        if matches!(outcome, "stable" | "inaccurate") {
            assert!(!r[8].contains("NaN"), "a finished run with NaN: {r:?}");
        }
    }

    // Section 5: both descriptors for both validation profiles.
    assert_eq!(rows(&md, "| validate_00").len(), 4 + 2, "{md}");
}

#[test]
fn bad_report_options_are_refused_with_the_reason() {
    let dir = scratch("bad");
    for (args, expected) in [
        (
            vec!["--partial", "10"],
            "--partial 10: must be a multiple of 4",
        ),
        (
            vec!["--reference", "25"],
            "--reference 25: must be a multiple of 10",
        ),
        (
            vec!["--only", "gravity"],
            "--only gravity: not a swept parameter",
        ),
        (vec!["--train", "no/such.csv"], "no/such.csv: no such file"),
    ] {
        let out = report(&dir, &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains(expected),
            "{args:?}: {stderr}"
        );
    }
}
