//! A trained mapping beside its alternatives on the same validation rows: the mapping
//! retrained with its own hyper-parameters, with the backbone switched, with XGBoost's
//! defaults, and the linear and backbone-alone baselines, each with its error per output
//! (eq 6.6) and its training time.

use std::time::Instant;

use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::models::booster::HyperParameters;
use crate::models::model::TrainedModel;
use crate::validation::baselines::{evaluate_baseline, Baseline};

/// What a row of the comparison trained.
#[derive(Debug, Clone, PartialEq)]
pub enum Contender {
    /// XGBoost with these hyper-parameters; `setting` says how they relate to the model's.
    Xgboost {
        setting: &'static str,
        params: HyperParameters,
    },
    /// A baseline regression.
    Baseline(Baseline),
}

/// One row of the comparison.
#[derive(Debug, Clone)]
pub struct ComparisonRow {
    pub contender: Contender,
    /// Relative L2 error of each output, or why the contender does not apply to these rows
    /// (e.g. a backbone that cannot be fitted on them).
    pub errors: std::result::Result<Vec<f64>, String>,
    /// Training time (s); NaN where nothing was trained.
    pub training_seconds: f64,
}

/// Trains every contender of a model trained with `trained` on `training` and measures it on
/// `validation`: the same setting, the same with the backbone switched, XGBoost's defaults
/// (when they differ from `trained`), then the linear, log-linear and backbone-alone
/// baselines.
pub fn compare_contenders(
    mapping: &Mapping,
    trained: &HyperParameters,
    training: &Samples,
    validation: &Samples,
) -> Vec<ComparisonRow> {
    let mut settings = vec![("as trained", trained.clone())];
    let flipped = HyperParameters {
        backbone: !trained.backbone,
        ..trained.clone()
    };
    settings.push(if flipped.backbone {
        ("the same on the backbone", flipped)
    } else {
        ("the same without backbone", flipped)
    });
    if *trained != HyperParameters::default() {
        settings.push(("XGBoost defaults", HyperParameters::default()));
    }
    let mut rows = Vec::new();
    for (setting, params) in settings {
        let started = Instant::now();
        let errors = TrainedModel::fit(mapping, training, &params)
            .and_then(|model| model.evaluate(validation))
            .map_err(|e| format!("not applicable: {e}"));
        rows.push(ComparisonRow {
            training_seconds: started.elapsed().as_secs_f64(),
            contender: Contender::Xgboost { setting, params },
            errors,
        });
    }
    for baseline in [
        Baseline::Linear,
        Baseline::LogLinear,
        Baseline::LocalRheology,
    ] {
        let score = evaluate_baseline(baseline, training, validation);
        rows.push(ComparisonRow {
            contender: Contender::Baseline(baseline),
            training_seconds: score
                .as_ref()
                .map_or(f64::NAN, |s| s.training_time.as_secs_f64()),
            errors: score
                .map(|s| s.per_output)
                .map_err(|e| format!("not applicable: {e}")),
        });
    }
    rows
}
