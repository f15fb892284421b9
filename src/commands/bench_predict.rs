//! `suspflow bench-predict --models DIR`: wall time of predicting one profile end to end
//! inside the process, as `predict` does it: load the model (sidecar and the trees of the
//! XGBoost JSON, `surrogate::Predictor`), read the input CSV file, predict every row. The target is a 50-bin profile in
//! under 10 ms. Each mapping is timed `--repeat` times; the first run (cold caches) is
//! reported apart from the median and minimum.
use anyhow::Context;
use std::fmt::Write as _;
use std::path::PathBuf;
use surrogate::{time_mapping, Mapping, Timing};

/// The end-to-end target per profile, in milliseconds.
const TARGET_MS: f64 = 10.0;

/// Most bins of the synthetic profile: a profile has tens of bins, and the table of 1e8
/// (about 20 GB of features and predictions) aborted on its allocation.
const ROWS_MAX: u64 = 1_000_000;

#[derive(clap::Args)]
pub struct Args {
    /// Directory of the trained models (`suspflow train --out`).
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Mappings to time (mu, theta, dv, ext); all four when absent.
    #[arg(long = "mapping")]
    mappings: Vec<String>,
    /// Input table with the mappings' feature columns; when absent, a synthetic profile of
    /// `--rows` bins is written to a temporary file.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Bins of the synthetic profile.
    #[arg(long, default_value_t = 50, allow_negative_numbers = true,
          value_parser = clap::value_parser!(u64).range(1..=ROWS_MAX))]
    rows: u64,
    /// Timed runs per mapping.
    #[arg(long, default_value_t = 20, allow_negative_numbers = true)]
    repeat: usize,
    /// Print a JSON array of records instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    anyhow::ensure!(args.repeat > 0, "--repeat must be at least 1");
    let mappings = Mapping::select(&args.mappings)?;
    let (input, temporary) = match &args.input {
        Some(path) => (path.clone(), false),
        None => (write_synthetic_profile(args.rows)?, true),
    };
    let timings: surrogate::Result<Vec<Timing>> = mappings
        .iter()
        .map(|m| time_mapping(m, &args.models, &input, args.repeat))
        .collect();
    if temporary {
        std::fs::remove_file(&input).with_context(|| format!("removing {}", input.display()))?;
    }
    let timings = timings?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&timings)?);
        return Ok(());
    }
    for t in &timings {
        println!(
            "{}: {} rows, load + read + predict: median {:.2} ms (load {:.2}, read {:.2}, predict {:.2}), \
             first {:.2} ms, min {:.2} ms over {} runs: {} the {TARGET_MS} ms target",
            t.mapping,
            t.rows,
            t.median_ms,
            t.load_ms,
            t.read_ms,
            t.predict_ms,
            t.first_ms,
            t.min_ms,
            t.runs,
            if t.median_ms < TARGET_MS { "under" } else { "OVER" }
        );
    }
    Ok(())
}

/// Writes a `rows`-bin profile holding every mapping's features to a temporary CSV file:
/// `u_inf = 0.1 sin(2 pi y / L)` with bins of width 2 and plausible local values that follow
/// the local shear, `|sin|`.
fn write_synthetic_profile(rows: u64) -> anyhow::Result<PathBuf> {
    let l_y = 2.0 * rows as f64;
    let mut csv = String::from("scene_id,profile,y,J,phi_loc,Theta,Delta_v,phi\n");
    for bin in 0..rows {
        let y = 2.0 * bin as f64 + 1.0;
        let shear = (2.0 * std::f64::consts::PI * y / l_y).cos().abs();
        let (j, phi_loc) = (1e-4 + 0.05 * shear, 0.58 - 0.06 * shear);
        let (theta, delta_v) = (0.01 + 0.05 * shear, 0.2 + 0.5 * (1.0 - shear));
        writeln!(
            csv,
            "bench,0.1*sin(2*pi*y/L),{y},{j},{phi_loc},{theta},{delta_v},0.54"
        )?;
    }
    let path =
        std::env::temp_dir().join(format!("suspflow-bench-predict-{}.csv", std::process::id()));
    schema::write_atomic(&path, csv.as_bytes())?;
    Ok(path)
}
