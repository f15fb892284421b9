//! The one stepping interface of the simulation: the scene's integrator, chosen once when
//! the system is built; each is a step of `Simulation` in its own module (`verlet`,
//! `backward_euler`, `brownian_midpoint`), dispatched by `Simulation::step_observed`.
use crate::input::integrator::Integrator;

/// How a step advances the system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Stepper {
    /// Velocity Verlet (`verlet`); in a Brownian scene every force evaluation adds the
    /// dissipative and Brownian loads.
    Verlet,
    /// The implicit step of a non-Brownian scene (`backward_euler`).
    BackwardEuler,
    /// The implicit step of a Brownian scene (`brownian_midpoint`).
    BrownianMidpoint,
}

impl Stepper {
    /// The stepper of `integrator` in a scene with (`brownian`) or without thermal noise.
    pub(super) fn of(integrator: Integrator, brownian: bool) -> Self {
        match (integrator, brownian) {
            (Integrator::Explicit, _) => Stepper::Verlet,
            (Integrator::Implicit, false) => Stepper::BackwardEuler,
            (Integrator::Implicit, true) => Stepper::BrownianMidpoint,
        }
    }
}
