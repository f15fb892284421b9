//! Closures of the momentum balance: what `(phi_loc, mu)` a local state gives.

use surrogate::{LocalRheology, Mapping, Predictor};

use crate::error::{Result, SolverError};

/// Relative half-width of the box over which a learned closure is averaged, for J and
/// Delta_v.
pub const SMOOTHING: f64 = 0.1;

/// What a closure gives at one local state.
pub trait Closure {
    /// `(phi_loc, mu)` at local viscous number `j`, velocity-lag descriptor `delta_v`
    /// (eq 6.2) and global volume fraction `phi`.
    fn evaluate(&self, j: f64, delta_v: f64, phi: f64) -> Result<(f64, f64)>;
}

impl Closure for LocalRheology {
    fn evaluate(&self, j: f64, _delta_v: f64, _phi: f64) -> Result<(f64, f64)> {
        Ok((self.phi_loc(j), self.mu(j)))
    }
}

/// A trained `dv` mapping, (J, Delta_v, phi) -> (phi_loc, mu), averaged over a box of
/// relative half-width [`SMOOTHING`] in J and Delta_v.
pub struct LearnedClosure {
    predictor: Predictor,
}

impl LearnedClosure {
    /// Wraps a predictor of the `dv` mapping.
    pub fn new(predictor: Predictor) -> Result<Self> {
        let meta = predictor.meta();
        let dv = Mapping::by_name("dv")?;
        if meta.features != dv.features || meta.outputs != dv.outputs {
            return Err(SolverError::InvalidArgument(format!(
                "the profile solver closes the balance with mapping (J, Delta_v, phi) -> \
                 (phi_loc, mu); model `{}` maps ({}) -> ({})",
                meta.mapping,
                meta.features.join(", "),
                meta.outputs.join(", ")
            )));
        }
        Ok(LearnedClosure { predictor })
    }
}

impl Closure for LearnedClosure {
    fn evaluate(&self, j: f64, delta_v: f64, phi: f64) -> Result<(f64, f64)> {
        let x = [j, delta_v, phi];
        let out = self
            .predictor
            .expected_outputs(&x, &[SMOOTHING * j, SMOOTHING * delta_v, 0.0])?;
        Ok((out[0], out[1]))
    }
}
