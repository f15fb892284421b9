//! The ensemble table's summary (`rheometry::sweep_tables`) as text, for `generate` and
//! `merge`.
pub use rheometry::EnsembleSummary;

/// The summary as text lines: one per observable with its figures.
pub fn describe(summary: &EnsembleSummary) -> String {
    let cell = |v: Option<f64>, percent: bool| match v {
        Some(v) if percent => crate::surrogate_text::percent(v),
        Some(v) => format!("{v:.2}"),
        None => "-".to_string(),
    };
    let mut text = format!(
        "{} scenes ({} with replicas), {} runs\n{:<10} {:>6} {:>14} {:>14} {:>14} {:>18}\n",
        summary.scenes,
        summary.replicated_scenes,
        summary.runs,
        "observable",
        "bins",
        "median ratio",
        "mean ratio^2",
        "median se/|x|",
        "away from extrema"
    );
    for o in &summary.observables {
        text += &format!(
            "{:<10} {:>6} {:>14} {:>14} {:>14} {:>18}\n",
            o.observable,
            o.bins,
            cell(o.median_ratio, false),
            cell(o.mean_square_ratio, false),
            cell(o.median_relative_se, true),
            cell(o.median_relative_se_away_from_extrema, true)
        );
    }
    text
}
