//! The stability map of the sweep: one row per (parameter, value), one column per dt
//! multiple, each cell coloured by the outcome (green stable, yellow finished but
//! inaccurate, red blow-up caught and explained, orange any other failure), as SVG.
use crate::stability_sweep::{CaseResult, DT_FACTORS};
use anyhow::Context;
use plotters::prelude::*;
use std::path::Path;

const CELL_W: i32 = 90;
const CELL_H: i32 = 22;
const LABEL_W: i32 = 150;
const TOP: i32 = 50;

/// Draws `results` (in [`crate::stability_sweep::cases`] order) to `path`.
pub fn draw(path: &Path, results: &[CaseResult]) -> anyhow::Result<()> {
    let rows = results.len() / DT_FACTORS.len();
    let size = ((LABEL_W + CELL_W * DT_FACTORS.len() as i32 + 20) as u32, (TOP + CELL_H * rows as i32 + 40) as u32);
    let root = SVGBackend::new(path, size).into_drawing_area();
    let svg_err = |e| anyhow::anyhow!("drawing {}: {e:?}", path.display());
    root.fill(&WHITE).map_err(svg_err)?;
    let text = |s: String, x: i32, y: i32| Text::new(s, (x, y), ("sans-serif", 13).into_font());
    root.draw(&text("stability map (columns: dt / automatic dt)".into(), 10, 8)).map_err(svg_err)?;
    for (c, f) in DT_FACTORS.iter().enumerate() {
        root.draw(&text(format!("x {f}"), LABEL_W + CELL_W * c as i32 + 25, TOP - 18)).map_err(svg_err)?;
    }
    for (k, r) in results.iter().enumerate() {
        let (row, col) = ((k / DT_FACTORS.len()) as i32, (k % DT_FACTORS.len()) as i32);
        let (x, y) = (LABEL_W + CELL_W * col, TOP + CELL_H * row);
        if col == 0 {
            root.draw(&text(format!("{} = {}", r.case.parameter, r.case.value), 10, y + 4)).map_err(svg_err)?;
        }
        let colour = match (r.status, r.cause_named) {
            ("stable", _) => RGBColor(120, 200, 120),
            ("inaccurate", _) => RGBColor(240, 220, 90),
            ("blow-up", true) => RGBColor(220, 90, 90),
            _ => RGBColor(240, 170, 60),
        };
        root.draw(&Rectangle::new([(x, y), (x + CELL_W - 4, y + CELL_H - 4)], colour.filled())).map_err(svg_err)?;
        root.draw(&text(r.status.to_string(), x + 6, y + 3)).map_err(svg_err)?;
    }
    root.present().with_context(|| format!("writing {}", path.display()))
}
