//! Closures of the momentum balance: what `(phi_loc, mu)` a local state gives, and the
//! interval around it where the closure is a trained mapping with intervals.

use surrogate::{LocalRheology, Mapping, Predictor};

use crate::error::{Result, SolverError};
use crate::smoothing::{EXTREMUM_SMOOTHING_FLOOR, SMOOTHING};
use crate::theta_balance::ThetaBalance;

/// The index of phi_loc and of mu among a closure's outputs `(phi_loc, mu)`.
pub const PHI_LOC: usize = 0;
pub const MU: usize = 1;

/// The ends of the intervals of `(phi_loc, mu)`: `[(lower, upper) of phi_loc, (lower,
/// upper) of mu]`.
pub type ClosureInterval = [(f64, f64); 2];

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
    /// The distance to the nearest velocity extremum, d_ext (units a), from the solved `u`
    /// (`surrogate::data::extremum_distance`).
    ExtremumDistance,
}

/// What a closure gives at one local state.
pub trait Closure {
    /// `(phi_loc, mu)` at local viscous number `j`, second feature `descriptor` (the value
    /// of [`Closure::descriptor`]; ignored by a law of J alone) and global volume fraction
    /// `phi`.
    fn evaluate(&self, j: f64, descriptor: f64, phi: f64) -> Result<(f64, f64)>;

    /// Output `output` ([`PHI_LOC`] or [`MU`]) of [`Closure::evaluate`] alone, for callers
    /// that need one (a learned closure then walks only that output's trees).
    fn evaluate_output(&self, j: f64, descriptor: f64, phi: f64, output: usize) -> Result<f64> {
        let (phi_loc, mu) = self.evaluate(j, descriptor, phi)?;
        Ok(if output == PHI_LOC { phi_loc } else { mu })
    }

    /// Which second feature [`Closure::evaluate`] reads.
    fn descriptor(&self) -> Descriptor<'_>;

    /// The interval at `level` of `(phi_loc, mu)` at the state of [`Closure::evaluate`];
    /// `None` for a closure without intervals (the local law, or a model saved without them).
    fn interval(
        &self,
        _j: f64,
        _descriptor: f64,
        _phi: f64,
        _level: f64,
    ) -> Result<Option<ClosureInterval>> {
        Ok(None)
    }
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
        smoothed(&self.predictor, &local_box(j, delta_v, phi))
    }

    fn evaluate_output(&self, j: f64, delta_v: f64, phi: f64, output: usize) -> Result<f64> {
        smoothed_output(&self.predictor, &local_box(j, delta_v, phi), output)
    }

    fn descriptor(&self) -> Descriptor<'_> {
        Descriptor::DeltaV
    }

    fn interval(
        &self,
        j: f64,
        delta_v: f64,
        phi: f64,
        level: f64,
    ) -> Result<Option<ClosureInterval>> {
        smoothed_interval(&self.predictor, &local_box(j, delta_v, phi), level)
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
        smoothed(&self.predictor, &local_box(j, theta, phi))
    }

    fn evaluate_output(&self, j: f64, theta: f64, phi: f64, output: usize) -> Result<f64> {
        smoothed_output(&self.predictor, &local_box(j, theta, phi), output)
    }

    fn descriptor(&self) -> Descriptor<'_> {
        Descriptor::Theta(&self.balance)
    }

    fn interval(
        &self,
        j: f64,
        theta: f64,
        phi: f64,
        level: f64,
    ) -> Result<Option<ClosureInterval>> {
        smoothed_interval(&self.predictor, &local_box(j, theta, phi), level)
    }
}

/// The closure of the `ext` mapping, (J, phi, d_ext) -> (phi_loc, mu), with d_ext the
/// distance to the nearest velocity extremum of the solved profile, averaged over a box of
/// relative half-width [`SMOOTHING`] in J and in d_ext (at least
/// [`EXTREMUM_SMOOTHING_FLOOR`]).
pub struct ExtremumClosure {
    predictor: Predictor,
}

impl ExtremumClosure {
    /// Wraps a predictor of the `ext` mapping.
    pub fn new(predictor: Predictor) -> Result<Self> {
        check_mapping(&predictor, "ext")?;
        Ok(ExtremumClosure { predictor })
    }

    /// The features `(J, phi, d_ext)` and their box.
    fn inputs(j: f64, d_ext: f64, phi: f64) -> FeatureBox {
        FeatureBox {
            x: [j, phi, d_ext],
            half_width: [
                SMOOTHING * j,
                0.0,
                SMOOTHING * d_ext + EXTREMUM_SMOOTHING_FLOOR,
            ],
        }
    }
}

impl Closure for ExtremumClosure {
    fn evaluate(&self, j: f64, d_ext: f64, phi: f64) -> Result<(f64, f64)> {
        smoothed(&self.predictor, &Self::inputs(j, d_ext, phi))
    }

    fn evaluate_output(&self, j: f64, d_ext: f64, phi: f64, output: usize) -> Result<f64> {
        smoothed_output(&self.predictor, &Self::inputs(j, d_ext, phi), output)
    }

    fn descriptor(&self) -> Descriptor<'_> {
        Descriptor::ExtremumDistance
    }

    fn interval(
        &self,
        j: f64,
        d_ext: f64,
        phi: f64,
        level: f64,
    ) -> Result<Option<ClosureInterval>> {
        smoothed_interval(&self.predictor, &Self::inputs(j, d_ext, phi), level)
    }
}

/// Refuses a model that is not of mapping `name`, with outputs (phi_loc, mu).
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

/// A mapping's three features and the half-widths of the box they are averaged over.
struct FeatureBox {
    x: [f64; 3],
    half_width: [f64; 3],
}

/// The features of the `dv` and `theta` mappings, `(J, second, phi)`, with a box of relative
/// half-width [`SMOOTHING`] in the first two.
fn local_box(j: f64, second: f64, phi: f64) -> FeatureBox {
    FeatureBox {
        x: [j, second, phi],
        half_width: [SMOOTHING * j, SMOOTHING * second, 0.0],
    }
}

/// The expected `(phi_loc, mu)` over the box (trees are piecewise constant; their box
/// average is continuous).
fn smoothed(predictor: &Predictor, b: &FeatureBox) -> Result<(f64, f64)> {
    let out = predictor.expected_outputs(&b.x, &b.half_width)?;
    Ok((out[0], out[1]))
}

/// One output of [`smoothed`].
fn smoothed_output(predictor: &Predictor, b: &FeatureBox, output: usize) -> Result<f64> {
    Ok(predictor.expected_output(&b.x, &b.half_width, output)?)
}

/// The interval at `level` of the expected `(phi_loc, mu)` over the box.
fn smoothed_interval(
    predictor: &Predictor,
    b: &FeatureBox,
    level: f64,
) -> Result<Option<ClosureInterval>> {
    Ok(predictor
        .expected_interval(&b.x, &b.half_width, level)?
        .map(|i| {
            [
                (i.lower[[0, 0]], i.upper[[0, 0]]),
                (i.lower[[0, 1]], i.upper[[0, 1]]),
            ]
        }))
}
