//! The numbers of a figure written beside it: `<figure>.csv` next to `<figure>.svg`, one row
//! per drawn point (long format, loads in pandas without arguments): `panel` (from 1, left
//! to right), `series`,
//! `x_quantity`, `x`, `x_se`, `y_quantity`, `y` and `y_se` (the standard errors drawn as
//! error bars, empty when none), in the figure's units (the axis labels say which).
use std::path::{Path, PathBuf};

/// One drawn point.
pub struct Row<'a> {
    /// The panel, counted from 1 left to right.
    pub panel: usize,
    pub series: &'a str,
    pub x_quantity: &'a str,
    pub x: f64,
    pub x_se: Option<f64>,
    pub y_quantity: &'a str,
    pub y: f64,
    pub y_se: Option<f64>,
}

/// `<figure>.csv` beside the figure `svg`.
pub fn path_beside(svg: &Path) -> PathBuf {
    svg.with_extension("csv")
}

/// Writes `rows` beside the figure `svg` (atomically).
pub fn write<'a>(svg: &Path, rows: impl IntoIterator<Item = Row<'a>>) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "panel",
        "series",
        "x_quantity",
        "x",
        "x_se",
        "y_quantity",
        "y",
        "y_se",
    ])?;
    let se = |s: Option<f64>| s.map(|s| s.to_string()).unwrap_or_default();
    for r in rows {
        w.write_record([
            &r.panel.to_string(),
            r.series,
            r.x_quantity,
            &r.x.to_string(),
            &se(r.x_se),
            r.y_quantity,
            &r.y.to_string(),
            &se(r.y_se),
        ])?;
    }
    let bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    schema::write_atomic(&path_beside(svg), &bytes)?;
    Ok(())
}
