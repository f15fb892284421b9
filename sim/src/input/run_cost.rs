//! What a run will cost before it starts: its time steps, particle-steps and wall time
//! on this machine, from the scene's automatic time step; runs that cannot finish are
//! refused and long ones announced, by the rule of [`schema::work_cost`].
use crate::error::SimError;
use crate::input::scene_file::RunSection;
use crate::input::scene_limits::show;
use schema::work_cost;

/// Particle-steps per second of a run here (2 cores): the validation scenes of the full
/// report ran at 9.0-9.3e5 (README, Report), rounded up so that estimates err short.
pub const PARTICLE_STEPS_PER_S: f64 = 1e6;

/// The same for a Brownian scene's implicit (midpoint) step, two force evaluations and two
/// solves a step, set by the slowest scenes measured, so that estimates err long elsewhere:
/// the dense frictional colloid-grain mixtures run 2.7-3.9e5 per core (reports/mixtures
/// README's cost table). Frictionless scenes run 2-3x faster: `suspflow bench --brownian`
/// (thesis Table 4.1's state, code 309b1b7, quiet machine) 8.9e5 at N 1000 and 7.7e5 at
/// N 4000 on one core, 9.1e5 and 8.8e5 on two; the Pe 0.1 step-convergence runs (N
/// 1013-1238) about 8e5 per core.
pub const BROWNIAN_PARTICLE_STEPS_PER_S: f64 = 3e5;

/// The cost of a run to its strain budget plus its averaging.
#[derive(Clone, Copy, Debug)]
pub struct RunCost {
    /// Time steps per unit strain (strain = gdot_max x time).
    pub steps_per_strain: f64,
    /// Most particle-steps of the equilibration (to `run.max_strain`) or warm-up.
    pub equilibration_particle_steps: f64,
    /// Particle-steps of the averaging (`run.snapshots` x `run.sample_strain`) or of the
    /// measured window.
    pub averaging_particle_steps: f64,
    /// Particle-steps per second here ([`PARTICLE_STEPS_PER_S`] or, for a Brownian scene,
    /// [`BROWNIAN_PARTICLE_STEPS_PER_S`]).
    pub rate: f64,
}

impl RunCost {
    /// The cost of a run of `run` for `n_particles` at `steps_per_strain` steps per unit
    /// of its clock, with Brownian forces or not.
    pub fn new(
        steps_per_strain: f64,
        n_particles: usize,
        r: &RunSection,
        brownian: bool,
    ) -> RunCost {
        RunCost::of_steps(
            steps_per_strain,
            n_particles,
            [
                steps_per_strain * r.max_strain,
                steps_per_strain * r.sample_strain * r.snapshots as f64,
            ],
            brownian,
        )
    }

    /// The cost of `[warm-up, window]` time steps (as real numbers: a length beyond any
    /// counter is refused, not wrapped) of `n_particles` at `steps_per_clock` steps per
    /// unit of the run's clock (strain or tau_B), with Brownian forces or not.
    pub fn of_steps(
        steps_per_clock: f64,
        n_particles: usize,
        [warmup, window]: [f64; 2],
        brownian: bool,
    ) -> RunCost {
        let n = n_particles as f64;
        RunCost {
            steps_per_strain: steps_per_clock,
            equilibration_particle_steps: warmup * n,
            averaging_particle_steps: window * n,
            rate: if brownian {
                BROWNIAN_PARTICLE_STEPS_PER_S
            } else {
                PARTICLE_STEPS_PER_S
            },
        }
    }

    /// Estimated wall time at most (s) here, at [`Self::rate`].
    pub fn seconds(&self) -> f64 {
        (self.equilibration_particle_steps + self.averaging_particle_steps) / self.rate
    }

    /// Refuses a run longer than [`work_cost::REFUSE_SECONDS`] (or of no finite length) and
    /// returns a warning for one longer than [`work_cost::WARN_SECONDS`].
    pub fn check(&self) -> Result<Option<String>, SimError> {
        self.check_levers(
            "the time step (forces.k_n, forces.xi_min, run.dt_factor, run.dt, the radii), the \
             shear rate of the flow, run.max_strain or run.snapshots are extreme",
        )
        .map_err(|message| SimError::field("run", message))
    }

    /// [`RunCost::check`] of any run: the refusal (its message, ending with `levers`, what
    /// sets the run's length) or the warning.
    pub fn check_levers(&self, levers: &str) -> Result<Option<String>, String> {
        let what = format!(
            "{:.2e} steps per unit strain (or tau_B), at most {:.2e} particle-steps at {} \
             particle-steps/s",
            self.steps_per_strain,
            self.equilibration_particle_steps + self.averaging_particle_steps,
            show(self.rate)
        );
        work_cost::check("run", self.seconds(), &what, levers)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lasting(seconds: f64) -> RunCost {
        RunCost {
            steps_per_strain: 1e3,
            equilibration_particle_steps: seconds * PARTICLE_STEPS_PER_S,
            averaging_particle_steps: 0.0,
            rate: PARTICLE_STEPS_PER_S,
        }
    }

    #[test]
    fn a_day_warns_a_year_is_refused_and_no_length_is_refused() {
        assert_eq!(lasting(3600.0).check().unwrap(), None);
        let warning = lasting(2.0 * work_cost::WARN_SECONDS)
            .check()
            .unwrap()
            .unwrap();
        assert!(warning.contains("about 2.0 days here"), "{warning}");
        let refusal = lasting(2.0 * work_cost::REFUSE_SECONDS)
            .check()
            .unwrap_err()
            .to_string();
        assert!(
            refusal.contains("the run cannot finish") && refusal.contains("about 2.0 years here"),
            "{refusal}"
        );
        assert!(lasting(f64::NAN).check().is_err());
        assert!(lasting(f64::INFINITY).check().is_err());
    }
}
