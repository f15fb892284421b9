//! The frame shared by the line charts: an SVG canvas, the caption, axes with their units
//! and short tick labels (on a logarithmic axis only as many as fit), and the legend box.
use crate::plots::axis_label::with_units;
use plotters::coord::combinators::{LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// A chart drawn (for `'a`) on an SVG canvas (writing for `'b`) with axes of types `X`, `Y`.
pub type Chart<'a, 'b, X, Y> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>;

/// Draws with `draw` on a white SVG canvas of `size` pixels and writes it to the file
/// `path` whole ([`schema::write_atomic`]: never through a link, never half-written): the
/// one writer of every figure.
pub fn svg_file(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    schema::write_atomic(path, text.as_bytes())?;
    Ok(())
}

/// [`svg_file`] on the 760 x 520 canvas of the line charts.
pub fn canvas(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    svg_file(path, (760, 520), draw)
}

/// A captioned chart on `root` over the axes `x` and `y` (ranges, possibly log-scaled),
/// with their labels ([`with_units`]) and [`tick`] labels drawn ([`log_ticks`] on a
/// logarithmic axis).
pub fn chart<'a, 'b, X, Y>(
    root: &'a DrawingArea<SVGBackend<'b>, Shift>,
    title: &str,
    (x_label, y_label): (&str, &str),
    x: X,
    y: Y,
) -> anyhow::Result<Chart<'a, 'b, X::CoordDescType, Y::CoordDescType>>
where
    X: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 18))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(x, y)?;
    let x_ticks = formatter(chart.as_coord_spec().x_spec());
    let y_ticks = formatter(chart.as_coord_spec().y_spec());
    chart
        .configure_mesh()
        .x_desc(with_units(x_label))
        .y_desc(with_units(y_label))
        .x_label_formatter(&x_ticks)
        .y_label_formatter(&y_ticks)
        .draw()?;
    Ok(chart)
}

/// The tick labels of `axis`: [`log_ticks`] when it is logarithmic (its geometric mean
/// lies in its middle), else [`tick`].
pub fn formatter<R: Ranged<ValueType = f64>>(axis: &R) -> Box<dyn Fn(&f64) -> String> {
    let range = axis.range();
    let (lo, hi) = (range.start, range.end);
    let middle = axis.map(&(lo * hi).sqrt(), (0, 1000));
    if lo > 0.0 && hi > 2.0 * lo && (middle - 500).abs() <= 2 {
        let labelled = log_ticks(lo, hi);
        Box::new(move |v| {
            if labelled(*v) {
                tick(*v)
            } else {
                String::new()
            }
        })
    } else {
        Box::new(|v| tick(*v))
    }
}

/// Which ticks of a logarithmic axis over `[lo, hi]` get a label, so that labels never run
/// into each other: the decades only over more than two decades, 1-2-5 over more than 0.7,
/// every tick over less; the sparsest choice that still labels at least two values.
pub fn log_ticks(lo: f64, hi: f64) -> impl Fn(f64) -> bool {
    let mantissa = |v: f64| (v / 10f64.powf(v.log10().floor())).round() as u32;
    let within = |keep: &[u32]| {
        let mut count = 0;
        let mut decade = 10f64.powf(lo.log10().floor());
        while decade <= hi {
            count += keep
                .iter()
                .filter(|&&k| (lo..=hi).contains(&(f64::from(k) * decade)))
                .count();
            decade *= 10.0;
        }
        count
    };
    let decades = (hi / lo).log10();
    let keep: &'static [u32] = match decades {
        d if d > 2.0 && within(&[1]) >= 2 => &[1],
        d if d > 0.7 && within(&[1, 2, 5]) >= 2 => &[1, 2, 5],
        _ => &[1, 2, 3, 4, 5, 6, 7, 8, 9],
    };
    move |v: f64| v > 0.0 && keep.contains(&mantissa(v))
}

