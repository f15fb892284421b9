//! The ensemble table of a dataset with replicas: per scene and bin, each observable's mean
//! over the scene's replicas (runs that differ only in `seed`), its standard error and the
//! replica count (columns in `schema::columns`), with a summary.
//!
//! With n >= 2 replicas of values x_i, the standard error is the between-replica one,
//! s(x) / sqrt(n) with s the sample standard deviation (n - 1 in the denominator). A scene
//! with one replica has no between-replica error: its row carries the run's own batch-means
//! error, and `se_from` says `batch_means` (`replicas` otherwise), so the two kinds are never
//! mixed silently. A value undefined in any replica (an empty cell: the simulator leaves J,
//! mu and Theta empty where P <= 0) leaves the ensemble value and its error empty.
//!
//! The summary compares, per observable, the two estimates of the same error: in each bin of
//! a replicated scene, the ratio of the between-replica standard error of the mean to the
//! batch-means standard error of the same mean, sqrt(sum_i se_i^2) / n (so the ratio is
//! s(x) / rms(se_i), about 1 when the batch-means errors describe the scatter between
//! realisations). It also gives the median relative standard error |se / mean|, over all
//! bins and over the bins away from the velocity extrema.
use schema::columns as col;
use schema::RunTable;
use serde::Serialize;

use crate::data::dataset::Dataset;
use crate::error::{Result, SurrogateError};
use crate::rheology::statistics::{mean_and_standard_error, median};

/// A bin is "away from the velocity extrema" when |u_inf| < this fraction of the scene's
/// largest |u_inf| (the criterion of datasets/README.md).
const AWAY_FROM_EXTREMA: f64 = 0.8;

/// The figures of one observable (see the module documentation); `None` where no bin has
/// them.
#[derive(Debug, Serialize)]
pub struct ObservableSummary {
    pub observable: String,
    /// Bins of replicated scenes with both errors defined and the batch-means one > 0.
    pub bins: usize,
    /// Median over those bins of (between-replica error) / (batch-means error).
    pub median_ratio: Option<f64>,
    /// Mean over those bins of the squared ratio (comparable with a mean squared z-score).
    pub mean_square_ratio: Option<f64>,
    /// Median over the bins of replicated scenes of |se / mean|.
    pub median_relative_se: Option<f64>,
    /// The same over the bins away from the velocity extrema.
    pub median_relative_se_away_from_extrema: Option<f64>,
}

/// The content of `<stem>.ensemble.json`.
#[derive(Debug, Serialize)]
pub struct EnsembleSummary {
    /// Scenes in the ensemble table.
    pub scenes: usize,
    /// Of which with two or more replicas.
    pub replicated_scenes: usize,
    /// Runs averaged.
    pub runs: usize,
    pub observables: Vec<ObservableSummary>,
}

/// An ensemble table and its summary.
pub struct Ensemble {
    /// The table as CSV text.
    pub csv: Vec<u8>,
    pub summary: EnsembleSummary,
}

/// One observable in one bin across a scene's replicas.
struct BinStats {
    mean: f64,
    /// Between-replica standard error (n >= 2) or the run's batch-means error (n = 1).
    se: f64,
    /// Between-replica / batch-means standard error of the mean (n >= 2, batch error > 0).
    ratio: Option<f64>,
}

impl BinStats {
    /// `values` and `errors`, one per replica, all finite.
    fn of(values: &[f64], errors: &[f64]) -> BinStats {
        let (mean, se) = mean_and_standard_error(values);
        if values.len() == 1 {
            return BinStats {
                mean,
                se: errors[0],
                ratio: None,
            };
        }
        let n = values.len() as f64;
        let batch = errors.iter().map(|e| e * e).sum::<f64>().sqrt() / n;
        BinStats {
            mean,
            se,
            ratio: (batch > 0.0).then(|| se / batch),
        }
    }
}

/// Figures gathered over bins for one observable.
#[derive(Default)]
struct Gathered {
    ratios: Vec<f64>,
    relative: Vec<f64>,
    relative_away: Vec<f64>,
}

