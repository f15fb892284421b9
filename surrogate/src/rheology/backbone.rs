//! A model's physics backbone: the [`LocalRheology`] fitted on its training rows, and the
//! scaling of the residual that the trees learn in its place (`y = backbone(J) + residual`).

use ndarray::{Array2, ArrayView2, Axis};
use schema::columns as col;
use serde::{Deserialize, Serialize};

use crate::data::physical_range::clip_to_physical_range;
use crate::data::samples::Samples;
use crate::data::scaling::MinMaxScaling;
use crate::error::{Result, SurrogateError};
use crate::rheology::local_rheology::LocalRheology;

/// The feature the backbone reads: the local viscous number.
const J_COLUMN: &str = col::J;

/// The backbone of a model and the min-max scaling of its residuals on the training rows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Backbone {
    pub law: LocalRheology,
    /// Ranges of `output - backbone` on the training rows; the trees predict these scaled.
    pub residual_scaling: MinMaxScaling,
}

impl Backbone {
    /// Fits the law on `samples` (which must hold J, phi_loc and mu among their features and
    /// outputs) and returns it with the scaled residuals the trees are to learn.
    pub fn fit(samples: &Samples) -> Result<(Self, Array2<f64>)> {
        let j = column(samples, J_COLUMN)?;
        let law = LocalRheology::fit(
            &j,
            &column(samples, col::PHI_LOC)?,
            &column(samples, col::MU)?,
        )?;
        let mut residual = samples.outputs.clone();
        add_law(&law, &samples.output_names, &j, &mut residual, -1.0)?;
        let residual_scaling = MinMaxScaling::fit(residual.view())?;
        let scaled = residual_scaling.scale(residual.view())?;
        Ok((
            Backbone {
                law,
                residual_scaling,
            },
            scaled,
        ))
    }

    /// Outputs in original units: the law at the rows' J plus the trees' scaled residuals
    /// `scaled` unscaled. `features` are the rows, columns named by `feature_names`.
    pub fn outputs(
        &self,
        feature_names: &[String],
        output_names: &[String],
        features: ArrayView2<f64>,
        scaled: ArrayView2<f64>,
    ) -> Result<Array2<f64>> {
        Ok(self.residual_scaling.unscale(scaled)?
            + self.law_outputs(feature_names, output_names, features)?)
    }

    /// The backbone alone as a model: [`Backbone::law_outputs`] clipped into each output's
    /// physical range ([`crate::data::physical_range`]).
    pub fn law_prediction(
        &self,
        feature_names: &[String],
        output_names: &[String],
        features: ArrayView2<f64>,
    ) -> Result<Array2<f64>> {
        let mut values = self.law_outputs(feature_names, output_names, features)?;
        clip_to_physical_range(output_names, &mut values);
        Ok(values)
    }

    /// The law's value of each output (columns `output_names`) at the J of each row of
    /// `features` (columns `feature_names`).
    pub fn law_outputs(
        &self,
        feature_names: &[String],
        output_names: &[String],
        features: ArrayView2<f64>,
    ) -> Result<Array2<f64>> {
        let j: Vec<f64> = features.column(feature_index(feature_names)?).to_vec();
        let mut values = Array2::zeros((features.nrows(), output_names.len()));
        add_law(&self.law, output_names, &j, &mut values, 1.0)?;
        Ok(values)
    }
}

/// Adds `sign` times the law's value of each output at the rows' `j` to `values`.
fn add_law(
    law: &LocalRheology,
    output_names: &[String],
    j: &[f64],
    values: &mut Array2<f64>,
    sign: f64,
) -> Result<()> {
    for (name, mut column) in output_names.iter().zip(values.axis_iter_mut(Axis(1))) {
        for (v, &j) in column.iter_mut().zip(j) {
            *v += sign * law.output(name, j)?;
        }
    }
    Ok(())
}

fn feature_index(feature_names: &[String]) -> Result<usize> {
    feature_names
        .iter()
        .position(|f| f == J_COLUMN)
        .ok_or_else(|| {
            SurrogateError::InvalidArgument(format!(
                "the local-rheology backbone needs feature {J_COLUMN}, the model has [{}]",
                feature_names.join(", ")
            ))
        })
}

/// Column `name` of `samples`, among the features or the outputs.
fn column(samples: &Samples, name: &str) -> Result<Vec<f64>> {
    if let Some(i) = samples.feature_names.iter().position(|f| f == name) {
        return Ok(samples.features.column(i).to_vec());
    }
    if let Some(i) = samples.output_names.iter().position(|f| f == name) {
        return Ok(samples.outputs.column(i).to_vec());
    }
    Err(SurrogateError::InvalidArgument(format!(
        "the local-rheology backbone is fitted on J, phi_loc and mu; {} has no `{name}` among \
         [{}] -> [{}]",
        samples.source_name,
        samples.feature_names.join(", "),
        samples.output_names.join(", ")
    )))
}
