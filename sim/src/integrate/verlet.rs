//! The explicit step: velocity Verlet (docs/physics.md section 5), with the forces at the
//! new positions evaluated with the half-step velocities, as in the seeds' LAMMPS scheme.
use crate::error::SimError;
use crate::integrate::simulation::Simulation;
use crate::integrate::stage_timers::Stage;
use crate::state::particle_ranges::each_range;
use crate::state::particles::sphere_inertia;

/// Half a kick, the drift with the loads at the new positions, the second half kick.
pub(super) fn step(sim: &mut Simulation) -> Result<(), SimError> {
    let t = sim.timers.start();
    half_kick(sim);
    sim.timers.stop(Stage::Integration, t);
    sim.drift_and_reload();
    let t = sim.timers.start();
    half_kick(sim);
    sim.step += 1;
    sim.time += sim.timestep.dt;
    sim.timers.stop(Stage::Integration, t);
    sim.check()
}

/// Half a kick `v += F dt / (2 m)`, `omega += T dt / (2 I)`.
fn half_kick(sim: &mut Simulation) {
    let h = 0.5 * sim.timestep.dt;
    let p = &mut sim.particles;
    let (force, torque, mass, radius) = (&p.force, &p.torque, &p.mass, &p.radius);
    each_range(
        sim.accumulator.bounds(),
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