/// Builds the ensemble table of a per-run table with the dataset columns (`source` names it
/// in messages). The table's reader has grouped the rows by scene and run and checked that
/// the replicas of a scene share its bins ([`RunTable`]).
pub fn build_ensemble(table: &RunTable, source: &str) -> Result<Ensemble> {
    let data = Dataset::from_csv_bytes(table.to_text().as_bytes(), source)?;
    let ids = data.group_keys()?;
    let seeds = data.text(col::SEED)?;
    let u_inf = data.column(col::U_INF)?;
    let [profile, l_y, phi, y_text, u_inf_text] =
        [col::PROFILE, col::L_Y, col::PHI, col::Y, col::U_INF].map(|c| data.text(c));
    let (profile, l_y, phi, y_text, u_inf_text) = (profile?, l_y?, phi?, y_text?, u_inf_text?);
    let csv_error = |e| SurrogateError::Csv {
        source_name: format!("the ensemble table of {source}"),
        source: e,
    };
    let mut writer = csv::Writer::from_writer(Vec::new());
    writer
        .write_record(col::ensemble_header())
        .map_err(csv_error)?;
    let mut gathered: Vec<Gathered> = col::OBSERVABLES
        .iter()
        .map(|_| Gathered::default())
        .collect();
    let columns = col::OBSERVABLES
        .iter()
        .map(|&o| Ok((data.column(o)?, data.column(&col::standard_error(o))?)))
        .collect::<Result<Vec<_>>>()?;
    let (mut scenes, mut replicated, mut runs) = (0, 0, 0);
    let versions = data.text(col::CODE_VERSION)?;
    for scene in table.scenes() {
        let replicas: Vec<Vec<usize>> = scene.into_iter().map(Vec::from_iter).collect();
        let bins = replicas[0].len();
        let id = &ids[replicas[0][0]];
        let n = replicas.len();
        scenes += 1;
        runs += n;
        replicated += usize::from(n > 1);
        let largest_u = replicas
            .iter()
            .flatten()
            .map(|&r| u_inf[r].abs())
            .fold(0.0, f64::max);
        for bin in 0..bins {
            let at = |k: usize| replicas[k][bin];
            let first = at(0);
            let mut record = vec![
                id.clone(),
                profile[first].clone(),
                l_y[first].clone(),
                phi[first].clone(),
                n.to_string(),
                replicas
                    .iter()
                    .map(|r| seeds[r[0]].as_str())
                    .collect::<Vec<_>>()
                    .join(" "),
                if n > 1 {
                    col::SE_FROM_REPLICAS
                } else {
                    col::SE_FROM_BATCH_MEANS
                }
                .to_string(),
                distinct((0..n).map(|k| versions[at(k)].as_str())),
                y_text[first].clone(),
                u_inf_text[first].clone(),
            ];
            let away = u_inf[first].abs() < AWAY_FROM_EXTREMA * largest_u;
            for ((values, errors), g) in columns.iter().zip(&mut gathered) {
                let x: Vec<f64> = (0..n).map(|k| values[at(k)]).collect();
                let e: Vec<f64> = (0..n).map(|k| errors[at(k)]).collect();
                if x.iter().chain(&e).any(|v| !v.is_finite()) {
                    record.extend([String::new(), String::new()]);
                    continue;
                }
                let stats = BinStats::of(&x, &e);
                record.extend([stats.mean.to_string(), stats.se.to_string()]);
                if n > 1 {
                    g.ratios.extend(stats.ratio);
                    if stats.mean != 0.0 {
                        let relative = (stats.se / stats.mean).abs();
                        g.relative.push(relative);
                        if away {
                            g.relative_away.push(relative);
                        }
                    }
                }
            }
            writer.write_record(&record).map_err(csv_error)?;
        }
    }
    let observables = col::OBSERVABLES
        .iter()
        .zip(gathered)
        .map(|(o, g)| ObservableSummary {
            observable: o.to_string(),
            bins: g.ratios.len(),
            median_ratio: (!g.ratios.is_empty()).then(|| median(g.ratios.clone())),
            mean_square_ratio: (!g.ratios.is_empty())
                .then(|| g.ratios.iter().map(|r| r * r).sum::<f64>() / g.ratios.len() as f64),
            median_relative_se: (!g.relative.is_empty()).then(|| median(g.relative)),
            median_relative_se_away_from_extrema: (!g.relative_away.is_empty())
                .then(|| median(g.relative_away)),
        })
        .collect();
    Ok(Ensemble {
        csv: writer
            .into_inner()
            .map_err(|e| csv_error(e.into_error().into()))?,
        summary: EnsembleSummary {
            scenes,
            replicated_scenes: replicated,
            runs,
            observables,
        },
    })
}

