//! Log-log line charts as SVG (error against run length, wall time or training time), with
//! an optional guide line of a given slope (e.g. -1/2 for a statistical error falling as
//! 1/sqrt(time)).
use crate::plots::profile_panels::COLOURS;
use anyhow::Context;
use plotters::prelude::*;
use std::path::Path;

/// One named line of `(x, y)` points; points with a non-positive or non-finite member are skipped.
pub struct Line {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// Draws `lines` on log-log axes to the SVG file `path`; `guide` adds a dashed grey line of
/// that slope through the first point of the first line.
pub fn draw(
    path: &Path,
    title: &str,
    axes: (&str, &str),
    lines: &[Line],
    guide: Option<f64>,
) -> anyhow::Result<()> {
    draw_inner(path, title, axes, lines, guide)
        .with_context(|| format!("drawing {}", path.display()))
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
    (x_label, y_label): (&str, &str),
    lines: &[Line],
    guide: Option<f64>,
) -> anyhow::Result<()> {
    let bounds = |f: fn((f64, f64)) -> f64| {
        let (lo, hi) = usable(lines)
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        if lo > hi {
            (0.1, 10.0)
        } else {
            (lo / 1.5, hi * 1.5)
        }
    };
    let (x0, x1) = bounds(|p| p.0);
    let (y0, y1) = bounds(|p| p.1);
    let root = SVGBackend::new(path, (760, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()?;
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
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RGBColor(120, 120, 120)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// A tick label with at most three significant digits, e.g. `0.3`, `150`, `2e-5`.
fn tick(v: f64) -> String {
    if (1e-3..1e5).contains(&v.abs()) {
        let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.0e}")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn ticks_are_short() {
        assert_eq!(super::tick(0.30000000000000004), "0.3");
        assert_eq!(super::tick(150.0), "150");
        assert_eq!(super::tick(0.0123456), "0.0123");
        assert_eq!(super::tick(2e-5), "2e-5");
    }
}
