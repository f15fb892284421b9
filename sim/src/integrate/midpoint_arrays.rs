//! The per-particle arrays of the Brownian midpoint step (docs/physics.md section 11): the
//! velocities at the start, the predictor's mean velocities, and the moves of the positions
//! to the midpoint and to the end of the step.
use crate::forces::resistance_network::{Motion, ResistanceNetwork};
use crate::state::particles::Particles;
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;

/// The per-particle arrays of the midpoint step, reused every step.
#[derive(Default)]
pub(super) struct MidpointArrays {
    /// Velocities and spins at the start of the step.
    pub(super) start: Vec<Motion>,
    /// The predictor's mean velocity over the step, which carried the positions to the
    /// midpoint.
    pub(super) predicted: Vec<Vec3>,
    /// The predictor's mean velocity and spin, the corrector's warm start.
    pub(super) guess: Vec<Motion>,
    /// The resistance network at the start of the step, kept while the midpoint's is
    /// built.
    pub(super) start_network: ResistanceNetwork,
}

impl MidpointArrays {
    /// Keeps the velocities and spins at the start of the step.
    pub(super) fn keep_start(&mut self, p: &Particles) {
        self.start.clear();
        self.start
            .extend(p.vel.iter().zip(&p.omega).map(|(v, w)| [*v, *w]));
    }

    /// Keeps the predictor's mean velocities and spins (in `p.vel`, `p.omega`) as the
    /// corrector's warm start.
    pub(super) fn keep_guess(&mut self, p: &Particles) {
        self.guess.clear();
        self.guess
            .extend(p.vel.iter().zip(&p.omega).map(|(v, w)| [*v, *w]));
    }

    /// Sets the velocities and spins back to those at the start of the step.
    pub(super) fn restore_start(&self, p: &mut Particles) {
        for ((v, w), s) in p.vel.iter_mut().zip(p.omega.iter_mut()).zip(&self.start) {
            (*v, *w) = (s[0], s[1]);
        }
    }

    /// Moves the particles by `half` (dt / 2) times the predictor's mean velocity (in
    /// `p.vel`, which it keeps) into the box at the midpoint time. A particle that leaves
    /// through a y face of a sheared box becomes its sliding image, and every velocity
    /// of the step kept for it is remapped with it.
    pub(super) fn move_to_midpoint(&mut self, p: &mut Particles, pbox: &PeriodicBox, half: f64) {
        self.predicted.clear();
        self.predicted.extend_from_slice(&p.vel);
        for ((x, w), s) in p
            .pos
            .iter_mut()
            .zip(&mut self.predicted)
            .zip(&mut self.start)
        {
            *x += *w * half;
            let before = s[0];
            pbox.wrap(x, &mut s[0]);
            *w += s[0] - before;
        }
        p.vel.copy_from_slice(&self.predicted);
    }

    /// The end of the step from the corrector's mean velocity `W` (in `p.vel`, spins in
    /// `p.omega`): positions `x + dt W` (from the midpoint, `+ dt W - dt/2 W_predicted`),
    /// wrapped into the box at the end time, velocities `2 W - V` (remapped with the
    /// position), spins likewise.
    pub(super) fn move_to_end(&self, p: &mut Particles, pbox: &PeriodicBox, dt: f64) {
        let moves = p
            .pos
            .iter_mut()
            .zip(p.vel.iter_mut())
            .zip(p.omega.iter_mut());
        for (((x, v), w), (s, wp)) in moves.zip(self.start.iter().zip(&self.predicted)) {
            *x += *v * dt - *wp * (0.5 * dt);
            *v = *v * 2.0 - s[0];
            *w = *w * 2.0 - s[1];
            pbox.wrap(x, v);
        }
    }
}
