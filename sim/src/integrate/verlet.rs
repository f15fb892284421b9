//! The explicit step: velocity Verlet (docs/physics.md section 5), with the forces at the
//! new positions evaluated with the half-step velocities, as in the seeds' LAMMPS scheme.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::integrate::stage_timers::Stage;
use crate::state::particle_ranges::each_range;
use crate::state::particles::sphere_inertia;

impl Simulation {
    /// Half a kick, the drift with the loads at the new positions, the second half kick.
    pub(super) fn verlet_step(&mut self) -> Result<(), SimError> {
        let t = self.timers.start();
        self.half_kick();
        self.timers.stop(Stage::Integration, t);
        self.drift_and_reload();
        let t = self.timers.start();
        self.half_kick();
        self.step += 1;
        self.time += self.timestep.dt;
        self.timers.stop(Stage::Integration, t);
        self.check()
    }

    /// Half a kick `v += F dt / (2 m)`, `omega += T dt / (2 I)`.
    fn half_kick(&mut self) {
        let h = 0.5 * self.timestep.dt;
        let p = &mut self.particles;
        let (force, torque, mass, radius) = (&p.force, &p.torque, &p.mass, &p.radius);
        each_range(
            self.accumulator.bounds(),
            (&mut p.vel[..], &mut p.omega[..]),
            &|_, first, (vel, omega)| {
                for (m, (v, w)) in vel.iter_mut().zip(omega.iter_mut()).enumerate() {
                    let i = first + m;
                    *v += force[i] * (h / mass[i]);
                    *w += torque[i] * (h / sphere_inertia(mass[i], radius[i]));
                }
            },
        );
    }
}
