//! Element symbols standing for the species in snapshot files: readers such as ASE and
//! MDAnalysis need a chemical element per particle, so species `k` is written as the element
//! of atomic number `k + 1` (species 0 = H, 1 = He, ...), the same as the LAMMPS dump's
//! `type = k + 1`, which ASE reads as that atomic number. The radius is written alongside.
use crate::error::SimError;

/// Symbols of atomic numbers 1 to 36.
const SYMBOLS: [&str; 36] = [
    "H", "He", "Li", "Be", "B", "C", "N", "O", "F", "Ne", "Na", "Mg", "Al", "Si", "P", "S", "Cl",
    "Ar", "K", "Ca", "Sc", "Ti", "V", "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Ga", "Ge", "As",
    "Se", "Br", "Kr",
];

/// The element symbol written for `species`; an error past the 36th species.
pub fn element_symbol(species: u16) -> Result<&'static str, SimError> {
    SYMBOLS
        .get(species as usize)
        .copied()
        .ok_or_else(|| SimError::Output {
            path: "snapshot".into(),
            message: format!(
                "species {species} has no element symbol (snapshots name at most {} species)",
                SYMBOLS.len()
            ),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn species_are_elements_by_atomic_number() {
        assert_eq!(element_symbol(0).unwrap(), "H");
        assert_eq!(element_symbol(1).unwrap(), "He");
        assert_eq!(element_symbol(35).unwrap(), "Kr");
        assert!(element_symbol(36).is_err());
    }
}
