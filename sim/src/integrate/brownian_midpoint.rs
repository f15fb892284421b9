//! The implicit step of a Brownian scene (docs/physics.md section 11): the dissipative
//! loads by the trapezoidal rule and the positions at the midpoint of the step's mean
//! velocity.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::integrate::stage_timers::Stage;

impl Simulation {
    /// One midpoint step: the step's mean velocity `W = (V + V') / 2` solves
    /// `(M + dt/2 (D + R)) W = M V + dt/2 (F_c + D V_inf + F_B)`. A predictor solves it with
    /// the loads and resistance at the start `x`, the corrector at `x + dt/2 W_predicted` with
    /// the same Brownian loads `F_B` (drawn once from `R(x)`); then `x' = x + dt W`,
    /// `V' = 2 W - V`. For a frozen resistance this keeps the velocities at `kT / m` and the
    /// long-time diffusion at `kT / R` at any `dt`, and the midpoint gives the stochastic drift
    /// `kT div R^-1` where the step overdamps the lubricated pairs. `at_midpoint` sees the
    /// system at the midpoint, its velocities the step's mean velocity `W`.
    pub(super) fn midpoint_step(
        &mut self,
        at_midpoint: &mut dyn FnMut(&Simulation),
    ) -> Result<(), SimError> {
        let (dt, half) = (self.timestep.dt, 0.5 * self.timestep.dt);
        if self.list.stale(&self.particles.pos, &self.pbox) {
            self.rebuild_list();
        }
        // Springs are advanced once, by the corrector's evaluation.
        self.evaluate_loads(0.0, self.step);
        let t = self.timers.start();
        let th = self
            .thermal
            .as_mut()
            .expect("a Brownian step has its noise");
        th.kick(&self.network, &mut self.particles, &self.field, self.step);
        self.midpoint.keep_start(&self.particles);
        self.timers.stop(Stage::Integration, t);
        self.solve_dissipation(half, None)?;
        let t = self.timers.start();
        self.pbox.set_time(self.time + half);
        self.midpoint
            .move_to_midpoint(&mut self.particles, &self.pbox, half);
        self.timers.stop(Stage::Integration, t);
        if self.list.stale(&self.particles.pos, &self.pbox) {
            // No re-sorting: the step's arrays keep their order.
            let identity: Vec<u32> = (0..self.particles.len() as u32).collect();
            self.build_list(self.particles.pos.clone(), &identity);
        }
        // The loads and resistances at the midpoint, the start's network kept aside.
        std::mem::swap(&mut self.network, &mut self.midpoint.start_network);
        self.evaluate_loads(dt, self.step);
        let th = self
            .thermal
            .as_mut()
            .expect("a Brownian step has its noise");
        th.kick_at_midpoint(
            (&self.midpoint.start_network, &self.network),
            (&mut self.particles, &self.pbox),
            &self.field,
            (&self.midpoint.predicted, half),
            self.step,
        );
        self.midpoint.keep_guess(&self.particles);
        self.midpoint.restore_start(&mut self.particles);
        let guess = std::mem::take(&mut self.midpoint.guess);
        let solved = self.solve_dissipation(half, Some(&guess));
        self.midpoint.guess = guess;
        solved?;
        let t = self.timers.start();
        at_midpoint(self);
        self.timers.stop(Stage::Sampling, t);
        let t = self.timers.start();
        self.pbox.set_time(self.time + dt);
        self.midpoint
            .move_to_end(&mut self.particles, &self.pbox, dt);
        self.step += 1;
        self.time += dt;
        self.timers.stop(Stage::Integration, t);
        self.check()
    }
}
