//! Scatter plots as SVG: panels side by side, each a plane of two columns with a logarithmic
//! horizontal axis, showing several named point sets in their own colours (the same set
//! keeps its colour in every panel), with one legend per panel.
use crate::plots::axis_label::with_units;
use crate::plots::chart_frame::svg_file;
use crate::plots::chart_frame::{formatter, log_axis};
use crate::plots::figure_data::{self, Row};
use crate::plots::profile_panels::COLOURS;
use anyhow::Context;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use std::path::Path;

/// One named set of `(x, y)` points; a point with a non-finite member or x <= 0 (or y <= 0
/// on a logarithmic y axis) is not drawn.
pub struct PointSet {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// One plane.
pub struct ScatterPanel {
    pub x_label: String,
    pub y_label: String,
    /// Whether the vertical axis is logarithmic too.
    pub log_y: bool,
    /// The sets, in legend order.
    pub sets: Vec<PointSet>,
}

const PANEL_SIZE: (u32, u32) = (620, 520);

/// Draws `panels` side by side under `title` to the SVG file `path`, and their points
/// beside it ([`figure_data`]).
pub fn scatter_panels(path: &Path, title: &str, panels: &[ScatterPanel]) -> anyhow::Result<()> {
    draw(path, title, panels).with_context(|| format!("drawing {}", path.display()))?;
    figure_data::write(
        path,
        panels.iter().enumerate().flat_map(|(k, panel)| {
            panel.sets.iter().flat_map(move |set| {
                drawn(panel, set).into_iter().map(move |(x, y)| Row {
                    panel: k + 1,
                    series: &set.name,
                    x_quantity: &panel.x_label,
                    x,
                    x_se: None,
                    y_quantity: &panel.y_label,
                    y,
                    y_se: None,
                })
            })
        }),
    )
}

fn drawn(panel: &ScatterPanel, set: &PointSet) -> Vec<(f64, f64)> {
    set.points
        .iter()
        .copied()
        .filter(|&(x, y)| x.is_finite() && y.is_finite() && x > 0.0 && (!panel.log_y || y > 0.0))
        .collect()
}

/// The axis range `(low, high)` of `values` with a margin: a factor on a logarithmic axis,
/// 5 % of the span on a linear one.
fn bounds(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    match (lo <= hi, log) {
        (false, true) => (0.1, 10.0),
        (false, false) => (0.0, 1.0),
        (true, true) => (lo / 1.5, hi * 1.5),
        (true, false) => {
            let pad = 0.05 * (hi - lo).max(1e-3 * hi.abs().max(1.0));
            (lo - pad, hi + pad)
        }
    }
}

fn draw(path: &Path, title: &str, panels: &[ScatterPanel]) -> anyhow::Result<()> {
    let width = PANEL_SIZE.0 * u32::try_from(panels.len().max(1))?;
    svg_file(path, (width, PANEL_SIZE.1), |root| {
        let root = root.titled(title, ("sans-serif", 18))?;
        let areas = root.split_evenly((1, panels.len().max(1)));
        for (panel, area) in panels.iter().zip(&areas) {
            let all = || panel.sets.iter().flat_map(|s| drawn(panel, s));
            let (x0, x1) = bounds(all().map(|p| p.0), true);
            let (y0, y1) = bounds(all().map(|p| p.1), panel.log_y);
            let mut builder = ChartBuilder::on(area);
            builder
                .margin(14)
                .x_label_area_size(44)
                .y_label_area_size(64);
            // The two axis kinds are different types: one branch each.
            if panel.log_y {
                let chart = builder.build_cartesian_2d(log_axis(x0, x1), log_axis(y0, y1))?;
                fill(chart, panel)?;
            } else {
                fill(builder.build_cartesian_2d(log_axis(x0, x1), y0..y1)?, panel)?;
            }
        }
        Ok(())
    })
}

/// Draws the axes of `chart`, each set of `panel` as small circles, and the legend.
fn fill<'a, X, Y>(
    mut chart: ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
    panel: &ScatterPanel,
) -> anyhow::Result<()>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let x_ticks = formatter(chart.as_coord_spec().x_spec());
    let y_ticks = formatter(chart.as_coord_spec().y_spec());
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc(with_units(&panel.x_label))
        .y_desc(with_units(&panel.y_label))
        .x_label_formatter(&x_ticks)
        .y_label_formatter(&y_ticks)
        .draw()?;
    for (i, set) in panel.sets.iter().enumerate() {
        let colour = COLOURS[(i + 1) % COLOURS.len()];
        chart
            .draw_series(
                drawn(panel, set)
                    .into_iter()
                    .map(|p| Circle::new(p, 2, colour.mix(0.6).filled())),
            )?
            .label(set.name.as_str())
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}
