//! Log-log line charts as SVG (error against run length, wall time or training time), with
//! an optional guide line of a given slope (e.g. -1/2 for a statistical error falling as
//! 1/sqrt(time)).
use crate::plots::chart_frame::{canvas, chart, legend, log_axis, log_bounds};
use crate::plots::figure_data::{self, Row};
use crate::plots::profile_panels::COLOURS;
use anyhow::Context;
use plotters::prelude::*;
use std::path::Path;

/// One named line of `(x, y)` points; points with a non-positive or non-finite member are skipped.
pub struct Line {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// Draws `lines` on log-log axes to the SVG file `path`, and their points beside it
/// ([`figure_data`]); `guide` adds a dashed grey line of that slope through the first point
/// of the first line.
pub fn draw(
    path: &Path,
    title: &str,
    axes: (&str, &str),
    lines: &[Line],
    guide: Option<f64>,
) -> anyhow::Result<()> {
    draw_inner(path, title, axes, lines, guide)
        .with_context(|| format!("drawing {}", path.display()))?;
    figure_data::write(path, rows(lines, axes))
}

/// The drawn points of `lines` as rows of the figure's data.
pub(crate) fn rows<'a>(
    lines: &'a [Line],
    (x, y): (&'a str, &'a str),
) -> impl Iterator<Item = Row<'a>> {
    lines.iter().flat_map(move |line| {
        usable(std::slice::from_ref(line)).map(move |(px, py)| Row {
            panel: 1,
            series: &line.name,
            x_quantity: x,
            x: px,
            x_se: None,
            y_quantity: y,
            y: py,
            y_se: None,
        })
    })
}

fn usable(lines: &[Line]) -> impl Iterator<Item = (f64, f64)> + '_ {
    lines
        .iter()
        .flat_map(|l| l.points.iter().copied())
        .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
}

fn draw_inner(
    path: &Path,
    title: &str,
    axes: (&str, &str),
    lines: &[Line],
    guide: Option<f64>,
) -> anyhow::Result<()> {
    let bounds = |f: fn((f64, f64)) -> f64| log_bounds(usable(lines).map(f), 1.5);
    let (x0, x1) = bounds(|p| p.0);
    let (y0, y1) = bounds(|p| p.1);
    canvas(path, |root| {
        let mut chart = chart(root, title, axes, log_axis(x0, x1), log_axis(y0, y1))?;
        for (i, line) in lines.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let pts: Vec<(f64, f64)> = usable(std::slice::from_ref(line)).collect();
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
            chart
                .draw_series(LineSeries::new(pts, colour.stroke_width(2)))?
                .label(line.name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        if let (Some(slope), Some((gx, gy))) = (guide, usable(lines).next()) {
            let ends = [x0, x1].map(|x| (x, gy * (x / gx).powf(slope)));
            chart
                .draw_series(DashedLineSeries::new(
                    ends,
                    6,
                    4,
                    RGBColor(120, 120, 120).stroke_width(1),
                ))?
                .label(format!("slope {slope}"))
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], RGBColor(120, 120, 120))
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    })
}
