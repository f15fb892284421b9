//! The observables of a binned profile, as an index: a lookup by [`Observable`] is total,
//! where a lookup by column name can fail.

use crate::columns::OBSERVABLES;

/// One observable of a bin, in table order (the order of [`OBSERVABLES`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Observable {
    U,
    Gdot,
    SigmaXy,
    P,
    PhiLoc,
    J,
    Mu,
    Theta,
    DeltaV,
    FX,
    Count,
}

impl Observable {
    /// Every observable, in table order.
    pub const ALL: [Observable; 11] = [
        Observable::U,
        Observable::Gdot,
        Observable::SigmaXy,
        Observable::P,
        Observable::PhiLoc,
        Observable::J,
        Observable::Mu,
        Observable::Theta,
        Observable::DeltaV,
        Observable::FX,
        Observable::Count,
    ];

    /// Position in table order (an index into [`Observable::ALL`] and [`OBSERVABLES`]).
    pub fn index(self) -> usize {
        self as usize
    }

    /// The column name (e.g. `phi_loc`).
    pub fn name(self) -> &'static str {
        OBSERVABLES[self.index()]
    }

    /// The observable whose column is called `name`, if one is.
    pub fn from_name(name: &str) -> Option<Observable> {
        OBSERVABLES
            .iter()
            .position(|&c| c == name)
            .map(|k| Observable::ALL[k])
    }
}

impl std::fmt::Display for Observable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::columns;

    #[test]
    fn the_enum_and_the_column_list_agree() {
        for (k, o) in Observable::ALL.iter().enumerate() {
            assert_eq!(o.index(), k);
            assert_eq!(Observable::from_name(o.name()), Some(*o));
        }
        assert_eq!(Observable::PhiLoc.name(), columns::PHI_LOC);
        assert_eq!(Observable::Count.name(), columns::COUNT);
        assert_eq!(Observable::from_name(columns::Y), None);
    }
}
