//! The Brownian loads of a scene with `kT > 0` (docs/physics.md section 11): the keyed
//! noise and its work arrays, and the one place where a step's Brownian loads are drawn
//! and added to the particles' loads, for the explicit step and the implicit midpoint step
//! alike.
use crate::forces::force_field::ForceField;
use crate::forces::lubrication::gap;
use crate::forces::network_loads::{
    add_dissipative_loads, add_selected_pair_loads, brownian_loads, Draw,
};
use crate::forces::resistance_network::{Motion, ResistanceNetwork, ResistancePair};
use crate::forces::thermal_noise::ThermalNoise;
use crate::input::flow_profile::FlowProfile;
use crate::state::particles::Particles;
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;

/// What a Brownian scene's steps keep besides the particles: the thermal energy, the keyed
/// noise and the per-particle arrays of its loads, reused every step.
pub(super) struct Thermal {
    /// Thermal energy kT (units of energy, > 0).
    kt: f64,
    noise: ThermalNoise,
    /// The step's Brownian loads (force, torque).
    kicks: Vec<Motion>,
    /// Work space of the explicit step's dissipative loads.
    motion: Vec<Motion>,
    scratch: Vec<Motion>,
}

impl Thermal {
    /// The noise at thermal energy `kt` for steps of `dt`, keyed by the run's `seed`.
    pub(super) fn new(kt: f64, dt: f64, seed: u64) -> Self {
        Thermal {
            kt,
            noise: ThermalNoise::new(kt, dt, seed),
            kicks: Vec::new(),
            motion: Vec::new(),
            scratch: Vec::new(),
        }
    }

    /// Thermal energy kT.
    pub(super) fn kt(&self) -> f64 {
        self.kt
    }

    /// The explicit step's loads of the fluid at the current motion: the dissipative loads
    /// of drag and lubrication (thesis eqs 3.5, 3.6, 3.13, 3.14), then the Brownian loads
    /// of evaluation `step` ([`Thermal::kick`]).
    pub(super) fn add_explicit_fluid_loads(
        &mut self,
        network: &ResistanceNetwork,
        (field, profile): (&ForceField, &FlowProfile),
        p: &mut Particles,
        step: u64,
    ) {
        add_dissipative_loads(
            network,
            field,
            profile,
            p,
            (&mut self.motion, &mut self.scratch),
        );
        self.kick(network, p, field, step);
    }

    /// Draws the Brownian loads of `step` from the resistance network at the current
    /// positions (one-body parts where the field has drag) and adds them to the particles'
    /// loads.
    pub(super) fn kick(
        &mut self,
        network: &ResistanceNetwork,
        p: &mut Particles,
        field: &ForceField,
        step: u64,
    ) {
        self.kicks.resize(p.len(), Motion::default());
        let drag_eta = field.drag.then_some(field.eta);
        let draw = Draw {
            noise: &self.noise,
            particles: p,
            step,
        };
        brownian_loads(draw, network, drag_eta, &mut self.kicks);
        self.add_kicks(p);
    }

    /// Adds the loads of [`Thermal::kick`] again, made those of the pairs inside the
    /// cut-off at the midpoint, where the corrector dissipates: the loads drawn at the
    /// start, less those of the start's pairs (`networks.0`) that have left the cut-off,
    /// plus those of the midpoint's pairs (`networks.1`) that were beyond it at the start,
    /// drawn from their resistance at the midpoint. `predicted`: the predictor's mean
    /// velocities, which carried the positions over `half` (dt / 2) to the midpoint. A
    /// pair's noise and its dissipation then switch on and off together, at the midpoint of
    /// the step that crosses the cut-off.
    pub(super) fn kick_at_midpoint(
        &mut self,
        (start, midpoint): (&ResistanceNetwork, &ResistanceNetwork),
        (p, pbox): (&mut Particles, &PeriodicBox),
        field: &ForceField,
        (predicted, half): (&[Vec3], f64),
        step: u64,
    ) {
        let positions: &Particles = p;
        // Whether the pair's gap, with particle j at `shift` from its midpoint place
        // relative to i, is beyond the cut-off.
        let beyond = |pair: &ResistancePair, shift: &dyn Fn(i32) -> Vec3| {
            let (i, j) = (pair.i as usize, pair.j as usize);
            let (r, image) = pbox.image(&positions.pos[i], &positions.pos[j]);
            let c = field.constants(positions.species[i], positions.species[j]);
            let lub = c.lubrication.as_ref().expect("network pairs lubricate");
            gap(
                (r + shift(image)).norm(),
                positions.radius[i],
                positions.radius[j],
            ) >= lub.xi_end()
        };
        let left = |pair: &ResistancePair| beyond(pair, &|_| Vec3::zeros());
        let entered = |pair: &ResistancePair| {
            let (i, j) = (pair.i as usize, pair.j as usize);
            beyond(pair, &|image| {
                (predicted[j] - predicted[i] + pbox.image_velocity(image)) * -half
            })
        };
        let draw = Draw {
            noise: &self.noise,
            particles: positions,
            step,
        };
        add_selected_pair_loads(draw, start, -1.0, &left, &mut self.kicks);
        add_selected_pair_loads(draw, midpoint, 1.0, &entered, &mut self.kicks);
        self.add_kicks(p);
    }

    /// Adds the drawn Brownian loads to the particles' loads.
    fn add_kicks(&self, p: &mut Particles) {
        for ((f, t), k) in p.force.iter_mut().zip(p.torque.iter_mut()).zip(&self.kicks) {
            *f += k[0];
            *t += k[1];
        }
    }
}
