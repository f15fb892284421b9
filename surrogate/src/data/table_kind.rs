//! Which of the two dataset tables a [`Dataset`] is, told by its columns: the per-run table
//! (one row per bin per run, a run being one replica of a scene, with `seed`) or the ensemble
//! table (one row per bin per scene, means over the replicas, with `replicas` and `se_from`;
//! docs/physics.md section 8 and `schema::columns`). Both train and validate the
//! same way: the mappings read the same columns, and cross-validation groups rows by
//! `scene_id`, so the replicas of a scene always fall on the same side of a split.

use crate::data::dataset::{Dataset, GROUP_COLUMN};
use crate::error::{Result, SurrogateError};
use schema::columns as col;

/// The kind of a dataset table, with its counts.
#[derive(Debug, Clone, PartialEq)]
pub enum TableKind {
    /// One row per bin per run.
    Runs {
        scenes: usize,
        /// Distinct (scene, seed) pairs; equal to `scenes` without replicas or `seed` column.
        runs: usize,
    },
    /// One row per bin per scene, averaged over replicas.
    Ensemble {
        scenes: usize,
        /// Fewest and most replicas of a scene.
        replicas: (usize, usize),
        /// Scenes with one replica, whose errors are batch-means ones.
        single: usize,
    },
}

impl TableKind {
    /// The kind of `data`: an ensemble table when it has the `replicas` and `se_from` columns.
    pub fn of(data: &Dataset) -> Result<TableKind> {
        let has = |name: &str| data.column_names().iter().any(|c| c == name);
        let ids = data.text(GROUP_COLUMN)?;
        let firsts: Vec<usize> = (0..data.n_rows())
            .filter(|&r| r == 0 || ids[r] != ids[r - 1])
            .collect();
        let mut scene_ids: Vec<&str> = firsts.iter().map(|&r| ids[r].as_str()).collect();
        scene_ids.sort_unstable();
        scene_ids.dedup();
        let scenes = scene_ids.len();
        if has(col::REPLICAS) && has(col::SE_FROM) {
            let counts = data.column(col::REPLICAS)?;
            let per_scene: Vec<usize> = firsts.iter().map(|&r| counts[r] as usize).collect();
            if let Some(&bad) = counts.iter().find(|c| !(c.fract() == 0.0 && **c >= 1.0)) {
                return Err(SurrogateError::InvalidArgument(format!(
                    "{}: column `{}` holds {bad}, not a replica count",
                    data.source_name(),
                    col::REPLICAS
                )));
            }
            return Ok(TableKind::Ensemble {
                scenes,
                replicas: (
                    per_scene.iter().copied().min().unwrap_or(0),
                    per_scene.iter().copied().max().unwrap_or(0),
                ),
                single: per_scene.iter().filter(|&&n| n == 1).count(),
            });
        }
        let runs = if has(col::SEED) {
            let seeds = data.text(col::SEED)?;
            let mut pairs: Vec<(&str, &str)> = (0..data.n_rows())
                .map(|r| (ids[r].as_str(), seeds[r].as_str()))
                .collect();
            pairs.sort_unstable();
            pairs.dedup();
            pairs.len()
        } else {
            scenes
        };
        Ok(TableKind::Runs { scenes, runs })
    }

    /// One line saying what the table is.
    pub fn describe(&self) -> String {
        match self {
            TableKind::Runs { scenes, runs } if runs > scenes => format!(
                "per-run table: {runs} runs of {scenes} scenes (replicas stay together in cross-validation)"
            ),
            TableKind::Runs { scenes, .. } => format!("per-run table: {scenes} scenes"),
            TableKind::Ensemble {
                scenes,
                replicas: (fewest, most),
                single,
            } => format!(
                "ensemble table: {scenes} scenes, means over {fewest}-{most} replicas; standard \
                 errors from the scatter between replicas{}",
                if *single > 0 {
                    format!(" ({single} scenes with one replica carry their batch-means errors)")
                } else {
                    String::new()
                }
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kind(text: &str) -> Result<TableKind> {
        TableKind::of(&Dataset::from_csv_bytes(text.as_bytes(), "t")?)
    }

    #[test]
    fn tells_the_tables_apart_by_their_columns() {
        assert_eq!(
            kind("scene_id,seed,y\na,1,1\na,1,2\na,2,1\nb,1,1\n").unwrap(),
            TableKind::Runs { scenes: 2, runs: 3 }
        );
        assert_eq!(
            kind("scene_id,y\na,1\nb,1\n").unwrap(),
            TableKind::Runs { scenes: 2, runs: 2 }
        );
        assert_eq!(
            kind(
                "scene_id,replicas,se_from,y\na,3,replicas,1\na,3,replicas,2\nb,1,batch_means,1\n"
            )
            .unwrap(),
            TableKind::Ensemble {
                scenes: 2,
                replicas: (1, 3),
                single: 1
            }
        );
        let message = kind("scene_id,replicas,se_from\na,0.5,replicas\n")
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("holds 0.5, not a replica count"),
            "{message}"
        );
    }
}
