//! `predict` and `validate` with trained models, as `suspflow predict` and `suspflow
//! validate --json` compute them: the tree walk of `surrogate::Predictor` with the
//! training-domain check and the clipping into the physical range, and
//! `surrogate::Validation`'s relative L2 errors per mapping, output and profile (eq 6.6).
use crate::dataset::{dataset, Table};
use crate::error::Error;
use pyo3::prelude::*;
use std::path::PathBuf;
use surrogate::{Mapping, Predictor, TrainedModel, Validation};

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
}

/// Predictions of the model `dir/<mapping>.json` (+ `.meta.json`) for `table` (a CSV path or
/// CSV bytes holding the mapping's feature columns).
#[pyfunction]
pub fn predict(dir: PathBuf, mapping: &str, table: Table) -> Result<Predictions, Error> {
    let model = Predictor::load(&dir, mapping)?;
    let data = dataset(table)?;
    let (predicted, clipped) = model.predict_counting_clips(&data)?;
    let domain = model.check_domain(&data)?;
    Ok(Predictions {
        outputs: model.meta().outputs.clone(),
        values: predicted
            .columns()
            .into_iter()
            .map(|c| c.to_vec())
            .collect(),
        in_domain: domain.iter().map(|c| c.inside()).collect(),
        in_range: domain.iter().map(|c| c.in_range).collect(),
        domain_distance: domain.iter().map(|c| c.distance).collect(),
        clipped,
    })
}

/// Relative L2 errors (eq 6.6, outputs min-max scaled with the training ranges) of the models
/// in `dir` (the mappings named, all when empty) on `table`: records (mapping, output,
/// profile, rel_l2), per profile and for the in- and out-of-domain rows, in the order of
/// `suspflow validate --json`.
#[pyfunction]
#[pyo3(signature = (dir, table, mappings = Vec::new()))]
pub fn validate(
    dir: PathBuf,
    table: Table,
    mappings: Vec<String>,
) -> Result<Vec<(String, String, String, f64)>, Error> {
    let data = dataset(table)?;
    let mut records = Vec::new();
    for mapping in Mapping::select(&mappings)? {
        let model = TrainedModel::load(&dir, mapping.name).map_err(|e| {
            Error::context(
                format!("loading model `{}` from {}", mapping.name, dir.display()),
                e,
            )
        })?;
        let validation = Validation::run(&model, &data)
            .map_err(|e| Error::context(format!("validating model `{}`", mapping.name), e))?;
        for (j, output) in mapping.outputs.iter().enumerate() {
            for error in validation.errors.iter().chain(&validation.domain_errors) {
                records.push((
                    mapping.name.to_owned(),
                    output.to_string(),
                    error.profile.clone(),
                    error.per_output[j],
                ));
            }
        }
    }
    Ok(records)
}
