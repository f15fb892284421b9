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
                    "{source}: learner_model_param.{name} = `{text}` is not a count"
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

/// What XGBoost's own loader reads of a tree model, checked before the file is handed to it:
/// its loader meets a missing field or a short array with a C++ exception and stack trace.
/// Holds both tree kinds (scalar leaves and `multi_output_tree` vector leaves).
#[derive(Deserialize)]
pub(crate) struct LoaderJson {
    pub learner: LoaderLearnerJson,
}

#[derive(Deserialize)]
pub(crate) struct LoaderLearnerJson {
    /// Required, read by [`ShapeJson`].
    #[serde(rename = "learner_model_param")]
    _learner_model_param: LearnerModelParamJson,
    pub gradient_booster: LoaderBoosterJson,
    /// Required; XGBoost reads the objective's name and parameters.
    #[serde(rename = "objective")]
    _objective: ObjectiveJson,
}

#[derive(Deserialize)]
pub(crate) struct LoaderBoosterJson {
    pub name: String,
    pub model: LoaderTreesJson,
}

#[derive(Deserialize)]
pub(crate) struct LoaderTreesJson {
    pub gbtree_model_param: GbtreeParamJson,
    pub trees: Vec<LoaderTreeJson>,
    pub tree_info: Vec<i64>,
}

#[derive(Deserialize)]
pub(crate) struct GbtreeParamJson {
    pub num_trees: String,
}

/// The per-node arrays of one tree that both tree kinds hold, one entry per node.
#[derive(Deserialize)]
pub(crate) struct LoaderTreeJson {
    pub tree_param: NodeCountJson,
    pub left_children: Vec<i64>,
    pub right_children: Vec<i64>,
    pub parents: Vec<i64>,
    pub split_indices: Vec<i64>,
    pub split_conditions: Vec<f64>,
    pub default_left: Vec<serde_json::Value>,
    pub base_weights: Vec<f64>,
}

#[derive(Deserialize)]
pub(crate) struct NodeCountJson {
    pub num_nodes: String,
}

impl LoaderJson {
    /// The first thing in the model that XGBoost's loader could not read: a count that is
    /// not one, trees that are not `num_trees`, a node array of another length than the
    /// tree's `num_nodes`, a child index out of range.
    pub fn problem(&self) -> Option<String> {
        let learner = &self.learner;
        if learner.gradient_booster.name != "gbtree" {
            return Some(format!(
                "booster `{}`, but only gbtree models are read here",
                learner.gradient_booster.name
            ));
        }
        let model = &learner.gradient_booster.model;
        let declared = &model.gbtree_model_param.num_trees;
        if declared.parse::<usize>().ok() != Some(model.trees.len())
            || model.tree_info.len() != model.trees.len()
        {
            return Some(format!(
                "gbtree_model_param.num_trees = `{declared}`, but it holds {} trees and {} \
                 tree_info entries",
                model.trees.len(),
                model.tree_info.len()
            ));
        }
        model
            .trees
            .iter()
            .enumerate()
            .find_map(|(index, tree)| tree.problem().map(|p| format!("tree {index}: {p}")))
    }
}

impl LoaderTreeJson {
    fn problem(&self) -> Option<String> {
        let declared = &self.tree_param.num_nodes;
        let Ok(nodes) = declared.parse::<usize>() else {
            return Some(format!("tree_param.num_nodes = `{declared}`"));
        };
        let lengths = [
            ("left_children", self.left_children.len()),
            ("right_children", self.right_children.len()),
            ("parents", self.parents.len()),
            ("split_indices", self.split_indices.len()),
            ("split_conditions", self.split_conditions.len()),
            ("default_left", self.default_left.len()),
        ];
        if nodes == 0 {
            return Some("no nodes".to_owned());
        }
        if let Some((name, len)) = lengths.iter().find(|(_, len)| *len != nodes) {
            return Some(format!("{name} has {len} entries for {nodes} nodes"));
        }
        if self.base_weights.len() < nodes {
            return Some(format!(
                "base_weights has {} entries for {nodes} nodes",
                self.base_weights.len()
            ));
        }
        let in_range = |c: i64| c == -1 || (0..nodes as i64).contains(&c);
        self.left_children
            .iter()
            .chain(&self.right_children)
            .find(|&&c| !in_range(c))
            .map(|c| format!("a child index {c} among {nodes} nodes"))
    }
}
