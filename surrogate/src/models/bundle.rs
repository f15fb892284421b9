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
use std::path::Path;

use crate::data::files;
use crate::data::mapping::Mapping;
use crate::data::training_domain::TrainingDomain;
use crate::error::{name_differences, SurrogateError};
use crate::models::booster::MultiStrategy;
use crate::models::model_meta::{ModelMeta, ModelPaths};
use crate::models::xgboost_json::ShapeJson;

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

/// Reads the sidecar `<dir>/<name>.meta.json`, the trees `<dir>/<name>.json` and the
/// training domain `<dir>/<name>.domain.json`, and checks that the sidecar, the trees'
/// counts and feature names (read first, from the file's `learner_model_param`, so that a
/// model of another mapping is named as such before its trees are read), the domain's
/// feature count and mapping `name`'s current definition agree; then reads the trees with
/// `load_trees` (the path and its bytes), then checks the whole bundle
/// ([`crate::models::bundle::check`]) with the tree count `n_trees` gives. Trees that
/// store no feature names are checked by their counts alone.
pub(crate) fn load_bundle<T>(
    dir: &Path,
    name: &str,
    load_trees: impl FnOnce(&Path, &[u8]) -> crate::error::Result<T>,
    n_trees: impl FnOnce(&T) -> Option<usize>,
) -> crate::error::Result<(ModelMeta, T, TrainingDomain)> {
    let mapping = Mapping::by_name(name)?;
    let paths = ModelPaths::new(dir, name);
    let (trees_path, meta_path) = (&paths.trees, &paths.meta);
    let meta: ModelMeta = files::read_json(meta_path, "a model sidecar")?;
    let trees_json = files::read(trees_path)?;
    let shape: ShapeJson = files::parse_json(trees_path, &trees_json, "an XGBoost JSON model")?;
    let (n_features, n_outputs) = shape
        .learner
        .learner_model_param
        .counts(&trees_path.display().to_string())?;
    let tree_features = shape.learner.feature_names;
    let domain: TrainingDomain = files::read_json(&paths.domain, "a training domain")?;
    let mismatch = |detail: String| SurrogateError::FeatureMismatch { detail };
    if meta.mapping != mapping.name {
        return Err(mismatch(format!(
            "{} describes mapping `{}`, not `{}` (the sidecar of another mapping?)",
            meta_path.display(),
            meta.mapping,
            mapping.name
        )));
    }
    for (what, listed, defined) in [
        ("features", &meta.features, mapping.features),
        ("outputs", &meta.outputs, mapping.outputs),
    ] {
        if listed
            .iter()
            .map(String::as_str)
            .ne(defined.iter().copied())
        {
            return Err(mismatch(format!(
                "{} lists {what} [{}], mapping `{}` now has [{}]: {}",
                meta_path.display(),
                listed.join(", "),
                mapping.name,
                defined.join(", "),
                name_differences(defined, listed)
            )));
        }
    }
    let counted = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    for (found, defined, what, param) in [
        (n_outputs, mapping.outputs, "output", "num_target"),
        (n_features, mapping.features, "feature", "num_feature"),
    ] {
        if found != defined.len() {
            return Err(mismatch(format!(
                "the model {} has {} (learner_model_param.{param}) where mapping `{}` has {} \
                 ({}): trees of another mapping, or an edited file?",
                trees_path.display(),
                counted(found, what),
                mapping.name,
                defined.len(),
                defined.join(", ")
            )));
        }
    }
    if meta.scaling.ranges.len() != meta.outputs.len() {
        return Err(mismatch(format!(
            "{} holds {} for its {}",
            meta_path.display(),
            counted(meta.scaling.ranges.len(), "scaling range"),
            counted(meta.outputs.len(), "output")
        )));
    }
    if !tree_features.is_empty() && tree_features != meta.features {
        return Err(mismatch(format!(
            "the trees in {} were trained on features [{}], {} lists [{}]: {} (trees of \
             another mapping?)",
            trees_path.display(),
            tree_features.join(", "),
            meta_path.display(),
            meta.features.join(", "),
            name_differences(&meta.features, &tree_features)
        )));
    }
    if domain.axes.len() != meta.features.len()
        || !domain
            .points
            .len()
            .is_multiple_of(meta.features.len().max(1))
    {
        return Err(mismatch(format!(
            "{} has {} feature axes and {} coordinates, {} lists {} features",
            paths.domain.display(),
            domain.axes.len(),
            domain.points.len(),
            meta_path.display(),
            meta.features.len()
        )));
    }
    let trees = load_trees(trees_path, &trees_json)?;
    check(&meta, n_trees(&trees), &domain).map_err(|detail| SurrogateError::InconsistentModel {
        model: dir.join(name).display().to_string(),
        detail,
    })?;
    Ok((meta, trees, domain))
}