/// A logarithmic axis over `[lo, hi]` with its ticks placed here, not by plotters, whose
/// log axis has none below the first power of ten inside the range (none at all on
/// `[0.31, 0.54]`, none below 0.01 on `[0.002, 0.02]`): a light tick at every `m x 10^k`
/// inside (`m` = 1..9, or 1.0..9.9 in tenths when that leaves fewer than two), and a
/// labelled one at those [`log_ticks`] labels (all of them when that leaves fewer than two).
pub fn log_axis(lo: f64, hi: f64) -> WithKeyPoints<LogCoord<f64>> {
    let inside = |mantissas: &mut dyn Iterator<Item = f64>| -> Vec<f64> {
        let mantissas: Vec<f64> = mantissas.collect();
        (lo.log10().floor() as i32..=hi.log10().ceil() as i32)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let mut light = inside(&mut (1..=9).map(f64::from));
    if light.len() < 2 {
        light = inside(&mut (10..=99).map(|m| f64::from(m) / 10.0));
    }
    let labelled = log_ticks(lo, hi);
    let mut bold: Vec<f64> = light.iter().copied().filter(|&v| labelled(v)).collect();
    if bold.len() < 2 {
        bold.clone_from(&light);
    }
    (lo..hi)
        .log_scale()
        .with_key_points(bold)
        .with_light_points(light)
}

/// Draws the legend of the labelled series at `position`.
pub fn legend<'a, 'b: 'a, X, Y>(
    chart: &mut Chart<'a, 'b, X, Y>,
    position: SeriesLabelPosition,
) -> anyhow::Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// The corner of a plot spanning `x` and `y` (log scales where `log.0`, `log.1`) that holds
/// the fewest of `points`, where a legend hides the least: each corner counts the points in
/// the 45 % of the width and 35 % of the height next to it (a legend of about five lines);
/// ties keep the order upper left, upper right, lower left, lower right.
pub fn emptiest_corner(
    points: &[(f64, f64)],
    x: (f64, f64),
    y: (f64, f64),
    log: (bool, bool),
) -> SeriesLabelPosition {
    let share = |v: f64, (lo, hi): (f64, f64), log: bool| {
        if log {
            (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let placed: Vec<(f64, f64)> = points
        .iter()
        .map(|&(px, py)| (share(px, x, log.0), share(py, y, log.1)))
        .collect();
    let corners = [
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::LowerLeft, false, false),
        (SeriesLabelPosition::LowerRight, true, false),
    ];
    let hidden = |&(_, right, upper): &(SeriesLabelPosition, bool, bool)| {
        placed
            .iter()
            .filter(|&&(fx, fy)| {
                let across = if right { fx > 0.55 } else { fx < 0.45 };
                let up = if upper { fy > 0.65 } else { fy < 0.35 };
                across && up
            })
            .count()
    };
    let fewest = corners.iter().map(hidden).min().unwrap_or(0);
    corners
        .into_iter()
        .find(|c| hidden(c) == fewest)
        .map_or(SeriesLabelPosition::UpperLeft, |c| c.0)
}

/// The smallest and largest of `values`, divided and multiplied by `pad` (a margin on a
/// log axis); `(0.1, 10)` when there are none.
pub fn log_bounds(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if lo > hi {
        (0.1, 10.0)
    } else {
        (lo / pad, hi * pad)
    }
}

/// A tick label with at most three significant digits, e.g. `0.3`, `150`, `2e-5`.
pub fn tick(v: f64) -> String {
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

    #[test]
    fn log_axes_label_only_what_fits() {
        // Over three decades the decades alone; 0.07, 0.08, 0.09 would run together.
        let wide = super::log_ticks(1e-3, 0.5);
        assert!(wide(0.01) && wide(0.1) && !wide(0.08) && !wide(0.02));
        // Over one decade 1-2-5.
        let decade = super::log_ticks(0.04, 0.6);
        assert!(decade(0.1) && decade(0.2) && decade(0.05) && !decade(0.07));
        // Within a decade with a single 1-2-5 value inside, every tick (never a lone label).
        let narrow = super::log_ticks(0.055, 0.095);
        assert!(narrow(0.06) && narrow(0.07) && narrow(0.09));
    }

    #[test]
    fn a_log_axis_has_two_labelled_ticks_at_least_wherever_it_lies() {
        use plotters::coord::ranged1d::{BoldPoints, LightPoints, Ranged};
        let labelled = |lo: f64, hi: f64| super::log_axis(lo, hi).key_points(BoldPoints(100));
        // Below the first power of ten (plotters' own log axis: none; 0.01 and 0.02 only).
        assert_eq!(labelled(0.31, 0.54).len(), 2, "{:?}", labelled(0.31, 0.54));
        let partial = labelled(0.002, 0.021);
        assert!(partial.len() >= 4 && partial[0] < 0.01, "{partial:?}");
        // Within a tenth of a decade: ticks in tenths of the mantissa.
        let tight = labelled(0.41, 0.46);
        assert!(
            tight.len() >= 4 && tight.iter().all(|v| (0.41..=0.46).contains(v)),
            "{tight:?}"
        );
        // Over three decades the decades only, with the light ticks between them.
        assert_eq!(labelled(1e-3, 0.5).len(), 3);
        let light = super::log_axis(1e-3, 0.5).key_points(LightPoints::new(100, 1000));
        assert_eq!(light.len(), 9 + 9 + 5);
    }
}
