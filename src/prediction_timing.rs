//! End-to-end timing of a saved model: load, read a table, predict (what `bench-predict`
//! reports and the report's surrogate sections reuse), with the median of repeated timings.
use serde::Serialize;
use std::path::Path;
use std::time::{Duration, Instant};
use surrogate::{median, Dataset, Mapping, Predictor};

/// Timings of one mapping, in milliseconds.
#[derive(Serialize)]
pub struct Timing {
    pub mapping: &'static str,
    pub rows: usize,
    pub runs: usize,
    /// The first run (load + read + predict).
    pub first_ms: f64,
    /// Median and minimum over all runs (load + read + predict).
    pub median_ms: f64,
    pub min_ms: f64,
    /// Medians of the three stages.
    pub load_ms: f64,
    pub read_ms: f64,
    pub predict_ms: f64,
}

/// Times `repeat` end-to-end predictions of `input` by the model of `mapping` in `models`.
pub fn time_mapping(
    mapping: &Mapping,
    models: &Path,
    input: &Path,
    repeat: usize,
) -> anyhow::Result<Timing> {
    let mut stages: Vec<[Duration; 3]> = Vec::with_capacity(repeat);
    let mut rows = 0;
    for _ in 0..repeat {
        let started = Instant::now();
        let model = Predictor::load(models, mapping.name)?;
        let loaded = Instant::now();
        let data = Dataset::read_csv(input)?;
        let read = Instant::now();
        rows = std::hint::black_box(model.predict(&data)?).nrows();
        stages.push([loaded - started, read - loaded, read.elapsed()]);
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let stage_median = |stage: &dyn Fn(&[Duration; 3]) -> Duration| {
        median(stages.iter().map(|s| ms(stage(s))).collect())
    };
    let total = |s: &[Duration; 3]| s[0] + s[1] + s[2];
    Ok(Timing {
        mapping: mapping.name,
        rows,
        runs: repeat,
        first_ms: ms(total(&stages[0])),
        median_ms: stage_median(&total),
        min_ms: stages
            .iter()
            .map(|s| ms(total(s)))
            .fold(f64::INFINITY, f64::min),
        load_ms: stage_median(&|s| s[0]),
        read_ms: stage_median(&|s| s[1]),
        predict_ms: stage_median(&|s| s[2]),
    })
}
