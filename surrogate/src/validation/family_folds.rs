//! Folds that hold out whole profile families, and the choice between them and folds that
//! hold out single simulations.
//!
//! A profile family is every row of one forcing expression ([`crate::data::dataset::PROFILE_COLUMN`]:
//! shape and amplitude) at every phi, L_y and seed. Scenes of one family share their local
//! states closely, so leaving one simulation out measures interpolation between near
//! neighbours; leaving a whole family out measures what a user sees on a new forcing. The
//! folds come from [`leave_one_group_out`] with the family as the group.

use std::collections::BTreeSet;

use serde::{Deserialize, Serialize};

use crate::data::dataset::{GROUP_COLUMN, PROFILE_COLUMN};
use crate::data::samples::Samples;
use crate::error::{Result, SurrogateError};
use crate::validation::cross_validation::{leave_one_group_out, Fold};

/// Fewest profile families for which tuning leaves one family out: with two, each fold would
/// train on a single forcing.
pub const MIN_TUNING_FAMILIES: usize = 3;

/// What one fold holds out.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LeftOut {
    /// One simulation (rows of one [`GROUP_COLUMN`] value, all its replicas).
    #[default]
    Simulation,
    /// One profile family (rows of one [`PROFILE_COLUMN`] value).
    Family,
}

impl LeftOut {
    /// What a fold holds out, in the plural: `simulations` or `profile families`.
    pub fn plural(self) -> &'static str {
        match self {
            LeftOut::Simulation => "simulations",
            LeftOut::Family => "profile families",
        }
    }

    /// The column whose value tells the held-out units apart.
    pub fn column(self) -> &'static str {
        match self {
            LeftOut::Simulation => GROUP_COLUMN,
            LeftOut::Family => PROFILE_COLUMN,
        }
    }
}

/// One fold of leave-one-family-out cross-validation: the family its test rows hold.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FamilyFold {
    pub family: String,
    pub fold: Fold,
}

/// The distinct profile families of `samples`, in sorted order; an error when the source has
/// no [`PROFILE_COLUMN`].
pub fn family_names(samples: &Samples) -> Result<Vec<String>> {
    let families = samples.families.as_ref().ok_or_else(|| {
        SurrogateError::InvalidArgument(format!(
            "{} has no `{PROFILE_COLUMN}` column, so its rows have no profile family",
            samples.source_name
        ))
    })?;
    Ok(families
        .iter()
        .collect::<BTreeSet<_>>()
        .into_iter()
        .cloned()
        .collect())
}

/// One fold per profile family, each testing on that family alone, in the order of
/// [`family_names`]. Needs at least two families.
pub fn leave_one_family_out(samples: &Samples) -> Result<Vec<FamilyFold>> {
    let names = family_names(samples)?;
    let families = samples.families.as_deref().unwrap_or_default();
    if names.len() < 2 {
        return Err(SurrogateError::InvalidArgument(format!(
            "leaving one profile family out needs rows of at least 2 families (distinct \
             `{PROFILE_COLUMN}` values); {} has {}",
            samples.source_name,
            names.len()
        )));
    }
    let mut folds: Vec<FamilyFold> = leave_one_group_out(families)?
        .into_iter()
        .map(|fold| FamilyFold {
            family: families[fold.test[0]].clone(),
            fold,
        })
        .collect();
    folds.sort_by(|a, b| a.family.cmp(&b.family));
    Ok(folds)
}

/// The folds tuning cross-validates on: one per profile family when `samples` hold at least
/// [`MIN_TUNING_FAMILIES`] of them, else one per simulation.
pub fn tuning_folds(samples: &Samples) -> Result<(LeftOut, Vec<Fold>)> {
    // No profile column: no families, and the simulations are all there is to leave out.
    let families = family_names(samples).map_or(0, |names| names.len());
    if families >= MIN_TUNING_FAMILIES {
        let folds = leave_one_family_out(samples)?;
        return Ok((LeftOut::Family, folds.into_iter().map(|f| f.fold).collect()));
    }
    let folds = leave_one_group_out(&samples.groups).map_err(|_| {
        SurrogateError::InvalidArgument(format!(
            "{} holds fewer than {MIN_TUNING_FAMILIES} profile families, so tuning leaves one \
             simulation out at a time and needs rows of at least 2 simulations (distinct \
             `{GROUP_COLUMN}` values)",
            samples.source_name
        ))
    })?;
    Ok((LeftOut::Simulation, folds))
}
