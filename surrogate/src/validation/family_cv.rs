//! Leave-one-family-out comparison of three ways to predict a mapping's outputs: XGBoost
//! alone, the physics backbone alone ([`crate::rheology::local_rheology`]: `mu = A J^b`, `phi_loc`
//! from eq 6.7) and XGBoost on the backbone's residual.
//!
//! Each fold holds out one profile family ([`crate::validation::family_folds`]); the three variants are
//! fitted on the fold's training rows with the same hyper-parameters (the trees' settings;
//! only whether they learn the outputs or the residual differs), and so is the training
//! domain ([`TrainingDomain`]), which splits the held-out rows into those inside and those
//! outside. The error is the relative L2 error of eq 6.6 with the outputs min-max scaled on
//! the fold's training rows, as in tuning and validation, on all held-out rows, the
//! in-domain ones and the out-of-domain ones; beside it the mean absolute error in the
//! outputs' own units, since eq 6.6 on mu is dominated by the near-zero mu of plugs.

use ndarray::{Array2, Axis};
use rayon::prelude::*;
use serde::Serialize;

use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::error::{Result, SurrogateError};
use crate::models::booster::HyperParameters;
use crate::models::metrics::relative_l2_error;
use crate::models::model::TrainedModel;
use crate::rheology::backbone::Backbone;
use crate::validation::family_folds::{leave_one_family_out, FamilyFold};
use crate::validation::target_noise::{beyond_noise, target_noise};

/// One way of predicting the outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Variant {
    /// Trees on the min-max scaled outputs (the thesis' model).
    Trees,
    /// The fitted local rheology alone; reads J only.
    Backbone,
    /// The local rheology plus trees on its scaled residual.
    BackboneTrees,
}

impl Variant {
    /// Every variant, in report order.
    pub const ALL: [Variant; 3] = [Variant::Trees, Variant::Backbone, Variant::BackboneTrees];

    /// How reports name the variant.
    pub fn label(self) -> &'static str {
        match self {
            Variant::Trees => "XGBoost alone",
            Variant::Backbone => "backbone alone",
            Variant::BackboneTrees => "backbone + XGBoost",
        }
    }
}

/// Errors on one class of held-out rows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RowErrors {
    /// Rows in the class.
    pub rows: usize,
    /// Relative L2 error of each output (eq 6.6), as a fraction; `None` without rows or when
    /// the variant could not be fitted.
    pub per_output: Option<Vec<f64>>,
    /// Mean absolute error `<|predicted - truth|>` of each output, in the output's own units
    /// (mu and phi_loc: dimensionless); `None` as `per_output`.
    pub mean_absolute: Option<Vec<f64>>,
    /// `per_output` beyond the held-out targets' own noise ([`beyond_noise`]), on the class of
    /// all held-out rows, where the noise is measured; `None` on the others, without
    /// standard errors, or as `per_output`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beyond_noise: Option<Vec<f64>>,
}

/// One variant's errors on one fold.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VariantErrors {
    pub variant: Variant,
    pub all: RowErrors,
    pub in_domain: RowErrors,
    pub out_of_domain: RowErrors,
    /// Why the variant has no errors on this fold (the backbone's laws did not fit the
    /// fold's training rows).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_applicable: Option<String>,
}

/// The errors of every variant on the fold that holds out `family`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FoldErrors {
    /// The profile family held out.
    pub family: String,
    /// Rows trained on.
    pub train_rows: usize,
    /// One entry per variant, in [`Variant::ALL`] order.
    pub variants: Vec<VariantErrors>,
    /// The held-out targets' own noise per output on all held-out rows
    /// ([`crate::validation::target_noise`], the fold's scaling); `None` without standard
    /// errors.
    pub target_noise: Option<Vec<f64>>,
}

/// Mean over the held-out families of one class's errors.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeanErrors {
    /// Families that had rows of the class (and a fitted variant).
    pub families: usize,
    /// Mean error of each output over those families; `None` when there are none.
    pub per_output: Option<Vec<f64>>,
    /// Mean over the same families of each output's mean absolute error (output units).
    pub mean_absolute: Option<Vec<f64>>,
    /// Mean over the same families of each output's error beyond noise, where known.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beyond_noise: Option<Vec<f64>>,
}

/// One variant's errors averaged over the families.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VariantSummary {
    pub variant: Variant,
    pub all: MeanErrors,
    pub in_domain: MeanErrors,
    pub out_of_domain: MeanErrors,
}

