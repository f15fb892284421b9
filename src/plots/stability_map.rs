//! Section 4 of the report, stability on stiff and extreme cases: the sweep's table and
//! its stability map, one row per (parameter, value), one column per dt multiple, each
//! cell coloured by the outcome (green stable, yellow finished but inaccurate, red blow-up
//! caught and explained, orange any other failure), as SVG.
use crate::plots::chart_frame::svg_file;
use anyhow::Context;
use plotters::prelude::*;
use sim::studies::stability_sweep::{
    self, box_height, CaseResult, Stability, SweepSize, DT_FACTORS,
};
use std::fmt::Write as _;
use std::path::Path;

const CELL_W: i32 = 90;
const CELL_H: i32 = 22;
const LABEL_W: i32 = 150;
const TOP: i32 = 50;

/// Draws `results` (in [`sim::studies::stability_sweep::cases`] order) to `path`.
fn draw(path: &Path, results: &[CaseResult]) -> anyhow::Result<()> {
    let rows = results.len() / DT_FACTORS.len();
    let size = (
        (LABEL_W + CELL_W * DT_FACTORS.len() as i32 + 20) as u32,
        (TOP + CELL_H * rows as i32 + 40) as u32,
    );
    svg_file(path, size, |root| {
        let svg_err = |e| anyhow::anyhow!("drawing {}: {e:?}", path.display());
        let text = |s: String, x: i32, y: i32| Text::new(s, (x, y), ("sans-serif", 13).into_font());
        root.draw(&text(
            "stability map (columns: dt / automatic dt)".into(),
            10,
            8,
        ))
        .map_err(svg_err)?;
        for (c, f) in DT_FACTORS.iter().enumerate() {
            root.draw(&text(
                format!("x {f}"),
                LABEL_W + CELL_W * c as i32 + 25,
                TOP - 18,
            ))
            .map_err(svg_err)?;
        }
        for (k, r) in results.iter().enumerate() {
            let (row, col) = ((k / DT_FACTORS.len()) as i32, (k % DT_FACTORS.len()) as i32);
            let (x, y) = (LABEL_W + CELL_W * col, TOP + CELL_H * row);
            if col == 0 {
                root.draw(&text(
                    format!("{} = {}", r.case.parameter, r.case.value),
                    10,
                    y + 4,
                ))
                .map_err(svg_err)?;
            }
            let colour = match (r.status, r.cause_named) {
                (Stability::Stable, _) => RGBColor(120, 200, 120),
                (Stability::Inaccurate, _) => RGBColor(240, 220, 90),
                (Stability::BlowUp, true) => RGBColor(220, 90, 90),
                _ => RGBColor(240, 170, 60),
            };
            root.draw(&Rectangle::new(
                [(x, y), (x + CELL_W - 4, y + CELL_H - 4)],
                colour.filled(),
            ))
            .map_err(svg_err)?;
            root.draw(&text(r.status.to_string(), x + 6, y + 3))
                .map_err(svg_err)?;
        }
        Ok(())
    })
    .with_context(|| format!("drawing {}", path.display()))
}

/// Draws `stability_map.svg` into `dir` and returns the section's markdown for `results`
/// of a sweep of `size` that took `sweep_s` seconds.
pub fn section(
    results: &[CaseResult],
    size: SweepSize,
    sweep_s: f64,
    dir: &Path,
) -> anyhow::Result<String> {
    draw(&dir.join("stability_map.svg"), results)?;
    let mut md = String::from("## 4. Stability on stiff and extreme cases\n\n");
    let _ = writeln!(md, "Base scene: phi 0.5, `0.15*sin(2*pi*y/L)`, radii 1 : 1.4, k_n 1e4, xi_min 1e-3, box {e} x {ly} x {e} \
        (larger for large spheres); one parameter changed at a time; each case runs 4 windows of {w} strain and {s} snapshots \
        0.01 strain apart, with the implicit step. dt factor = multiple of the automatic step (0.3 of the contact limit, capped by accuracy); the limit column gives what set it and the automatic step's gain over the explicit scheme's on the same scene. {} cases in {sweep_s:.0} s.\n",
        results.len(), e = size.box_edge, ly = box_height(size.box_edge), w = size.window_strain, s = size.snapshots);
    md.push_str("![stability map](stability_map.svg)\n\n");
    md.push_str("| parameter | value | dt factor | outcome | dt | limit, gain over explicit | max overlap / a_min | momentum residual | message names the cause |\n");
    md.push_str("|---|---|---|---|---|---|---|---|---|\n");
    let finished = |r: &CaseResult| r.status.finished();
    for r in results {
        let named = if finished(r) {
            ""
        } else if r.cause_named {
            "yes"
        } else {
            "no"
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.3e} | {} | {:.2e} | {:.4} | {} |",
            r.case.parameter,
            r.case.value,
            r.case.dt_factor,
            r.status,
            r.dt,
            r.dt_limit,
            r.max_overlap,
            r.momentum_residual,
            named
        );
    }
    let count = |f: &dyn Fn(&CaseResult) -> bool| results.iter().filter(|r| f(r)).count();
    let _ = writeln!(md, "\nAt the automatic dt and half of it: {} of {} cases unstable. Above it: {} of {} failed, {} of the failures \
        with a message naming step, particle and cause. Finished with a momentum residual above {}: {}. \
        Finished runs with a non-finite result: {}.\n",
        count(&|r| r.case.dt_factor <= 1.0 && r.status != Stability::Stable), count(&|r| r.case.dt_factor <= 1.0),
        count(&|r| r.case.dt_factor > 1.0 && !finished(r)), count(&|r| r.case.dt_factor > 1.0),
        count(&|r| !finished(r) && r.cause_named), stability_sweep::INACCURATE_RESIDUAL, count(&|r| r.status == Stability::Inaccurate),
        count(&|r| finished(r) && !(r.momentum_residual.is_finite() && r.max_overlap.is_finite())));
    md.push_str("Each failure with its error message:\n\n");
    for r in results.iter().filter(|r| !finished(r)) {
        let _ = writeln!(
            md,
            "- {} = {}, dt x {}: {}",
            r.case.parameter, r.case.value, r.case.dt_factor, r.message
        );
    }
    md.push('\n');
    Ok(md)
}
