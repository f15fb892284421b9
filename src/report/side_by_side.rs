//! Simulator and surrogate side by side: for each validation profile,
//! the surrogate's error against the long reference run of section 1 (relative L2 on
//! outputs scaled with the model's training ranges, eq 6.6) and its end-to-end time per
//! profile, and the shortest simulation, equilibration included, whose profile is as
//! close to the same reference in the same metric: measured among the partial runs when
//! one gets there, else extrapolated from the longest
//! with `error^2 = c (1/n + 1/reference)`.
use anyhow::Context;
use schema::Observable;
use sim::studies::convergence::{simulation_cost, ConvergenceRun, SimulationCost};
use std::fmt::Write as _;
use std::path::Path;
use surrogate::{model_errors, relative_l2, time_mapping, Dataset, Predictor, MAPPINGS};

/// One line of the side-by-side table.
pub struct Row {
    pub scene_id: String,
    pub mapping: &'static str,
    pub output: &'static str,
    pub surrogate_error: f64,
    /// Median end-to-end time (load model, read profile CSV, predict), ms.
    pub surrogate_ms: f64,
    pub simulation: SimulationCost,
    /// The reference's own noise in the same metric, `sqrt(c / reference)`.
    pub reference_noise: f64,
}

/// A surrogate error below this multiple of the reference's noise is mostly that noise:
/// the simulation length that matches it is uncertain by a large factor.
const NEAR_NOISE: f64 = 1.25;

/// Writes each run's reference profile to `dir/reference_<scene>.csv` and compares the
/// models in `models` with the simulation on it.
pub fn compare(runs: &[ConvergenceRun], models: &Path, dir: &Path) -> anyhow::Result<Vec<Row>> {
    let mut rows = Vec::new();
    for run in runs {
        let id = run.scene.file.name.clone();
        let path = dir.join(format!("reference_{id}.csv"));
        let csv = format!(
            "{}\n{}",
            schema::columns::header(),
            sim::output::result_files::profile_rows(&run.scene, &run.reference, &run.summary)
        );
        schema::write_atomic(&path, csv.as_bytes())?;
        let data = Dataset::read_csv(&path)?;
        for mapping in &MAPPINGS {
            let model = Predictor::load(models, mapping.name).with_context(|| {
                format!(
                    "loading the {} model from {}",
                    mapping.name,
                    models.display()
                )
            })?;
            let errors = model_errors(&model, mapping, &data)?;
            let ms = time_mapping(mapping, models, &path, 20)?.median_ms;
            for (k, &output) in mapping.outputs.iter().enumerate() {
                let min = model.meta().scaling.ranges[k].min;
                let observable = Observable::from_name(output)
                    .with_context(|| format!("output `{output}` is not a profile observable"))?;
                let (simulation, reference_noise) =
                    simulation_cost(run, observable, errors[k], |a, b| relative_l2(a, b, min));
                rows.push(Row {
                    scene_id: id.clone(),
                    mapping: mapping.name,
                    output,
                    surrogate_error: errors[k],
                    surrogate_ms: ms,
                    simulation,
                    reference_noise,
                });
            }
        }
    }
    Ok(rows)
}

/// Section 3 of the report.
pub fn markdown(rows: &[Row]) -> String {
    let mut md = String::from("## 3. Side by side\n\n");
    let _ = write!(md, "For each validation profile: the surrogate's error against the long reference run of section 1 \
        (relative L2 on outputs scaled with the training ranges, eq 6.6, with the reference run's own J, Theta or \
        Delta_v and phi as inputs) and its time per profile (load model + read CSV + predict, median of 20), next to \
        the shortest simulation from rest whose profile is as close to the same reference in the same metric. \
        A simulation marked extrapolated did not reach the error within the partial averages; its length follows from the \
        noise law `c (1/n + 1/R)` through the longest one. Where the surrogate's error is below {NEAR_NOISE} times the \
        reference's own noise `sqrt(c/R)`, most of it is that noise, and the matching simulation length is uncertain by a \
        large factor (marked uncertain). The surrogate's time does not include obtaining its inputs.\n\n");
    md.push_str("| profile | mapping: output | surrogate error | surrogate time | simulation to the same error | simulation wall time |\n|---|---|---|---|---|---|\n");
    for r in rows {
        let uncertain = if near_noise(r) {
            format!(
                "; uncertain: reference noise {:.2} %",
                100.0 * r.reference_noise
            )
        } else {
            String::new()
        };
        let (run, wall) = match r.simulation {
            SimulationCost::Measured(n, strain, wall) => (
                format!("{n} snapshots, strain {strain:.1} (measured{uncertain})"),
                minutes(wall),
            ),
            SimulationCost::Extrapolated(n, strain, wall) => (
                format!("{n:.0} snapshots, strain {strain:.1} (extrapolated{uncertain})"),
                minutes(wall),
            ),
            SimulationCost::BelowReferenceNoise(floor) => (
                format!(
                    "not measurable: below the reference's own noise {:.2} %",
                    100.0 * floor
                ),
                "-".into(),
            ),
        };
        let _ = writeln!(
            md,
            "| {} | {}: {} | {:.2} % | {:.1} ms | {run} | {wall} |",
            r.scene_id,
            r.mapping,
            r.output,
            100.0 * r.surrogate_error,
            r.surrogate_ms
        );
    }
    md.push('\n');
    for r in rows
        .iter()
        .filter(|r| r.mapping == "theta" && !near_noise(r))
    {
        if let SimulationCost::Measured(_, _, wall) | SimulationCost::Extrapolated(_, _, wall) =
            r.simulation
        {
            let _ = writeln!(md, "- {}: the surrogate gives {:.1} % error on {} in {:.1} ms where the simulator needs {}.",
                r.scene_id, 100.0 * r.surrogate_error, r.output, r.surrogate_ms, minutes(wall));
        }
    }
    md.push('\n');
    md
}

/// Whether `r`'s surrogate error is mostly the reference's own noise.
fn near_noise(r: &Row) -> bool {
    r.surrogate_error < NEAR_NOISE * r.reference_noise
}

/// A wall time in seconds, as minutes when over two minutes, e.g. `48 s`, `3.2 min`.
fn minutes(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else {
        format!("{:.1} min", s / 60.0)
    }
}
