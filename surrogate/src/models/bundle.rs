//! The parts of a saved model (the bundle: trees `<mapping>.json`, sidecar
//! `<mapping>.meta.json`, training domain `<mapping>.domain.json`) must agree with each
//! other and hold values a trained model can have; every loader checks them here, so that
//! `predict`, `validate`, `solve` and `cross-validate` accept and refuse the same bundles.
//!
//! - the domain is of the model's features and training rows (the sidecar's hash and row
//!   count): another model's domain computes its flags in another feature space;
//! - the sidecar has a backbone exactly when its hyper-parameters say the trees learn the
//!   backbone's residual (without it the residuals would be read as outputs);
//! - the scaling ranges are ranges: finite, `min <= max`, and of nonzero width for the
//!   outputs (eq 6.4 divides by it);
//! - the backbone's law is physical ([`LocalRheology::check`](crate::rheology::local_rheology::LocalRheology::check));
//! - the trees number one per round and output (`n_estimators` rounds), or one per round
//!   with vector leaves.
use crate::data::training_domain::TrainingDomain;
use crate::models::booster::MultiStrategy;
use crate::models::model::ModelMeta;

/// The checks of the sidecar alone, also made when a model is trained.
pub fn check_meta(meta: &ModelMeta) -> Result<(), String> {
    meta.scaling.check(&meta.outputs, true)?;
    let learns_residual = meta.hyper_parameters.backbone;
    match &meta.backbone {
        None if learns_residual => {
            return Err(
                "the sidecar's hyper-parameters say the trees learn the residual of a \
                        backbone, but it holds none (predictions would be residuals)"
                    .into(),
            )
        }
        Some(_) if !learns_residual => {
            return Err(
                "the sidecar holds a backbone, but its hyper-parameters say the trees \
                        learn the outputs themselves"
                    .into(),
            )
        }
        None => {}
        Some(backbone) => {
            backbone.law.check()?;
            backbone.residual_scaling.check(&meta.outputs, false)?;
        }
    }
    Ok(())
}

/// [`check_meta`], then the sidecar against the domain and, when known, the trees' count.
pub fn check(
    meta: &ModelMeta,
    n_trees: Option<usize>,
    domain: &TrainingDomain,
) -> Result<(), String> {
    check_meta(meta)?;
    if domain.features != meta.features {
        return Err(format!(
            "its training domain is of features [{}], the model's are [{}] (the domain file of \
             another mapping?)",
            domain.features.join(", "),
            meta.features.join(", ")
        ));
    }
    let rows = domain.points.len() / domain.features.len().max(1);
    let data = &meta.training_data;
    if domain.training_fnv1a_64 != data.fnv1a_64 || rows != data.rows {
        return Err(format!(
            "its training domain holds {rows} rows of data {}, the model was trained on {} rows \
             of data {} ({}): the domain file of another training",
            domain.training_fnv1a_64, data.rows, data.fnv1a_64, data.source
        ));
    }
    let params = &meta.hyper_parameters;
    let per_round = match params.multi_strategy {
        MultiStrategy::OneOutputPerTree => meta.outputs.len(),
        MultiStrategy::MultiOutputTree => 1,
    };
    let expected = params.n_estimators as usize * per_round;
    match n_trees {
        Some(n) if n != expected => Err(format!(
            "its trees number {n}, the sidecar's {} rounds of {} output(s) make {expected}",
            params.n_estimators,
            meta.outputs.len()
        )),
        _ => Ok(()),
    }
}
