//! XGBoost's regression trees read from its JSON model format and evaluated here, without
//! the XGBoost library.
//!
//! Loading a model into the library costs tens of milliseconds (its JSON reader builds a
//! document of every node first), more than the 10 ms a 50-bin profile may take end to
//! end; reading just the node arrays takes about a millisecond. Prediction follows
//! XGBoost's rule for numerical splits on complete data: the input is rounded to f32, a
//! split node with feature `i` and threshold `t` sends `x` left when `x_i < t` and right
//! otherwise, a leaf's value is its `split_conditions` entry, and output `k` is `base_score_k`
//! plus the values of the leaves reached in the trees whose `tree_info` is `k`, summed in
//! f32 in tree order. With `reg:squarederror` and `reg:quantileerror` that margin is the
//! prediction. Tests check it against the library's own predictions.

use ndarray::{Array2, ArrayView2};

use crate::error::{Result, SurrogateError};
use crate::models::f32_input::prediction_input;
use crate::models::xgboost_json::{ModelJson, TreeJson};

/// The objectives whose prediction is the margin itself (an identity link), which is what
/// [`Forest::predict`] computes: the squared error's mean and the pinball loss's quantiles.
const EVALUATED_OBJECTIVES: [&str; 2] = ["reg:squarederror", "reg:quantileerror"];

/// The trees of one model.
#[derive(Debug, Clone)]
pub struct Forest {
    n_features: usize,
    /// Feature names stored in the model (empty if none were).
    feature_names: Vec<String>,
    /// The starting value of each output.
    base_score: Vec<f32>,
    trees: Vec<Tree>,
}

/// One tree; node 0 is the root.
#[derive(Debug, Clone)]
struct Tree {
    /// The output this tree adds to.
    output: usize,
    nodes: Vec<Node>,
}

#[derive(Debug, Clone, Copy)]
enum Node {
    Split {
        feature: usize,
        threshold: f32,
        left: usize,
        right: usize,
        /// Loss reduction of the split (XGBoost's `loss_changes`).
        gain: f64,
    },
    Leaf {
        value: f32,
    },
}

