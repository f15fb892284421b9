//! Section 1 of the report: simulation error against run length and wall time, as a
//! table per scene and two log-log figures (`sim_error_vs_strain.svg`,
//! `sim_error_vs_wall.svg`).
use crate::plots::loglog::{self, Line};
use sim::studies::convergence::{
    decorrelated_slope, log_slope, noise_constant, ConvergenceRun, DECORRELATED_STRAIN, OBSERVABLES,
};
use std::fmt::Write as _;
use std::path::Path;

/// Draws the figures into `dir` and returns the section's markdown.
pub fn section(runs: &[ConvergenceRun], dir: &Path) -> anyhow::Result<String> {
    let mut md = String::from("## 1. Simulation error against run time\n\n");
    let sample = runs
        .first()
        .map_or(f64::NAN, |r| r.scene.file.run.sample_strain);
    let _ = write!(md, "Each validation scene runs once: from rest to the steady state, then a partial averaging of n snapshots \
        ({sample} strain apart) and, after it, an independent reference average of R snapshots. Error = relative L2 \
        difference over bins between the n-snapshot profile and the reference, `||x_n - x_ref|| / ||x_ref||`. \
        Wall time counts from the start of the run (equilibration included); the scenes ran concurrently, one core each. \
        For independent averages the squared error is expected to be `c (1/n + 1/R)`: 1/sqrt(time) while n << R.\n\n");
    let mut by_strain = Vec::new();
    let mut by_wall = Vec::new();
    for run in runs {
        let s = &run.summary;
        let id = &run.scene.file.name;
        let _ = writeln!(
            md,
            "### {id}: `{}`, L_y = {}, phi = {}, N = {}\n",
            run.scene.file.fluid.profile,
            run.scene.box_len[1],
            run.scene.file.particles.phi,
            s.n_particles
        );
        let _ = writeln!(md, "Steady at strain {:.1} after {:.0} s; reference R = {} snapshots ({:.1} strain); whole run {:.0} s, \
            {:.2e} particle-steps/s, momentum residual of the whole run {:.4}.\n",
            s.strain_to_steady, run.wall_to_steady_s, run.reference_snapshots,
            run.reference_snapshots as f64 * run.scene.file.run.sample_strain, s.wall_s, s.particle_steps_per_s,
            s.momentum_residual.unwrap_or(f64::NAN));
        md.push_str("| snapshots n | strain averaged | wall time (s) | error phi_loc | error mu | error u |\n|---|---|---|---|---|---|\n");
        for p in &run.partials {
            let _ = writeln!(
                md,
                "| {} | {:.2} | {:.1} | {:.2} % | {:.2} % | {:.2} % |",
                p.average.snapshots,
                p.averaging_strain,
                p.average.wall_s,
                100.0 * p.error[0],
                100.0 * p.error[1],
                100.0 * p.error[2]
            );
        }
        md.push('\n');
        for (k, name) in OBSERVABLES.iter().enumerate() {
            let points: Vec<(f64, f64)> = run
                .partials
                .iter()
                .map(|p| (p.average.snapshots as f64, p.error[k]))
                .collect();
            let last = run
                .partials
                .last()
                .expect("a convergence run has partial profiles");
            let c = noise_constant(
                last.average.snapshots as f64,
                last.error[k],
                run.reference_snapshots as f64,
            );
            let _ = writeln!(md, "- {name}: log-log slope of error against n {:.2} over all n, {:.2} over averages of at least \
                {DECORRELATED_STRAIN} strain with the reference's noise taken out (1/sqrt: -0.5); noise law through the longest \
                average: sqrt(c) = {:.3}, so 1 % would need n = {:.0} snapshots ({:.0} strain); reference's own noise sqrt(c/R) = {:.2} %.",
                log_slope(&points), decorrelated_slope(run, k), c.sqrt(), c / 1e-4,
                c / 1e-4 * run.scene.file.run.sample_strain, 100.0 * (c / run.reference_snapshots as f64).sqrt());
            by_strain.push(Line {
                name: format!("{id} {name}"),
                points: run
                    .partials
                    .iter()
                    .map(|p| (p.averaging_strain, p.error[k]))
                    .collect(),
            });
            by_wall.push(Line {
                name: format!("{id} {name}"),
                points: run
                    .partials
                    .iter()
                    .map(|p| (p.average.wall_s, p.error[k]))
                    .collect(),
            });
        }
        md.push('\n');
    }
    loglog::draw(
        &dir.join("sim_error_vs_strain.svg"),
        "simulation error against strain averaged",
        (
            "strain averaged after the steady state",
            "relative L2 error vs reference",
        ),
        &by_strain,
        Some(-0.5),
    )?;
    loglog::draw(
        &dir.join("sim_error_vs_wall.svg"),
        "simulation error against wall time",
        ("wall time from rest (s)", "relative L2 error vs reference"),
        &by_wall,
        None,
    )?;
    md.push_str("![error against strain](sim_error_vs_strain.svg)\n\n![error against wall time](sim_error_vs_wall.svg)\n\n");
    Ok(md)
}