/// The distinct texts of `cells`, in first-seen order, separated by spaces.
fn distinct<'a>(cells: impl Iterator<Item = &'a str>) -> String {
    let mut seen: Vec<&str> = Vec::new();
    for c in cells {
        if !seen.contains(&c) {
            seen.push(c);
        }
    }
    seen.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dataset row: the given `(column, cell)` pairs, else every cell "1" except
    /// `scene_id`, `seed`, `y`, `u_inf`, `code_version` and `L_y` (4: two bins at y = 1, 3).
    fn row(id: &str, seed: u64, y: f64, cells: &[(&str, &str)]) -> String {
        let header = col::header();
        header
            .split(',')
            .map(|name| match cells.iter().find(|(c, _)| *c == name) {
                Some((_, v)) => v.to_string(),
                None => match name {
                    "scene_id" => id.to_string(),
                    "seed" => seed.to_string(),
                    "y" => y.to_string(),
                    "u_inf" => (0.1 * y).to_string(),
                    "code_version" => "v1".to_string(),
                    "L_y" => "4".to_string(),
                    _ => "1".to_string(),
                },
            })
            .collect::<Vec<_>>()
            .join(",")
    }

    fn table(rows: &[String]) -> RunTable {
        let text = format!("{}\n{}\n", col::header(), rows.join("\n"));
        RunTable::parse(&text).unwrap()
    }

    #[test]
    fn means_and_between_replica_errors_match_a_hand_computation() {
        // Scene a: three replicas, two bins; phi_loc 0.50, 0.53, 0.56 in bin 1 (batch-means
        // error 0.01 each), mu 0.4, 0.5, 0.9 in bin 2, undefined in seed 2's bin 1.
        // Scene b: one replica.
        let rows = [
            row(
                "a",
                1,
                1.0,
                &[("phi_loc", "0.50"), ("phi_loc_se", "0.01"), ("mu", "0.3")],
            ),
            row("a", 1, 3.0, &[("mu", "0.4"), ("mu_se", "0.05")]),
            row(
                "a",
                2,
                1.0,
                &[
                    ("phi_loc", "0.53"),
                    ("phi_loc_se", "0.01"),
                    ("mu", ""),
                    ("mu_se", ""),
                ],
            ),
            row("a", 2, 3.0, &[("mu", "0.5"), ("mu_se", "0.05")]),
            row(
                "a",
                7,
                1.0,
                &[("phi_loc", "0.56"), ("phi_loc_se", "0.01"), ("mu", "0.3")],
            ),
            row("a", 7, 3.0, &[("mu", "0.9"), ("mu_se", "0.05")]),
            row(
                "b",
                4,
                1.0,
                &[("phi_loc", "0.6"), ("phi_loc_se", "0.02"), ("L_y", "2")],
            ),
        ];
        let ensemble = build_ensemble(&table(&rows), "t").unwrap();
        let out = Dataset::from_csv_bytes(&ensemble.csv, "ensemble").unwrap();
        assert_eq!(out.column_names(), col::ensemble_header().as_slice());
        assert_eq!(out.n_rows(), 3);
        assert_eq!(out.text("scene_id").unwrap(), ["a", "a", "b"]);
        assert_eq!(out.column("replicas").unwrap(), [3.0, 3.0, 1.0]);
        assert_eq!(out.text("seeds").unwrap(), ["1 2 7", "1 2 7", "4"]);
        assert_eq!(
            out.text("se_from").unwrap(),
            ["replicas", "replicas", "batch_means"]
        );
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        // Bin 1: deviations -0.03, 0, +0.03 -> s^2 = 0.0018 / 2, se = 0.03 / sqrt(3).
        let (phi, phi_se) = (
            out.column("phi_loc").unwrap(),
            out.column("phi_loc_se").unwrap(),
        );
        assert!(
            close(phi[0], 0.53) && close(phi_se[0], 0.03 / 3f64.sqrt()),
            "{phi:?} {phi_se:?}"
        );
        // Bin 2: mean 0.6, deviations -0.2, -0.1, 0.3 -> s^2 = 0.14 / 2, se = sqrt(0.07 / 3).
        let (mu, mu_se) = (out.column("mu").unwrap(), out.column("mu_se").unwrap());
        assert!(
            close(mu[1], 0.6) && close(mu_se[1], (0.07f64 / 3.0).sqrt()),
            "{mu:?}"
        );
        // Undefined in one replica: undefined in the ensemble, not a mean of the others.
        assert_eq!(out.text("mu").unwrap()[0], "");
        assert_eq!(out.text("mu_se").unwrap()[0], "");
        // One replica: its own value and batch-means error.
        assert!(close(phi[2], 0.6) && close(phi_se[2], 0.02));
        let summary = &ensemble.summary;
        assert_eq!(
            (summary.scenes, summary.replicated_scenes, summary.runs),
            (2, 1, 4)
        );
        // phi_loc: bin 1 ratio = (0.03 / sqrt 3) / (sqrt(3 * 0.01^2) / 3) = 3; bin 2 has
        // phi_loc = 1 in every replica, ratio 0.
        let phi_summary = &summary.observables[4];
        assert_eq!(phi_summary.observable, "phi_loc");
        assert_eq!(phi_summary.bins, 2);
        assert!(close(phi_summary.mean_square_ratio.unwrap(), 9.0 / 2.0));
        assert!(close(phi_summary.median_ratio.unwrap(), 3.0));
        // Relative errors: bin 1 (|u_inf| = 0.1 < 0.8 * 0.3, away from the extrema) and bin 2.
        assert!(close(
            phi_summary.median_relative_se_away_from_extrema.unwrap(),
            0.03 / 3f64.sqrt() / 0.53
        ));
        // mu: only bin 2 is defined in every replica; ratio = sqrt(0.07/3) / (sqrt(3) 0.05 / 3).
        let mu_summary = &summary.observables[6];
        assert_eq!(mu_summary.bins, 1);
        assert!(close(
            mu_summary.median_ratio.unwrap(),
            (0.07f64 / 3.0).sqrt() / (3f64.sqrt() * 0.05 / 3.0)
        ));
        assert_eq!(mu_summary.median_relative_se_away_from_extrema, None);
    }
}
