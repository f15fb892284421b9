//! Hyper-parameter selection for one mapping: a grid search cross-validated on the training
//! data only, so that the validation profiles never influence the choice. The folds leave
//! one profile family out ([`crate::validation::family_folds`]) when the data hold at least
//! [`MIN_TUNING_FAMILIES`] of them, so that the choice favours settings that carry over to a
//! new forcing; otherwise (the seeds' training grid has a single profile) they leave one
//! simulation out (folds by [`crate::data::dataset::GROUP_COLUMN`]). The record keeps every
//! candidate's error next to that of XGBoost's defaults, the setting the thesis trained
//! with ("without hyperparameter optimization", section 6.2), and is saved as
//! `<mapping>.tuning.json` beside the model.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::data::files;
use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::error::Result;
use crate::models::booster::HyperParameters;
use crate::rheology::backbone::Backbone;
use crate::validation::cross_validation::{
    cross_validate, grid_search, CvScore, Fold, HyperParameterGrid,
};
use crate::validation::family_folds::{tuning_folds, LeftOut, MIN_TUNING_FAMILIES};

/// The grid `suspflow train` searches: 2 x 2 x 4 x 3 x 2 = 96 settings around XGBoost's
/// defaults (which it contains): trees on the outputs or on the residual of the physics
/// backbone ([`crate::rheology::local_rheology`]), with shallow trees, slower learning and heavier
/// leaves (`min_child_weight`, a sum of unit hessians: rows per leaf) for smoother fits of
/// about 300 noisy rows from 8 simulations. At most 300 rounds, so that training all three
/// mappings with any of them stays well under a second. At the wide grid's size (about 5000
/// rows, 12 profile families) the search of one mapping is 1152 fits, 163 s on one free
/// core (README, Commands), so the grid is kept whole there too.
pub fn standard_grid() -> HyperParameterGrid {
    HyperParameterGrid {
        base: HyperParameters::default(),
        n_estimators: vec![100, 300],
        max_depth: vec![2, 3, 4, 6],
        learning_rate: vec![0.05, 0.1, 0.3],
        min_child_weight: vec![1.0, 5.0],
        backbone: vec![false, true],
    }
}

/// The outcome of tuning one mapping.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tuning {
    /// Name of the [`Mapping`].
    pub mapping: String,
    /// Output columns, in the order of each score's `per_output`.
    pub outputs: Vec<String>,
    /// How the folds were made.
    pub cross_validation: String,
    /// What each fold leaves out (records written before families existed left out
    /// simulations).
    #[serde(default)]
    pub left_out: LeftOut,
    /// Number of folds (= simulations or profile families left out).
    pub folds: usize,
    /// Rows used (rows with an empty cell in the mapping's columns are left out).
    pub rows: usize,
    /// Rows of the training data left out for an empty cell.
    pub skipped_rows: usize,
    pub grid: HyperParameterGrid,
    /// Every candidate, in grid order.
    pub scores: Vec<CvScore>,
    /// The candidate with the lowest mean error (the first one on a tie).
    pub chosen: CvScore,
    /// XGBoost's default setting ([`HyperParameters::default`]), the thesis's untuned model.
    pub untuned: CvScore,
    /// Wall time of the whole search, in seconds.
    pub seconds: f64,
    /// Why the settings with the physics backbone were left out of the search, if they were:
    /// the backbone's laws could not be fitted on every fold's training rows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub backbone_excluded: Option<String>,
}

impl Tuning {
    /// Cross-validates every setting of `grid` (and XGBoost's defaults, if the grid lacks
    /// them) on `samples`, one fold per profile family or per simulation
    /// ([`tuning_folds`]), and picks the lowest mean error.
    pub fn run(mapping: &Mapping, samples: &Samples, grid: &HyperParameterGrid) -> Result<Self> {
        let started = Instant::now();
        let (left_out, folds) = tuning_folds(samples)?;
        let backbone_excluded = backbone_unfittable(samples, &folds)?;
        let mut searched = grid.clone();
        if backbone_excluded.is_some() {
            searched.backbone.retain(|&b| !b);
            searched.base.backbone = false;
        }
        let search = grid_search(mapping, samples, &folds, &searched)?;
        let defaults = HyperParameters::default();
        let untuned = match search.scores.iter().find(|score| score.params == defaults) {
            Some(score) => score.clone(),
            None => cross_validate(mapping, samples, &folds, &defaults)?,
        };
        Ok(Tuning {
            mapping: mapping.name.to_owned(),
            outputs: samples.output_names.clone(),
            cross_validation: describe_folds(left_out),
            left_out,
            folds: folds.len(),
            rows: samples.n_rows(),
            skipped_rows: samples.skipped_rows,
            grid: grid.clone(),
            scores: search.scores,
            chosen: search.best,
            untuned,
            seconds: started.elapsed().as_secs_f64(),
            backbone_excluded,
        })
    }

    /// Writes `<dir>/<mapping>.tuning.json`, creating `dir` if needed.
    pub fn save(&self, dir: &Path) -> Result<()> {
        files::create_dir_all(dir)?;
        files::write_json(&Self::path(dir, &self.mapping), self)
    }

    /// Reads `<dir>/<name>.tuning.json`.
    pub fn load(dir: &Path, name: &str) -> Result<Self> {
        files::read_json(&Self::path(dir, name), "a tuning record")
    }

    /// `<dir>/<name>.tuning.json`.
    pub fn path(dir: &Path, name: &str) -> PathBuf {
        dir.join(format!("{name}.tuning.json"))
    }

    /// Removes `<dir>/<name>.tuning.json` left by an earlier tuned run, when a model is
    /// trained without tuning: the record would describe a choice the new model does not
    /// use. No record is no error.
    pub fn remove_stale(dir: &Path, name: &str) -> Result<()> {
        let path = Self::path(dir, name);
        match std::fs::remove_file(&path) {
            Err(source) if source.kind() != std::io::ErrorKind::NotFound => {
                Err(crate::error::SurrogateError::Io { path, source })
            }
            _ => Ok(()),
        }
    }
}

/// The record's account of how the folds were made and scored.
fn describe_folds(left_out: LeftOut) -> String {
    let why = match left_out {
        LeftOut::Family => format!("at least {MIN_TUNING_FAMILIES} families in the data"),
        LeftOut::Simulation => format!("fewer than {MIN_TUNING_FAMILIES} profile families"),
    };
    format!(
        "leave one of the {} out (groups: `{}`; {why}), relative L2 error of each output \
         (eq 6.6) on the left-out rows, scaled with the fold's training ranges, averaged over \
         folds",
        left_out.plural(),
        left_out.column()
    )
}

/// Why the backbone cannot be fitted on the training rows of one of `folds`, if it cannot.
fn backbone_unfittable(samples: &Samples, folds: &[Fold]) -> Result<Option<String>> {
    for fold in folds {
        if let Err(e) = Backbone::fit(&samples.subset(&fold.train)?) {
            return Ok(Some(e.to_string()));
        }
    }
    Ok(None)
}