/// Leave-one-family-out errors of the three variants for one mapping.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FamilyCv {
    pub mapping: String,
    pub outputs: Vec<String>,
    /// The trees' settings, for both variants with trees (`backbone` is set per variant).
    pub hyper_parameters: HyperParameters,
    /// Rows used (rows with an empty cell in the mapping's columns are left out).
    pub rows: usize,
    /// Rows of the source left out for an empty cell.
    pub skipped_rows: usize,
    /// One entry per family, in sorted order of the families.
    pub folds: Vec<FoldErrors>,
    /// One entry per variant, in [`Variant::ALL`] order.
    pub summary: Vec<VariantSummary>,
    /// Mean over the folds of [`FoldErrors::target_noise`].
    pub target_noise: Option<Vec<f64>>,
}

impl FamilyCv {
    /// Runs the comparison on `samples` (which need at least two profile families), with the
    /// targets' standard errors `standard_errors` (rows x outputs, for their own noise) where
    /// known; the folds run in parallel on rayon's pool, and `done` is called as each one
    /// finishes.
    pub fn run(
        mapping: &Mapping,
        samples: &Samples,
        standard_errors: Option<&Array2<f64>>,
        params: &HyperParameters,
        done: &(dyn Fn(&FoldErrors) + Sync),
    ) -> Result<Self> {
        let folds = leave_one_family_out(samples)?
            .par_iter()
            .map(|fold| {
                let errors =
                    fold_errors(mapping, samples, standard_errors, fold, params).map_err(|e| {
                        SurrogateError::InvalidArgument(format!(
                            "holding out profile family `{}`: {e}",
                            fold.family
                        ))
                    })?;
                done(&errors);
                Ok(errors)
            })
            .collect::<Result<Vec<_>>>()?;
        let summary = Variant::ALL
            .iter()
            .enumerate()
            .map(|(k, &variant)| {
                let mean = |class: fn(&VariantErrors) -> &RowErrors| {
                    mean_errors(folds.iter().map(|f| class(&f.variants[k])))
                };
                VariantSummary {
                    variant,
                    all: mean(|v| &v.all),
                    in_domain: mean(|v| &v.in_domain),
                    out_of_domain: mean(|v| &v.out_of_domain),
                }
            })
            .collect();
        let target_noise = folds
            .iter()
            .map(|f| f.target_noise.as_ref())
            .collect::<Option<Vec<_>>>()
            .and_then(|n| column_means(&n));
        Ok(FamilyCv {
            mapping: mapping.name.to_owned(),
            outputs: samples.output_names.clone(),
            hyper_parameters: params.clone(),
            rows: samples.n_rows(),
            skipped_rows: samples.skipped_rows,
            folds,
            summary,
            target_noise,
        })
    }
}

/// Fits the three variants and the training domain on `fold`'s training rows and measures
/// them on its test rows.
fn fold_errors(
    mapping: &Mapping,
    samples: &Samples,
    standard_errors: Option<&Array2<f64>>,
    fold: &FamilyFold,
    params: &HyperParameters,
) -> Result<FoldErrors> {
    let train = samples.subset(&fold.fold.train)?;
    let test = samples.subset(&fold.fold.test)?;
    let with_backbone = |backbone| HyperParameters {
        backbone,
        ..params.clone()
    };
    let trees = TrainedModel::fit(mapping, &train, &with_backbone(false))?;
    let inside = trees.domain().inside(test.features.view())?;
    let classes: [Vec<usize>; 3] = [
        (0..test.n_rows()).collect(),
        (0..test.n_rows()).filter(|&i| inside[i]).collect(),
        (0..test.n_rows()).filter(|&i| !inside[i]).collect(),
    ];
    let scaling = &trees.meta().scaling;
    let truth = scaling.scale(test.outputs.view())?;
    let target_noise = standard_errors
        .map(|se| {
            let se = se.select(Axis(0), &fold.fold.test);
            target_noise(scaling, test.outputs.view(), se.view())
        })
        .transpose()?;
    // The backbone alone, or why its laws do not fit these rows.
    let law = Backbone::fit(&train).map(|(backbone, _)| backbone);
    let mut variants = Vec::with_capacity(Variant::ALL.len());
    for variant in Variant::ALL {
        let predicted = match (variant, &law) {
            (Variant::Trees, _) => Ok(trees.predict_features(test.features.view())?),
            (_, Err(why)) => Err(why.to_string()),
            (Variant::Backbone, Ok(law)) => Ok(law.law_prediction(
                &test.feature_names,
                &test.output_names,
                test.features.view(),
            )?),
            (Variant::BackboneTrees, Ok(_)) => {
                Ok(TrainedModel::fit(mapping, &train, &with_backbone(true))?
                    .predict_features(test.features.view())?)
            }
        };
        let scaled = match &predicted {
            Ok(values) => Some((scaling.scale(values.view())?, values)),
            Err(_) => None,
        };
        let [all, in_domain, out_of_domain] = classes.each_ref().map(|rows| {
            row_errors(
                (&truth, &test.outputs),
                scaled.as_ref().map(|(s, v)| (s, *v)),
                rows,
            )
        });
        let mut all = all?;
        all.beyond_noise = all
            .per_output
            .as_ref()
            .zip(target_noise.as_ref())
            .map(|(e, n)| e.iter().zip(n).map(|(&e, &n)| beyond_noise(e, n)).collect());
        variants.push(VariantErrors {
            variant,
            all,
            in_domain: in_domain?,
            out_of_domain: out_of_domain?,
            not_applicable: predicted.err(),
        });
    }
    Ok(FoldErrors {
        family: fold.family.clone(),
        train_rows: train.n_rows(),
        variants,
        target_noise,
    })
}

