//! The parts of XGBoost's JSON model format (XGBoost's `doc/model.schema`) this crate reads.
//! XGBoost writes the counts in `learner_model_param` as JSON strings; fields not listed
//! here are skipped.

use serde::Deserialize;

use crate::error::{Result, SurrogateError};

/// A model read only for its shape: the trees are skipped unparsed.
#[derive(Deserialize)]
pub(crate) struct ShapeJson {
    pub learner: LearnerShapeJson,
}

#[derive(Deserialize)]
pub(crate) struct LearnerShapeJson {
    pub learner_model_param: LearnerModelParamJson,
    /// The feature names the model was trained with (empty if it was given none).
    #[serde(default)]
    pub feature_names: Vec<String>,
}

/// A model with its trees.
#[derive(Deserialize)]
pub(crate) struct ModelJson {
    pub learner: LearnerJson,
}

#[derive(Deserialize)]
pub(crate) struct LearnerJson {
    pub learner_model_param: LearnerModelParamJson,
    /// The feature names the model was trained with (empty if it was given none).
    #[serde(default)]
    pub feature_names: Vec<String>,
    pub gradient_booster: GradientBoosterJson,
    pub objective: ObjectiveJson,
}

/// Counts and the global bias, as XGBoost writes them: strings such as `"3"`, and
/// `base_score` as `"5E-1"` or, one per output, `"[5E-1,5E-1]"`.
#[derive(Deserialize)]
pub(crate) struct LearnerModelParamJson {
    pub num_feature: String,
    pub num_target: String,
    pub base_score: String,
}

impl LearnerModelParamJson {
    /// The numbers of features and outputs; `source` names the model in errors.
    pub fn counts(&self, source: &str) -> Result<(usize, usize)> {
        let count = |name: &str, text: &str| {
            text.parse::<usize>().map_err(|_| {
                SurrogateError::ModelFormat(format!(
                    "{source}: learner_model_param.{name} = `{text}`"
                ))
            })
        };
        // A single-output model may say 0 or 1.
        Ok((
            count("num_feature", &self.num_feature)?,
            count("num_target", &self.num_target)?.max(1),
        ))
    }
}

#[derive(Deserialize)]
pub(crate) struct ObjectiveJson {
    pub name: String,
}

#[derive(Deserialize)]
pub(crate) struct GradientBoosterJson {
    pub model: TreesJson,
}

#[derive(Deserialize)]
pub(crate) struct TreesJson {
    pub trees: Vec<TreeJson>,
    /// The output each tree adds to.
    pub tree_info: Vec<usize>,
}

/// Node arrays of one tree, indexed by node id; a node whose left child is -1 is a leaf, and
/// a leaf's `split_conditions` entry is its value.
#[derive(Deserialize)]
pub(crate) struct TreeJson {
    pub left_children: Vec<i64>,
    pub right_children: Vec<i64>,
    pub split_indices: Vec<usize>,
    pub split_conditions: Vec<f32>,
    pub loss_changes: Vec<f64>,
    /// 0 for a numerical split, 1 for a categorical one.
    #[serde(default)]
    pub split_type: Vec<u8>,
    pub tree_param: TreeParamJson,
}

#[derive(Deserialize)]
pub(crate) struct TreeParamJson {
    /// Outputs per leaf: 0 or 1 for scalar leaves, more for `multi_output_tree`.
    pub size_leaf_vector: String,
}
