//! Measured points with error bars beside model curves, on a logarithmic y axis and a
//! linear or logarithmic x axis, as SVG (the flow curves of homogeneous shear against the
//! jamming law), the legend in the corner that hides the fewest of them.
use crate::plots::chart_frame::{canvas, chart, emptiest_corner, legend, log_axis, log_bounds};
use crate::plots::figure_data::{self, Row};
use crate::plots::loglog::Line;
use crate::plots::profile_panels::COLOURS;
use anyhow::Context;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use std::path::Path;

/// Named measured points `(x, y, standard error of y)`, drawn as markers with error bars.
pub struct Points {
    pub name: String,
    pub points: Vec<(f64, f64, f64)>,
}

/// Draws `data` and the model `curves` (dashed lines) to the SVG file `path`, y logarithmic, x logarithmic when
/// `log_x` (a narrow range such as `phi` in [0.45, 0.6] reads better linear); non-positive
/// or non-finite values are left out. The points and curves are written beside the figure
/// ([`figure_data`]).
pub fn draw(
    path: &Path,
    title: &str,
    axes: (&str, &str),
    log_x: bool,
    data: &[Points],
    curves: &[Line],
) -> anyhow::Result<()> {
    let all = drawable(data, curves);
    let ((x0, x1), y) = ranges(&all, log_x);
    let corner = emptiest_corner(&all, (x0, x1), y, (log_x, true));
    let frame = Frame {
        title,
        axes,
        y,
        corner,
    };
    let result = if log_x {
        draw_inner(path, &frame, log_axis(x0, x1), data, curves)
    } else {
        draw_inner(path, &frame, x0..x1, data, curves)
    };
    result.with_context(|| format!("drawing {}", path.display()))?;
    let measured = data.iter().flat_map(|d| {
        d.points
            .iter()
            .filter(|&&(x, y, _)| usable(x, y))
            .map(move |&(x, y, se)| Row {
                panel: 1,
                series: &d.name,
                x_quantity: axes.0,
                x,
                x_se: None,
                y_quantity: axes.1,
                y,
                y_se: Some(se),
            })
    });
    figure_data::write(
        path,
        measured.chain(crate::plots::loglog::rows(curves, axes)),
    )
}

fn usable(x: f64, y: f64) -> bool {
    x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()
}

/// Every drawable value of the points and the curves.
fn drawable(data: &[Points], curves: &[Line]) -> Vec<(f64, f64)> {
    data.iter()
        .flat_map(|d| d.points.iter().map(|&(x, y, _)| (x, y)))
        .chain(curves.iter().flat_map(|c| c.points.iter().copied()))
        .filter(|&(x, y)| usable(x, y))
        .collect()
}

/// The x and y ranges of the drawable values `all`, padded.
fn ranges(all: &[(f64, f64)], log_x: bool) -> ((f64, f64), (f64, f64)) {
    let range = |f: fn(&(f64, f64)) -> f64, pad: f64| log_bounds(all.iter().map(f), pad);
    let x = if log_x {
        range(|p| p.0, 1.1)
    } else {
        let (lo, hi) = range(|p| p.0, 1.0);
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    };
    (x, range(|p| p.1, 1.3))
}

/// What frames a figure besides its x axis: title, axis names, y range, legend corner.
struct Frame<'a> {
    title: &'a str,
    axes: (&'a str, &'a str),
    y: (f64, f64),
    corner: SeriesLabelPosition,
}

fn draw_inner<X>(
    path: &Path,
    frame: &Frame,
    x_axis: X,
    data: &[Points],
    curves: &[Line],
) -> anyhow::Result<()>
where
    X: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
{
    canvas(path, |root| {
        let (y0, y1) = frame.y;
        let mut chart = chart(root, frame.title, frame.axes, x_axis, log_axis(y0, y1))?;
        for (i, d) in data.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let pts: Vec<(f64, f64, f64)> = d
                .points
                .iter()
                .copied()
                .filter(|&(x, y, _)| usable(x, y))
                .collect();
            chart.draw_series(pts.iter().map(|&(x, y, se)| {
                let lo = (y - se).max(y0);
                ErrorBar::new_vertical(x, lo, y, y + se, colour.stroke_width(1), 6)
            }))?;
            chart
                .draw_series(
                    pts.iter()
                        .map(|&(x, y, _)| Circle::new((x, y), 4, colour.filled())),
                )?
                .label(d.name.as_str())
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
        }
        for (i, c) in curves.iter().enumerate() {
            let colour = COLOURS[(data.len() + i) % COLOURS.len()];
            let pts: Vec<(f64, f64)> = c
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| usable(x, y))
                .collect();
            chart
                .draw_series(DashedLineSeries::new(pts, 8, 4, colour.stroke_width(2)))?
                .label(c.name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        legend(&mut chart, frame.corner.clone())?;
        Ok(())
    })
}
