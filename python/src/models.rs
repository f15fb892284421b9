//! `predict` and `validate` with trained models, as `suspflow predict` and `suspflow
//! validate --json` compute them: the tree walk of `surrogate::Predictor` with the
//! training-domain check, the clipping into the physical range and the intervals, and
//! `surrogate::Validation`'s relative L2 errors per mapping, output and profile (eq 6.6),
//! their part beyond noise and the intervals' coverage (`surrogate::records`).
use crate::dataset::{dataset, Table};
use crate::error::Error;
use pyo3::prelude::*;
use std::path::PathBuf;
use surrogate::{records as records_of, Mapping, Predictor, TrainedModel, Validation};

/// Predictions of one mapping for every row of a table.
#[pyclass(module = "suspflow._native", frozen, get_all)]
pub struct Predictions {
    /// The mapping's output names (e.g. `phi_loc`, `mu`).
    pub outputs: Vec<String>,
    /// One list per output, one value per row, clipped into the output's physical range.
    pub values: Vec<Vec<f64>>,
    /// Whether each row lies inside the training domain.
    pub in_domain: Vec<bool>,
    /// Whether each row lies inside every feature's training range.
    pub in_range: Vec<bool>,
    /// Distance of each row to the nearest training rows, in units of the domain threshold.
    pub domain_distance: Vec<f64>,
    /// Predicted values that left their physical range and were clipped.
    pub clipped: usize,
    /// The intervals' level, and per output one list of lower and one of upper bounds per
    /// row; `None` for a model saved without intervals.
    pub level: f64,
    pub lower: Option<Vec<Vec<f64>>>,
    pub upper: Option<Vec<Vec<f64>>>,
}

/// Predictions of the model `dir/<mapping>.json` (+ `.meta.json`) for `table` (a CSV path or
/// CSV bytes holding the mapping's feature columns), with their intervals at `level`.
#[pyfunction]
#[pyo3(signature = (dir, mapping, table, level = surrogate::DEFAULT_LEVEL))]
pub fn predict(
    dir: PathBuf,
    mapping: &str,
    table: Table,
    level: f64,
) -> Result<Predictions, Error> {
    let model = Predictor::load(&dir, mapping)?;
    let data = dataset(table)?;
    let prediction = model.predict_with_intervals(&data, level)?;
    let domain = model.check_domain(&data)?;
    let columns = |a: &ndarray::Array2<f64>| -> Vec<Vec<f64>> {
        a.columns().into_iter().map(|c| c.to_vec()).collect()
    };
    Ok(Predictions {
        outputs: model.meta().outputs.clone(),
        values: columns(&prediction.values),
        in_domain: domain.iter().map(|c| c.inside()).collect(),
        in_range: domain.iter().map(|c| c.in_range).collect(),
        domain_distance: domain.iter().map(|c| c.distance).collect(),
        clipped: prediction.clipped,
        level,
        lower: prediction.intervals.as_ref().map(|i| columns(&i.lower)),
        upper: prediction.intervals.as_ref().map(|i| columns(&i.upper)),
    })
}

/// One record of [`validate`]: mapping, output, profile, rel_l2, beyond_noise, coverage,
/// interval_width (the last three `None` where unknown).
type ValidationRecord = (
    String,
    String,
    String,
    f64,
    Option<f64>,
    Option<f64>,
    Option<f64>,
);

/// Relative L2 errors (eq 6.6, outputs min-max scaled with the training ranges) of the models
/// in `dir` (the mappings named, all when empty) on `table`, their part beyond the targets'
/// own noise, and the coverage and mean width of the intervals at `level`: records
/// (mapping, output, profile, rel_l2, beyond_noise, coverage, interval_width), per profile
/// and for the in- and out-of-domain rows, in the order of `suspflow validate --json`.
#[pyfunction]
#[pyo3(signature = (dir, table, mappings = Vec::new(), level = surrogate::DEFAULT_LEVEL))]
pub fn validate(
    dir: PathBuf,
    table: Table,
    mappings: Vec<String>,
    level: f64,
) -> Result<Vec<ValidationRecord>, Error> {
    let data = dataset(table)?;
    let mut records = Vec::new();
    for mapping in Mapping::select(&mappings)? {
        let model = TrainedModel::load(&dir, mapping.name).map_err(|e| {
            Error::context(
                format!("loading model `{}` from {}", mapping.name, dir.display()),
                e,
            )
        })?;
        let validation = Validation::run_at(&model, &data, level)
            .map_err(|e| Error::context(format!("validating model `{}`", mapping.name), e))?;
        records.extend(records_of(mapping, &validation).into_iter().map(|r| {
            (
                r.mapping.to_owned(),
                r.output.to_owned(),
                r.profile.to_owned(),
                r.rel_l2,
                r.beyond_noise,
                r.coverage,
                r.interval_width,
            )
        }));
    }
    Ok(records)
}