impl Forest {
    /// Reads the trees of an XGBoost JSON model; `source` names it in errors. Refuses
    /// objectives other than `reg:squarederror`, categorical splits, vector leaves
    /// (`multi_output_tree`), and node arrays that do not form trees (a child that is not
    /// after its parent, an index out of range).
    pub fn from_json(bytes: &[u8], source: &str) -> Result<Self> {
        let unreadable =
            |detail: String| SurrogateError::ModelFormat(format!("{source}: {detail}"));
        let format_error = |detail: String| {
            SurrogateError::ModelFormat(format!(
                "{source} is not an XGBoost model this crate reads: {detail}"
            ))
        };
        let model: ModelJson = crate::data::files::parse_json_bytes(bytes, "an XGBoost JSON model")
            .map_err(unreadable)?;
        let learner = model.learner;
        if !EVALUATED_OBJECTIVES.contains(&learner.objective.name.as_str()) {
            return Err(format_error(format!(
                "objective `{}`, but only reg:squarederror and reg:quantileerror are evaluated \
                 here",
                learner.objective.name
            )));
        }
        let shape = &learner.learner_model_param;
        let (n_features, n_outputs) = shape.counts(source)?;
        let base_score = parse_base_score(&shape.base_score, n_outputs).map_err(format_error)?;
        let forest = learner.gradient_booster.model;
        if forest.tree_info.len() != forest.trees.len() {
            return Err(format_error(format!(
                "{} trees but {} tree_info entries",
                forest.trees.len(),
                forest.tree_info.len()
            )));
        }
        let trees = forest
            .trees
            .iter()
            .zip(&forest.tree_info)
            .enumerate()
            .map(|(index, (tree, &output))| {
                if output >= n_outputs {
                    return Err(format_error(format!(
                        "tree {index} adds to output {output} of {n_outputs}"
                    )));
                }
                Tree::from_json(tree, output, n_features)
                    .map_err(|detail| format_error(format!("tree {index}: {detail}")))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Forest {
            n_features,
            feature_names: learner.feature_names,
            base_score,
            trees,
        })
    }

    /// Feature names stored in the model file, in input order (empty if none were).
    pub fn feature_names(&self) -> &[String] {
        &self.feature_names
    }

    /// Number of input features.
    pub fn n_features(&self) -> usize {
        self.n_features
    }

    /// Number of outputs.
    pub fn n_outputs(&self) -> usize {
        self.base_score.len()
    }

    /// Number of trees (of all outputs).
    pub fn n_trees(&self) -> usize {
        self.trees.len()
    }

    /// Predictions (rows x outputs) for `features` (rows x features), all finite.
    pub fn predict(&self, features: ArrayView2<f64>) -> Result<Array2<f64>> {
        let values = prediction_input(features, self.n_features, &self.feature_names)?;
        let mut predicted = Array2::zeros((features.nrows(), self.n_outputs()));
        let mut sums = self.base_score.clone();
        for (i, row) in values.chunks(self.n_features.max(1)).enumerate() {
            sums.copy_from_slice(&self.base_score);
            for tree in &self.trees {
                sums[tree.output] += tree.leaf_value(row);
            }
            for (out, &sum) in predicted.row_mut(i).iter_mut().zip(&sums) {
                *out = f64::from(sum);
            }
        }
        Ok(predicted)
    }

    /// The expected prediction of each output when feature `i` of `x` is spread uniformly
    /// over `[x_i - half_width_i, x_i + half_width_i]` (a half-width of 0 is a sharp value):
    /// each split sends the fraction of the interval below its threshold left and the rest
    /// right. Unlike [`Forest::predict`], which is piecewise constant, this is continuous in
    /// `x` wherever every half-width is positive, so a Newton solver can differentiate it.
    pub fn expected(&self, x: &[f64], half_width: &[f64]) -> Vec<f64> {
        (0..self.base_score.len())
            .map(|output| self.expected_output(x, half_width, output))
            .collect()
    }

    /// Output `output` of [`Forest::expected`] alone: the other outputs' trees are not
    /// walked (a solver that needs one output of a two-output model halves its work).
    pub fn expected_output(&self, x: &[f64], half_width: &[f64], output: usize) -> f64 {
        let mut sum = f64::from(self.base_score[output]);
        for tree in self.trees.iter().filter(|t| t.output == output) {
            sum += tree.expected(0, x, half_width);
        }
        sum
    }

    /// XGBoost's "gain" importance of each feature, in feature order: the average loss
    /// reduction of the splits on that feature over all trees (0 for a feature never split on).
    pub fn feature_importance_gain(&self) -> Vec<f64> {
        let mut total_gain = vec![0.0; self.n_features];
        let mut splits = vec![0_u32; self.n_features];
        for node in self.trees.iter().flat_map(|tree| &tree.nodes) {
            if let Node::Split { feature, gain, .. } = *node {
                total_gain[feature] += gain;
                splits[feature] += 1;
            }
        }
        total_gain
            .iter()
            .zip(&splits)
            .map(|(&g, &n)| if n > 0 { g / f64::from(n) } else { 0.0 })
            .collect()
    }
}

impl Tree {
    /// Expected leaf value below `node` for features spread as in [`Forest::expected`].
    fn expected(&self, node: usize, x: &[f64], half_width: &[f64]) -> f64 {
        match self.nodes[node] {
            Node::Leaf { value } => f64::from(value),
            Node::Split {
                feature,
                threshold,
                left,
                right,
                ..
            } => {
                let (v, h, t) = (x[feature], half_width[feature], f64::from(threshold));
                let below = if h > 0.0 {
                    ((t - (v - h)) / (2.0 * h)).clamp(0.0, 1.0)
                } else if (v as f32) < threshold {
                    1.0
                } else {
                    0.0
                };
                let mut sum = 0.0;
                if below > 0.0 {
                    sum += below * self.expected(left, x, half_width);
                }
                if below < 1.0 {
                    sum += (1.0 - below) * self.expected(right, x, half_width);
                }
                sum
            }
        }
    }

    /// Checks and converts one tree's node arrays; the error says what is wrong.
    fn from_json(
        tree: &TreeJson,
        output: usize,
        n_features: usize,
    ) -> std::result::Result<Self, String> {
        let n = tree.left_children.len();
        let lengths = [
            tree.right_children.len(),
            tree.split_indices.len(),
            tree.split_conditions.len(),
            tree.loss_changes.len(),
        ];
        if n == 0 || lengths.iter().any(|&len| len != n) {
            return Err(format!(
                "node arrays of lengths {n} and {lengths:?}: need one entry per node"
            ));
        }
        if !matches!(tree.tree_param.size_leaf_vector.as_str(), "0" | "1") {
            return Err(format!(
                "leaves of {} values (multi_output_tree); only scalar leaves are evaluated here",
                tree.tree_param.size_leaf_vector
            ));
        }
        if tree.split_type.iter().any(|&t| t != 0) {
            return Err("a categorical split; only numerical splits are evaluated here".to_owned());
        }
        // A child must come after its parent, which also rules out cycles.
        let child = |index: usize, id: i64| {
            usize::try_from(id)
                .ok()
                .filter(|&c| c > index && c < n)
                .ok_or_else(|| format!("node {index} has child {id} among {n} nodes"))
        };
        let nodes = (0..n)
            .map(|index| {
                if tree.left_children[index] == -1 {
                    return Ok(Node::Leaf {
                        value: tree.split_conditions[index],
                    });
                }
                let feature = tree.split_indices[index];
                if feature >= n_features {
                    return Err(format!(
                        "node {index} splits on feature {feature} of {n_features}"
                    ));
                }
                Ok(Node::Split {
                    feature,
                    threshold: tree.split_conditions[index],
                    left: child(index, tree.left_children[index])?,
                    right: child(index, tree.right_children[index])?,
                    gain: tree.loss_changes[index],
                })
            })
            .collect::<std::result::Result<Vec<_>, String>>()?;
        Ok(Tree { output, nodes })
    }

