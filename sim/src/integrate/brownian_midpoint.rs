//! The implicit step of a Brownian scene (docs/physics.md section 11): the dissipative
//! loads by the trapezoidal rule and the positions at the midpoint of the step's mean
//! velocity.
use crate::error::SimError;
use crate::forces::resistance_network::{Motion, ResistanceNetwork};
use crate::integrate::backward_euler::solve_dissipation;
use crate::integrate::simulation::Simulation;
use crate::integrate::stage_timers::Stage;
use crate::state::particles::Particles;
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;

/// The per-particle arrays of the midpoint step, reused every step.
#[derive(Default)]
pub(super) struct MidpointArrays {
    /// Velocities and spins at the start of the step.
    start: Vec<Motion>,
    /// The predictor's mean velocity over the step, which carried the positions to the
    /// midpoint.
    predicted: Vec<Vec3>,
    /// The predictor's mean velocity and spin, the corrector's warm start.
    guess: Vec<Motion>,
    /// The resistance network at the start of the step, kept while the midpoint's is
    /// built.
    start_network: ResistanceNetwork,
}

/// One midpoint step: the step's mean velocity `W = (V + V') / 2` solves
/// `(M + dt/2 (D + R)) W = M V + dt/2 (F_c + D V_inf + F_B)`. A predictor solves it with
/// the loads and resistance at the start `x`, the corrector at `x + dt/2 W_predicted` with
/// the same Brownian loads `F_B` (drawn once from `R(x)`); then `x' = x + dt W`,
/// `V' = 2 W - V`. For a frozen resistance this keeps the velocities at `kT / m` and the
/// long-time diffusion at `kT / R` at any `dt`, and the midpoint gives the stochastic drift
/// `kT div R^-1` where the step overdamps the lubricated pairs. `at_midpoint` sees the
/// system at the midpoint, its velocities the step's mean velocity `W`.
pub(super) fn step(
    sim: &mut Simulation,
    at_midpoint: &mut dyn FnMut(&Simulation),
) -> Result<(), SimError> {
    let (dt, half) = (sim.timestep.dt, 0.5 * sim.timestep.dt);
    if sim.list.stale(&sim.particles.pos, &sim.pbox) {
        sim.rebuild_list();
    }
    // Springs are advanced once, by the corrector's evaluation.
    sim.evaluate_loads(0.0, sim.step);
    let t = sim.timers.start();
    let th = sim.thermal.as_mut().expect("a Brownian step has its noise");
    th.kick(&sim.network, &mut sim.particles, &sim.field, sim.step);
    sim.midpoint.keep_start(&sim.particles);
    sim.timers.stop(Stage::Integration, t);
    solve_dissipation(sim, half, None)?;
    let t = sim.timers.start();
    sim.pbox.set_time(sim.time + half);
    sim.midpoint
        .move_to_midpoint(&mut sim.particles, &sim.pbox, half);
    sim.timers.stop(Stage::Integration, t);
    if sim.list.stale(&sim.particles.pos, &sim.pbox) {
        // No re-sorting: the step's arrays keep their order.
        let identity: Vec<u32> = (0..sim.particles.len() as u32).collect();
        sim.build_list(sim.particles.pos.clone(), &identity);
    }
    // The loads and resistances at the midpoint, the start's network kept aside.
    std::mem::swap(&mut sim.network, &mut sim.midpoint.start_network);
    sim.evaluate_loads(dt, sim.step);
    let th = sim.thermal.as_mut().expect("a Brownian step has its noise");
    th.kick_at_midpoint(
        (&sim.midpoint.start_network, &sim.network),
        (&mut sim.particles, &sim.pbox),
        &sim.field,
        (&sim.midpoint.predicted, half),
        sim.step,
    );
    sim.midpoint.keep_guess(&sim.particles);
    sim.midpoint.restore_start(&mut sim.particles);
    let guess = std::mem::take(&mut sim.midpoint.guess);
    let solved = solve_dissipation(sim, half, Some(&guess));
    sim.midpoint.guess = guess;
    solved?;
    let t = sim.timers.start();
    at_midpoint(sim);
    sim.timers.stop(Stage::Sampling, t);
    let t = sim.timers.start();
    sim.pbox.set_time(sim.time + dt);
    sim.midpoint.move_to_end(&mut sim.particles, &sim.pbox, dt);
    sim.step += 1;
    sim.time += dt;
    sim.timers.stop(Stage::Integration, t);
    sim.check()
}

impl MidpointArrays {
    /// Keeps the velocities and spins at the start of the step.
    fn keep_start(&mut self, p: &Particles) {
        self.start.clear();
        self.start
            .extend(p.vel.iter().zip(&p.omega).map(|(v, w)| [*v, *w]));
    }

    /// Keeps the predictor's mean velocities and spins (in `p.vel`, `p.omega`) as the
    /// corrector's warm start.
    fn keep_guess(&mut self, p: &Particles) {
        self.guess.clear();
        self.guess
            .extend(p.vel.iter().zip(&p.omega).map(|(v, w)| [*v, *w]));
    }

    /// Sets the velocities and spins back to those at the start of the step.
    fn restore_start(&self, p: &mut Particles) {
        for ((v, w), s) in p.vel.iter_mut().zip(p.omega.iter_mut()).zip(&self.start) {
            (*v, *w) = (s[0], s[1]);
        }
    }

    /// Moves the particles by `half` (dt / 2) times the predictor's mean velocity (in
    /// `p.vel`, which it keeps) into the box at the midpoint time. A particle that leaves
    /// through a y face of a sheared box becomes its sliding image, and every velocity
    /// of the step kept for it is remapped with it.
    fn move_to_midpoint(&mut self, p: &mut Particles, pbox: &PeriodicBox, half: f64) {
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
    fn move_to_end(&self, p: &mut Particles, pbox: &PeriodicBox, dt: f64) {
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
