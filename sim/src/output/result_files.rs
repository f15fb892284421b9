//! Result files: `profile.csv` (one row per bin, the column names of docs/physics.md
//! section 8 with `_se` standard errors), `stress.csv` (the parts of the stress per bin,
//! section 11), `summary.json`, `snapshot_sums.json` (the scene and
//! its averaged snapshot sums, from which the profile follows under any observable
//! convention). The particle frames are [`snapshot_format`](crate::output::snapshot_format)'s.
use crate::error::SimError;
use crate::input::scene::{Scene, SceneFile};
use crate::output::run_summary::{RunOutcome, RunSummary};
use crate::sampling::bin_averages::BinAverages;
use crate::sampling::block_sums::BlockSums;
use crate::sampling::stress_parts::StressParts;
use schema::columns::{self as dataset_columns, OBSERVABLES};
use schema::write_atomic;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// Formats a value; undefined (NaN) values become empty fields.
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        String::new()
    }
}

/// The rows of a profile table for `profile` of `scene`, run as `summary` says (no header).
pub fn profile_rows(scene: &Scene, profile: &BinAverages, summary: &RunSummary) -> String {
    let f = &scene.file;
    let mut out = String::new();
    let (mean, se) = (profile.mean.columns(), profile.se.columns());
    for k in 0..profile.y.len() {
        let _ = write!(
            out,
            "{},\"{}\",{},{},{},{},{},{},{},{}",
            f.name,
            scene.profile.expr(),
            scene.box_len[1],
            f.particles.phi,
            f.seed,
            num(summary.strain_to_steady),
            num(summary.momentum_residual.unwrap_or(f64::NAN)),
            &summary.code_version,
            num(profile.y[k]),
            num(profile.u_inf[k])
        );
        for c in 0..OBSERVABLES.len() {
            let _ = write!(out, ",{},{}", num(mean[c][k]), num(se[c][k]));
        }
        out.push('\n');
    }
    out
}

/// The rows of a stress-parts table (no header): the bin centre, then each part of
/// [`STRESS_PARTS`](schema::columns::STRESS_PARTS) and its standard error.
pub fn stress_rows(y: &[f64], stress: &StressParts) -> String {
    let mut out = String::new();
    for (k, y) in y.iter().enumerate() {
        out.push_str(&num(*y));
        for part in &stress.bins {
            let _ = write!(out, ",{},{}", num(part[k].mean), num(part[k].se));
        }
        out.push('\n');
    }
    out
}

/// Name of the snapshot-sums file in a result directory.
pub const SNAPSHOT_SUMS: &str = "snapshot_sums.json";
/// Name of the binned profile in a result directory.
pub const PROFILE: &str = "profile.csv";
/// Name of the run summary in a result directory.
pub const SUMMARY: &str = "summary.json";
/// Name of the stress parts per bin in a result directory.
pub const STRESS: &str = "stress.csv";
/// The files whose presence says a steady run is finished.
pub const RESULTS: [&str; 2] = [PROFILE, SUMMARY];
/// Every file [`write_results`] writes.
pub const WRITTEN: [&str; 4] = [PROFILE, STRESS, SUMMARY, SNAPSHOT_SUMS];

/// Contents of [`SNAPSHOT_SUMS`]: the scene as run and its averaged snapshot sums.
#[derive(Debug, Serialize, Deserialize)]
pub struct SnapshotSums {
    pub scene: SceneFile,
    pub sums: BlockSums,
}

/// Writes `dir/profile.csv`, `dir/stress.csv`, `dir/summary.json` and
/// `dir/snapshot_sums.json` atomically.
pub fn write_results(dir: &Path, scene: &Scene, outcome: &RunOutcome) -> Result<(), SimError> {
    let err = |e: std::io::Error| SimError::Output {
        path: dir.display().to_string(),
        message: e.to_string(),
    };
    std::fs::create_dir_all(dir).map_err(err)?;
    let csv = format!(
        "{}\n{}",
        dataset_columns::header(),
        profile_rows(scene, &outcome.profile, &outcome.summary)
    );
    write_atomic(&dir.join(PROFILE), csv.as_bytes())?;
    let stress = format!(
        "{}\n{}",
        dataset_columns::stress_parts_header(),
        stress_rows(&outcome.profile.y, &outcome.stress)
    );
    write_atomic(&dir.join(STRESS), stress.as_bytes())?;
    write_json(&dir.join(SUMMARY), &outcome.summary)?;
    let sums = SnapshotSums {
        scene: scene.file.clone(),
        sums: outcome.sums.clone(),
    };
    write_json(&dir.join(SNAPSHOT_SUMS), &sums)
}

fn write_json(path: &Path, value: &impl Serialize) -> Result<(), SimError> {
    let json = serde_json::to_vec_pretty(value).map_err(|e| SimError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(write_atomic(path, &json)?)
}
