//! Closures of the momentum balance: what `(phi_loc, mu)` a local state gives.

use surrogate::{LocalRheology, Mapping, Predictor};

use crate::error::{Result, SolverError};
use crate::theta_balance::ThetaBalance;

/// Relative half-width of the box over which a learned closure is averaged, for J and its
/// second feature (Delta_v or Theta).
pub const SMOOTHING: f64 = 0.3;

/// The local state's second feature, beside J and phi, that a closure reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Descriptor<'a> {
    /// None: a function of J alone.
    None,
    /// The velocity lag Delta_v (eq 6.2), from the solved `u` and the forcing.
    DeltaV,
    /// The suspension temperature Theta (eq 6.1), an unknown of the solve with its own
    /// balance.
    Theta(&'a ThetaBalance),
}

/// What a closure gives at one local state.
pub trait Closure {
    /// `(phi_loc, mu)` at local viscous number `j`, second feature `descriptor` (the value
    /// of [`Closure::descriptor`]; ignored by a law of J alone) and global volume fraction
    /// `phi`.
    fn evaluate(&self, j: f64, descriptor: f64, phi: f64) -> Result<(f64, f64)>;

    /// Which second feature [`Closure::evaluate`] reads.
    fn descriptor(&self) -> Descriptor<'_>;
}

impl Closure for LocalRheology {
    fn evaluate(&self, j: f64, _descriptor: f64, _phi: f64) -> Result<(f64, f64)> {
        Ok((self.phi_loc(j), self.mu(j)))
    }

    fn descriptor(&self) -> Descriptor<'_> {
        Descriptor::None
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
        check_mapping(&predictor, "dv")?;
        Ok(LearnedClosure { predictor })
    }
}

impl Closure for LearnedClosure {
    fn evaluate(&self, j: f64, delta_v: f64, phi: f64) -> Result<(f64, f64)> {
        smoothed(&self.predictor, j, delta_v, phi)
    }

    fn descriptor(&self) -> Descriptor<'_> {
        Descriptor::DeltaV
    }
}

/// The nonlocal closure: a trained `theta` mapping, (J, Theta, phi) -> (phi_loc, mu),
/// averaged over a box of relative half-width [`SMOOTHING`] in J and Theta, with Theta from
/// its own balance ([`ThetaBalance`]).
pub struct NonlocalClosure {
    predictor: Predictor,
    balance: ThetaBalance,
}

impl NonlocalClosure {
    /// Wraps a predictor of the `theta` mapping and the balance that gives Theta.
    pub fn new(predictor: Predictor, balance: ThetaBalance) -> Result<Self> {
        check_mapping(&predictor, "theta")?;
        Ok(NonlocalClosure { predictor, balance })
    }
}

impl Closure for NonlocalClosure {
    fn evaluate(&self, j: f64, theta: f64, phi: f64) -> Result<(f64, f64)> {
        smoothed(&self.predictor, j, theta, phi)
    }

    fn descriptor(&self) -> Descriptor<'_> {
        Descriptor::Theta(&self.balance)
    }
}

/// Refuses a model that is not of mapping `name`, (J, _, phi) -> (phi_loc, mu).
fn check_mapping(predictor: &Predictor, name: &str) -> Result<()> {
    let meta = predictor.meta();
    let mapping = Mapping::by_name(name)?;
    if meta.features != mapping.features || meta.outputs != mapping.outputs {
        return Err(SolverError::InvalidArgument(format!(
            "this closure takes mapping `{name}`, ({}) -> ({}); model `{}` maps ({}) -> ({})",
            mapping.features.join(", "),
            mapping.outputs.join(", "),
            meta.mapping,
            meta.features.join(", "),
            meta.outputs.join(", ")
        )));
    }
    Ok(())
}

/// The expected `(phi_loc, mu)` over a box of relative half-width [`SMOOTHING`] in the first
/// two features (trees are piecewise constant; their box average is continuous).
fn smoothed(predictor: &Predictor, j: f64, second: f64, phi: f64) -> Result<(f64, f64)> {
    let out =
        predictor.expected_outputs(&[j, second, phi], &[SMOOTHING * j, SMOOTHING * second, 0.0])?;
    Ok((out[0], out[1]))
}
