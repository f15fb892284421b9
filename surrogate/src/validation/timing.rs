//! Timings of the surrogate: end-to-end prediction by a saved model (load, read a table,
//! predict; what `bench-predict` reports and the report's surrogate sections reuse) and
//! training, each with the median of repeated timings.
use serde::Serialize;
use std::path::Path;
use std::time::{Duration, Instant};

use crate::data::dataset::Dataset;
use crate::data::mapping::Mapping;
use crate::error::Result;
use crate::models::booster::HyperParameters;
use crate::models::model::TrainedModel;
use crate::models::predictor::Predictor;
use crate::rheology::statistics::median;

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

/// Times `repeat` (at least 1) end-to-end predictions of `input` by the model of `mapping`
/// in `models`: wall-clock milliseconds of loading the model, reading the table and
/// predicting it.
pub fn time_mapping(
    mapping: &Mapping,
    models: &Path,
    input: &Path,
    repeat: usize,
) -> Result<Timing> {
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

/// Fits timed by [`timed_fit`]; the median is reported.
pub const FITS: usize = 3;

/// Trains `mapping` on `data` [`FITS`] times with the same (seeded) parameters, so the
/// models are identical, and returns the last model with the median wall-clock training
/// time in milliseconds.
pub fn timed_fit(
    mapping: &Mapping,
    data: &Dataset,
    params: &HyperParameters,
) -> Result<(TrainedModel, f64)> {
    let fit = || -> Result<(TrainedModel, f64)> {
        let started = Instant::now();
        let model = TrainedModel::train(mapping, data, params)?;
        Ok((model, started.elapsed().as_secs_f64() * 1e3))
    };
    let (mut model, first) = fit()?;
    let mut times = Vec::with_capacity(FITS);
    times.push(first);
    for _ in 1..FITS {
        let (next, ms) = fit()?;
        model = next;
        times.push(ms);
    }
    Ok((model, median(times)))
}
