//! The one stepping interface of a [`Simulation`]: the scene's integrator, chosen once
//! when the system is built, each in its own module.
use crate::error::SimError;
use crate::input::integrator::Integrator;
use crate::integrate::simulation::Simulation;
use crate::integrate::{backward_euler, brownian_midpoint, verlet};

/// How a step advances the system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Stepper {
    /// Velocity Verlet ([`verlet`]); in a Brownian scene every force evaluation adds the
    /// dissipative and Brownian loads.
    Verlet,
    /// The implicit step of a non-Brownian scene ([`backward_euler`]).
    BackwardEuler,
    /// The implicit step of a Brownian scene ([`brownian_midpoint`]).
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

    /// One step of `sim`; `at_midpoint` sees the system at the midpoint of a Brownian
    /// midpoint step (the other steppers never call it).
    pub(super) fn step(
        self,
        sim: &mut Simulation,
        at_midpoint: &mut dyn FnMut(&Simulation),
    ) -> Result<(), SimError> {
        match self {
            Stepper::Verlet => verlet::step(sim),
            Stepper::BackwardEuler => backward_euler::step(sim),
            Stepper::BrownianMidpoint => brownian_midpoint::step(sim, at_midpoint),
        }
    }
}
