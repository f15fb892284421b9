//! The ensemble table of a dataset with replicas (`surrogate::rheology::ensemble`), written
//! beside the dataset as `<stem>.ensemble.csv` with its summary `<stem>.ensemble.json`.
use schema::RunTable;
use std::path::{Path, PathBuf};
pub use surrogate::EnsembleSummary;
use surrogate::{build_ensemble, Ensemble};

/// The ensemble files beside dataset `path`: `<stem>.ensemble.csv` and `<stem>.ensemble.json`.
pub fn paths(path: &Path) -> [PathBuf; 2] {
    ["csv", "json"].map(|ext| {
        let mut name = path.with_extension("").into_os_string();
        name.push(format!(".ensemble.{ext}"));
        PathBuf::from(name)
    })
}

/// The ensemble table and summary of the per-run table `table` of `dataset`.
pub fn build(dataset: &Path, table: &RunTable) -> anyhow::Result<Ensemble> {
    Ok(build_ensemble(table, &dataset.display().to_string())?)
}

/// Writes `ensemble` beside `dataset` (atomically) and returns its summary.
pub fn write_beside(dataset: &Path, ensemble: Ensemble) -> anyhow::Result<EnsembleSummary> {
    let [table, summary] = paths(dataset);
    schema::write_atomic(&table, &ensemble.csv)?;
    let json = serde_json::to_string_pretty(&ensemble.summary)? + "\n";
    schema::write_atomic(&summary, json.as_bytes())?;
    Ok(ensemble.summary)
}

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