/// The errors of `predicted` on `rows`: eq 6.6 on the scaled outputs and the mean absolute
/// error on the unscaled ones. `truth` and `predicted` are (scaled, unscaled) pairs;
/// `predicted` is `None` for a variant without predictions.
fn row_errors(
    truth: (&Array2<f64>, &Array2<f64>),
    predicted: Option<(&Array2<f64>, &Array2<f64>)>,
    rows: &[usize],
) -> Result<RowErrors> {
    let (per_output, mean_absolute) = match predicted {
        Some((scaled, unscaled)) if !rows.is_empty() => {
            let pick = |a: &Array2<f64>| a.select(Axis(0), rows);
            let relative = relative_l2_error(pick(truth.0).view(), pick(scaled).view())?;
            let absolute = (pick(unscaled) - pick(truth.1))
                .mapv(f64::abs)
                .mean_axis(Axis(0))
                .map(|m| m.to_vec());
            (Some(relative), absolute)
        }
        _ => (None, None),
    };
    Ok(RowErrors {
        rows: rows.len(),
        per_output,
        mean_absolute,
        beyond_noise: None,
    })
}

/// The mean over the folds that have errors of each output, relative and absolute.
fn mean_errors<'a>(errors: impl Iterator<Item = &'a RowErrors> + Clone) -> MeanErrors {
    let mean = |pick: fn(&RowErrors) -> Option<&Vec<f64>>| {
        let present: Vec<&Vec<f64>> = errors.clone().filter_map(pick).collect();
        (present.len(), column_means(&present))
    };
    let (families, per_output) = mean(|e| e.per_output.as_ref());
    let (_, mean_absolute) = mean(|e| e.mean_absolute.as_ref());
    let (with_noise, beyond_noise) = mean(|e| e.beyond_noise.as_ref());
    MeanErrors {
        families,
        per_output,
        mean_absolute,
        beyond_noise: beyond_noise.filter(|_| with_noise == families),
    }
}

/// The mean of each entry over `rows` (all of one length); `None` without rows.
fn column_means(rows: &[&Vec<f64>]) -> Option<Vec<f64>> {
    rows.first().map(|first| {
        (0..first.len())
            .map(|j| rows.iter().map(|e| e[j]).sum::<f64>() / rows.len() as f64)
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn absolute_error_is_in_output_units_and_relative_error_on_scaled_ones() {
        // Two outputs on three rows; the scaled pair is the unscaled one divided by 10, so
        // the relative error is unchanged by the scaling and the absolute one is not.
        let truth = array![[0.5, 0.1], [0.6, 0.2], [0.7, 0.3]];
        let predicted = array![[0.5, 0.2], [0.8, 0.2], [0.7, 0.0]];
        let (truth_s, predicted_s) = (&truth / 10.0, &predicted / 10.0);
        let e = row_errors(
            (&truth_s, &truth),
            Some((&predicted_s, &predicted)),
            &[0, 1],
        )
        .unwrap();
        let absolute = e.mean_absolute.unwrap();
        assert!((absolute[0] - 0.1).abs() < 1e-12, "{absolute:?}");
        assert!((absolute[1] - 0.05).abs() < 1e-12, "{absolute:?}");
        // eq 6.6 on rows 0 and 1 of output 1: ||(0.01, 0)|| / ||(0.01, 0.02)||.
        let relative = e.per_output.unwrap();
        assert!(
            (relative[1] - (1.0f64 / 5.0).sqrt()).abs() < 1e-9,
            "{relative:?}"
        );
        let none = row_errors((&truth_s, &truth), None, &[0]).unwrap();
        assert_eq!((none.rows, none.mean_absolute), (1, None));
    }
}
