//! The names of the closures a solve can use, and the trained mapping behind each.
use crate::error::{Result, SolverError};

/// Which closure a solve uses (its discriminant indexes [`ClosureKind::ALL`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClosureKind {
    /// The trained `dv` mapping, (J, Delta_v, phi) -> (phi_loc, mu).
    Learned,
    /// mu = A J^b and phi_loc by eq 6.7, fitted on the training data.
    Local,
    /// The trained `theta` mapping, (J, Theta, phi) -> (phi_loc, mu), with Theta from its
    /// balance l^2 Theta'' = Theta - c J^beta fitted on the training data.
    Nonlocal,
    /// The trained `ext` mapping, (J, phi, d_ext) -> (phi_loc, mu), d_ext the distance to the
    /// nearest velocity extremum of the solved profile.
    Extremum,
}

impl ClosureKind {
    pub const ALL: [ClosureKind; 4] = [
        ClosureKind::Learned,
        ClosureKind::Local,
        ClosureKind::Nonlocal,
        ClosureKind::Extremum,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ClosureKind::Learned => "learned",
            ClosureKind::Local => "local",
            ClosureKind::Nonlocal => "nonlocal",
            ClosureKind::Extremum => "extremum",
        }
    }

    /// The trained mapping the closure evaluates; `None` for the local law.
    pub fn mapping(self) -> Option<&'static str> {
        match self {
            ClosureKind::Learned => Some("dv"),
            ClosureKind::Local => None,
            ClosureKind::Nonlocal => Some("theta"),
            ClosureKind::Extremum => Some("ext"),
        }
    }

    /// The closure called `name`.
    pub fn from_name(name: &str) -> Result<ClosureKind> {
        ClosureKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| {
                SolverError::InvalidArgument(format!(
                    "unknown closure `{name}` (learned, local, nonlocal or extremum)"
                ))
            })
    }
}
