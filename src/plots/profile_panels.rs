//! Figures of quantities along the position `y` across the box, as SVG.
//!
//! A figure is a row of panels sharing the vertical axis, the position `y` (in units of the
//! small radius `a`); each panel shows one quantity on its horizontal axis, as one or more
//! named series. A series with standard errors is data (markers with horizontal error bars
//! of one standard error); a series without is a curve (a line through small markers). A
//! series keeps its colour in every panel of the figure, and one legend below the panels
//! names them all. Text is left to the SVG viewer's sans-serif font.

use crate::plots::chart_frame::svg_file;
use std::ops::Range;
use std::path::Path;

use anyhow::Context;
use plotters::prelude::*;

use crate::plots::axis_label::with_units;
use crate::plots::figure_data::{self, Row};

/// One named curve or data set of a panel.
pub struct Series {
    pub name: String,
    /// `(y, value)` pairs; a pair with a non-finite member is not drawn.
    pub points: Vec<(f64, f64)>,
    /// One standard error per point (non-finite: no bar), or `None` for a curve.
    pub errors: Option<Vec<f64>>,
}

/// One quantity along `y`.
pub struct Panel {
    /// Axis label of the quantity, e.g. `phi_loc`.
    pub quantity: String,
    pub series: Vec<Series>,
}

const PANEL_WIDTH: u32 = 380;
const HEIGHT: u32 = 560;
const LEGEND_HEIGHT: u32 = 30;

/// Series colours, in order of first appearance in the figure (then again from the start).
pub(crate) const COLOURS: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
];

/// Writes `panels` side by side under `title` to the SVG file `path`, and their points
/// beside it ([`figure_data`]: x the quantity with its error, y the position).
pub fn profile_panels(path: &Path, title: &str, panels: &[Panel]) -> anyhow::Result<()> {
    draw(path, title, panels).with_context(|| format!("drawing {}", path.display()))?;
    figure_data::write(
        path,
        panels.iter().enumerate().flat_map(|(k, panel)| {
            panel.series.iter().flat_map(move |series| {
                finite_points(series).map(move |(y, value, error)| Row {
                    panel: k + 1,
                    series: &series.name,
                    x_quantity: &panel.quantity,
                    x: value,
                    x_se: Some(error).filter(|e| e.is_finite()),
                    y_quantity: "y",
                    y,
                    y_se: None,
                })
            })
        }),
    )
}

fn draw(path: &Path, title: &str, panels: &[Panel]) -> anyhow::Result<()> {
    let width = PANEL_WIDTH * u32::try_from(panels.len().max(1))?;
    svg_file(path, (width, HEIGHT), |root| {
        let root = root.titled(title, ("sans-serif", 18))?;
        let (root, legend) = root.split_vertically(HEIGHT - LEGEND_HEIGHT - 30);
        let names = series_names(panels);
        let colour = |name: &str| {
            let index = names.iter().position(|n| n == name).unwrap_or(0);
            COLOURS[index % COLOURS.len()]
        };
        let y_range = padded(panels.iter().flat_map(|p| &p.series).flat_map(|s| {
            s.points
                .iter()
                .filter(|(y, v)| y.is_finite() && v.is_finite())
                .map(|&(y, _)| y)
        }));
        for (panel, area) in panels.iter().zip(root.split_evenly((1, panels.len()))) {
            let mut chart = ChartBuilder::on(&area)
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d(value_range(panel), y_range.clone())?;
            chart
                .configure_mesh()
                .x_desc(with_units(&panel.quantity))
                .y_desc(with_units("y"))
                .x_labels(5)
                .draw()?;
            for series in &panel.series {
                let colour = colour(&series.name);
                let points: Vec<(f64, f64)> = finite_points(series)
                    .map(|(y, value, _)| (value, y))
                    .collect();
                if series.errors.is_some() {
                    chart.draw_series(finite_points(series).map(|(y, value, error)| {
                        let error = if error.is_finite() { error } else { 0.0 };
                        ErrorBar::new_horizontal(
                            y,
                            value - error,
                            value,
                            value + error,
                            colour.mix(0.6).stroke_width(1),
                            6,
                        )
                    }))?;
                    chart
                        .draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
                } else {
                    chart
                        .draw_series(points.iter().map(|&p| Circle::new(p, 2, colour.filled())))?;
                    chart.draw_series(LineSeries::new(points, colour.stroke_width(2)))?;
                }
            }
        }
        let mut x = 60;
        let y = i32::try_from(LEGEND_HEIGHT / 2)?;
        for name in &names {
            let colour = colour(name);
            legend.draw(&PathElement::new(
                vec![(x, y), (x + 24, y)],
                colour.stroke_width(2),
            ))?;
            legend.draw(&Circle::new((x + 12, y), 3, colour.filled()))?;
            legend.draw(&Text::new(
                name.as_str(),
                (x + 30, y - 7),
                ("sans-serif", 14),
            ))?;
            x += 50 + 8 * i32::try_from(name.len())?;
        }
        Ok(())
    })
}

/// The drawable points of `series` as `(y, value, error)`; the error is NaN for a curve.
fn finite_points(series: &Series) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
    series
        .points
        .iter()
        .enumerate()
        .filter(|(_, (y, value))| y.is_finite() && value.is_finite())
        .map(|(i, &(y, value))| {
            let error = series
                .errors
                .as_ref()
                .and_then(|errors| errors.get(i).copied())
                .unwrap_or(f64::NAN);
            (y, value, error)
        })
}

/// Distinct series names over all panels, in order of first appearance (the colour index).
fn series_names(panels: &[Panel]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for series in panels.iter().flat_map(|p| &p.series) {
        if !names.contains(&series.name) {
            names.push(series.name.clone());
        }
    }
    names
}

/// The range of a panel's values, error bars included.
fn value_range(panel: &Panel) -> Range<f64> {
    padded(panel.series.iter().flat_map(|series| {
        finite_points(series).flat_map(|(_, value, error)| {
            let error = if error.is_finite() { error } else { 0.0 };
            [value - error, value + error]
        })
    }))
}

/// The range of `values` widened by 5 % on each side; `0..1` when there are none, and a
/// range around the value when all are equal.
fn padded(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (min, max) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if min > max {
        return 0.0..1.0;
    }
    let pad = if max > min {
        0.05 * (max - min)
    } else {
        0.1 * min.abs().max(1e-12)
    };
    (min - pad)..(max + pad)
}
