//! The input -> output mappings learnt by the surrogate (docs/physics.md section 8, thesis section 6.2).

use crate::error::{Result, SurrogateError};
use schema::columns as col;

/// Which dataset columns a model reads (features) and which it predicts (outputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mapping {
    /// Short name, used on the command line and in model file names.
    pub name: &'static str,
    /// Feature columns, in the order the model sees them.
    pub features: &'static [&'static str],
    /// Output columns, in the order the model predicts them.
    pub outputs: &'static [&'static str],
}

/// The thesis' three mappings of docs/physics.md section 8, with local inputs, and `ext`,
/// whose input `d_ext` is nonlocal.
pub const MAPPINGS: [Mapping; 4] = [
    // Motivated by the scaling law J/mu = alpha (phi_J - phi_loc)^2 (thesis eq 6.7).
    Mapping {
        name: "mu",
        features: &[col::J, col::PHI_LOC, col::PHI],
        outputs: &[col::MU],
    },
    // The suspension temperature Theta carries the non-local information (thesis eqs 6.8-6.9).
    Mapping {
        name: "theta",
        features: &[col::J, col::THETA, col::PHI],
        outputs: &[col::PHI_LOC, col::MU],
    },
    // Delta_v, measurable from average velocities alone, in place of Theta.
    Mapping {
        name: "dv",
        features: &[col::J, col::DELTA_V, col::PHI],
        outputs: &[col::PHI_LOC, col::MU],
    },
    // A nonlocal input: the distance to the nearest velocity extremum, where the stress
    // passes through zero (crate::data::extremum_distance), from the profile's velocities,
    // which the profile solver has among its unknowns.
    Mapping {
        name: "ext",
        features: &[col::J, col::PHI, col::EXTREMUM_DISTANCE],
        outputs: &[col::PHI_LOC, col::MU],
    },
];

impl Mapping {
    /// Every column the mapping reads: its features, then its outputs.
    pub fn columns(&self) -> Vec<&'static str> {
        self.features.iter().chain(self.outputs).copied().collect()
    }

    /// The mappings called `names`, in that order, or all of [`MAPPINGS`] when `names` is
    /// empty; an unknown name is an error listing the known ones.
    pub fn select<S: AsRef<str>>(names: &[S]) -> Result<Vec<&'static Mapping>> {
        if names.is_empty() {
            return Ok(MAPPINGS.iter().collect());
        }
        names
            .iter()
            .map(|name| Self::by_name(name.as_ref()))
            .collect()
    }

    /// The mapping called `name`, or an error listing the known names.
    pub fn by_name(name: &str) -> Result<&'static Mapping> {
        MAPPINGS
            .iter()
            .find(|m| m.name == name)
            .ok_or_else(|| SurrogateError::UnknownMapping {
                name: name.to_owned(),
                known: MAPPINGS.iter().map(|m| m.name.to_owned()).collect(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_each_mapping_by_its_name() {
        for mapping in &MAPPINGS {
            assert_eq!(Mapping::by_name(mapping.name).unwrap(), mapping);
        }
        assert_eq!(
            Mapping::by_name("theta").unwrap().outputs,
            &["phi_loc", "mu"]
        );
    }

    #[test]
    fn selects_all_by_default_or_the_named_ones() {
        assert_eq!(Mapping::select::<&str>(&[]).unwrap().len(), MAPPINGS.len());
        let picked = Mapping::select(&["dv", "mu"]).unwrap();
        assert_eq!(
            picked.iter().map(|m| m.name).collect::<Vec<_>>(),
            ["dv", "mu"]
        );
        assert!(matches!(
            Mapping::select(&["mu", "nope"]),
            Err(SurrogateError::UnknownMapping { .. })
        ));
    }
}
