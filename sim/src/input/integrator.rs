//! Which time integrator a scene uses (docs/physics.md section 5).
use serde::{Deserialize, Serialize};

/// The two schemes: the implicit step, in which drag and lubrication are integrated by
/// backward Euler and only contacts and accuracy limit the step, and the explicit
/// velocity-Verlet scheme of the thesis' LAMMPS runs, kept for checks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    #[default]
    Implicit,
    Explicit,
}

impl std::fmt::Display for Integrator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Integrator::Implicit => "implicit",
            Integrator::Explicit => "explicit",
        })
    }
}