    /// The value of the leaf `row` reaches.
    fn leaf_value(&self, row: &[f32]) -> f32 {
        let mut index = 0;
        loop {
            match self.nodes[index] {
                Node::Leaf { value } => return value,
                Node::Split {
                    feature,
                    threshold,
                    left,
                    right,
                    ..
                } => {
                    index = if row[feature] < threshold {
                        left
                    } else {
                        right
                    }
                }
            }
        }
    }
}

/// `"5E-1"` or `"[5E-1,5E-1]"` as one value per output (a single value serves them all);
/// the error says what is wrong with it.
fn parse_base_score(text: &str, n_outputs: usize) -> std::result::Result<Vec<f32>, String> {
    let inner = text.trim().trim_start_matches('[').trim_end_matches(']');
    let values = inner
        .split(',')
        .map(|v| v.trim().parse::<f32>().ok().filter(|v| v.is_finite()))
        .collect::<Option<Vec<f32>>>()
        .ok_or_else(|| format!("base_score `{text}` is not a list of finite numbers"))?;
    match values.len() {
        1 => Ok(vec![values[0]; n_outputs]),
        len if len == n_outputs => Ok(values),
        len => Err(format!(
            "base_score `{text}` holds {len} values, but learner_model_param.num_target says \
             {n_outputs} output(s)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    /// A one-output model with a stump on feature 1 at 0.5 (leaves -1 and 2), base 0.25.
    fn stump(left_children: &str, objective: &str) -> String {
        format!(
            r#"{{"learner": {{
                "learner_model_param": {{"num_feature": "2", "num_target": "1", "base_score": "[2.5E-1]"}},
                "objective": {{"name": "{objective}"}},
                "gradient_booster": {{"model": {{"tree_info": [0], "trees": [{{
                    "left_children": {left_children}, "right_children": [2, -1, -1],
                    "split_indices": [1, 0, 0], "split_conditions": [0.5, -1.0, 2.0],
                    "loss_changes": [3.0, 0.0, 0.0], "split_type": [0, 0, 0],
                    "tree_param": {{"size_leaf_vector": "1"}}
                }}]}}}}
            }}}}"#
        )
    }

    #[test]
    fn a_stump_sends_values_below_the_threshold_left() {
        let forest =
            Forest::from_json(stump("[1, -1, -1]", "reg:squarederror").as_bytes(), "t").unwrap();
        assert_eq!((forest.n_features(), forest.n_outputs()), (2, 1));
        let predicted = forest
            .predict(array![[9.0, 0.4], [9.0, 0.5], [-9.0, 0.6]].view())
            .unwrap();
        assert_eq!(predicted, array![[-0.75], [2.25], [2.25]]);
        assert_eq!(forest.feature_importance_gain(), vec![0.0, 3.0]);
    }

    #[test]
    fn malformed_trees_and_other_objectives_are_refused() {
        for (left, objective, expected) in [
            ("[0, -1, -1]", "reg:squarederror", "node 0 has child 0"),
            (
                "[7, -1, -1]",
                "reg:squarederror",
                "node 0 has child 7 among 3 nodes",
            ),
            ("[1, -1]", "reg:squarederror", "need one entry per node"),
            (
                "[1, -1, -1]",
                "binary:logistic",
                "objective `binary:logistic`",
            ),
        ] {
            let error = Forest::from_json(stump(left, objective).as_bytes(), "m.json").unwrap_err();
            assert!(matches!(error, SurrogateError::ModelFormat(_)), "{error:?}");
            let message = error.to_string();
            assert!(
                message.contains("m.json") && message.contains(expected),
                "{message}"
            );
        }
    }

    #[test]
    fn base_score_is_read_as_one_value_or_one_per_output() {
        assert_eq!(parse_base_score("5E-1", 2), Ok(vec![0.5, 0.5]));
        assert_eq!(parse_base_score("[5E-1,2.5E-1]", 2), Ok(vec![0.5, 0.25]));
        assert_eq!(
            parse_base_score("[1,2,3]", 2).unwrap_err(),
            "base_score `[1,2,3]` holds 3 values, but learner_model_param.num_target says 2 \
             output(s)"
        );
        assert!(parse_base_score("NaN", 1)
            .unwrap_err()
            .contains("not a list of finite numbers"));
    }
}
