//! One-dimensional minimisation by Brent's method (`argmin`), shared by the rheology fits
//! that reduce to one nonlinear parameter (the flow-curve exponent `b`, the jamming
//! fraction `phi_J`).

use argmin::core::{CostFunction, Executor};
use argmin::solver::brent::BrentOpt;

use crate::error::{Result, SurrogateError};

/// Iterations before Brent's method gives up.
const MAX_ITERATIONS: u64 = 200;

/// A cost of one parameter, as `argmin` takes it.
struct Cost<F>(F);

impl<F: Fn(f64) -> f64> CostFunction for Cost<F> {
    type Param = f64;
    type Output = f64;

    fn cost(&self, x: &f64) -> std::result::Result<f64, argmin::core::Error> {
        Ok((self.0)(*x))
    }
}

/// The `x` in `[lower, upper]` that minimises `cost`; `what` names the fit in errors
/// (e.g. "fitting the flow curve mu(J)").
pub fn minimise(cost: impl Fn(f64) -> f64, lower: f64, upper: f64, what: &str) -> Result<f64> {
    let result = Executor::new(Cost(cost), BrentOpt::new(lower, upper))
        .configure(|state| state.max_iters(MAX_ITERATIONS))
        .run()
        .map_err(|e| SurrogateError::InvalidArgument(format!("{what}: {e}")))?;
    result
        .state()
        .best_param
        .ok_or_else(|| SurrogateError::InvalidArgument(format!("{what} found no value")))
}
