//! The implicit step of a non-Brownian scene (docs/physics.md section 5) and the
//! backward-Euler solve for the velocities that it and the Brownian midpoint step share.
use crate::error::SimError;
use crate::forces::resistance_network::Motion;
use crate::integrate::simulation::Simulation;
use crate::integrate::stage_timers::Stage;

impl Simulation {
    /// Drift with the last velocities, conservative loads and lubrication resistances at the
    /// new positions, then the backward-Euler solve for the new velocities under those loads,
    /// drag and lubrication. The loads a snapshot evaluates afterwards (lubrication at the new
    /// velocities) are the ones the step applied.
    pub(super) fn backward_euler_step(&mut self) -> Result<(), SimError> {
        self.drift_and_reload();
        let solved = self.solve_dissipation(self.timestep.dt, None);
        self.step += 1;
        self.time += self.timestep.dt;
        solved?;
        self.check()
    }

    /// Replaces the velocities and spins by the solution of the implicit system with step
    /// `dt` (docs/physics.md section 5), under the loads in `p.force`, `p.torque`. `guess`: the
    /// solve's warm start, when better than the current velocities.
    pub(super) fn solve_dissipation(
        &mut self,
        dt: f64,
        guess: Option<&[Motion]>,
    ) -> Result<(), SimError> {
        let t = self.timers.start();
        let drag = self.field.drag.then_some((self.field.eta, &self.profile));
        let solved = self.dissipation.solve(
            &mut self.particles,
            &self.network,
            drag,
            (dt, self.solver),
            guess,
        );
        self.timers.stop(Stage::Integration, t);
        match solved {
        Ok(stats) => {
            self.last_solve = stats;
            self.solver_totals.0 += 1;
            self.solver_totals.1 += stats.iterations as u64;
            Ok(())
        }
        Err(failure) => Err(self.blow_up(
            failure.particle,
            format!(
                "the implicit solve stopped at relative residual {:.3e} after {} iterations (largest residual on this particle)",
                failure.stats.residual, failure.stats.iterations
            ),
            "the system is ill-conditioned or not finite: lower run.dt_safety or run.dt, or raise run.solver_tolerance",
        )),
    }
    }
}
