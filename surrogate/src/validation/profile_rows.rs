//! The rows `validate` and the report print from validations on unseen profiles: one
//! record per mapping, output and profile, the theta mapping beside the dv mapping profile
//! by profile, and each model's gain importance as shares.
use serde::Serialize;

use crate::data::mapping::Mapping;
use crate::validation::unseen_profiles::Validation;

/// One relative L2 error (eq 6.6, a fraction) of one output of a mapping on one profile
/// (or all of them, or the rows in or out of the training domain), with the part of it
/// beyond the targets' own noise, and the coverage and mean width of the intervals.
#[derive(Serialize)]
pub struct Record<'a> {
    pub mapping: &'a str,
    pub output: &'a str,
    pub profile: &'a str,
    pub rel_l2: f64,
    /// `None` (JSON null) without standard errors in the table.
    pub beyond_noise: Option<f64>,
    /// Fraction of the rows inside their interval, and the intervals' mean width (output
    /// units); `None` for a model without intervals.
    pub coverage: Option<f64>,
    pub interval_width: Option<f64>,
}

/// The records of `validation` of `mapping`: output by output, each profile then the
/// training-domain classes.
pub fn records<'a>(mapping: &'a Mapping, validation: &'a Validation) -> Vec<Record<'a>> {
    let mut records = Vec::new();
    for (j, output) in mapping.outputs.iter().enumerate() {
        for error in validation.errors.iter().chain(&validation.domain_errors) {
            records.push(Record {
                mapping: mapping.name,
                output,
                profile: &error.profile,
                rel_l2: error.per_output[j],
                beyond_noise: error.beyond_noise().map(|b| b[j]),
                coverage: error.coverage.as_ref().map(|c| c[j]),
                interval_width: error.mean_width.as_ref().map(|w| w[j]),
            });
        }
    }
    records
}

/// Which of the two mappings has the lower error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lower {
    Theta,
    Dv,
    Tie,
}

/// The relative L2 errors (eq 6.6, fractions) of the theta and the dv mapping on one
/// output and profile.
pub struct ThetaVsDv<'a> {
    pub profile: &'a str,
    pub output: &'a str,
    pub theta: f64,
    pub dv: f64,
    /// The profile's targets' own noise in the same measure (the two models share the
    /// training ranges); `None` without standard errors.
    pub noise: Option<f64>,
}

impl ThetaVsDv<'_> {
    pub fn lower(&self) -> Lower {
        if self.theta < self.dv {
            Lower::Theta
        } else if self.dv < self.theta {
            Lower::Dv
        } else {
            Lower::Tie
        }
    }
}

/// Each profile's errors of the theta mapping (`theta`, outputs `outputs`) beside those of
/// the dv mapping (`dv`, the same outputs), profile by profile then output by output; a
/// profile the dv validation lacks is left out.
pub fn theta_vs_dv<'a>(
    theta: &'a Validation,
    dv: &'a Validation,
    outputs: &'a [&'a str],
) -> Vec<ThetaVsDv<'a>> {
    let mut rows = Vec::new();
    for t in &theta.errors {
        let Some(d) = dv.errors.iter().find(|d| d.profile == t.profile) else {
            continue;
        };
        for (j, output) in outputs.iter().enumerate() {
            rows.push(ThetaVsDv {
                profile: &t.profile,
                output,
                theta: t.per_output[j],
                dv: d.per_output[j],
                noise: t.target_noise.as_ref().map(|n| n[j]),
            });
        }
    }
    rows
}

/// Each feature's share of a model's total gain, `gain / sum of gains` (0 when the sum is
/// not positive), from `gains` as (feature, gain) in the model's feature order.
pub fn gain_shares(gains: &[(String, f64)]) -> Vec<(&str, f64)> {
    let total: f64 = gains.iter().map(|(_, g)| g).sum();
    gains
        .iter()
        .map(|(name, g)| (name.as_str(), if total > 0.0 { g / total } else { 0.0 }))
        .collect()
}
