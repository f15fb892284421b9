//! Helpers shared by the integration tests.
use sim::integrate::simulation::Simulation;
use sim::Vec3;

/// Pushes the particle of identity 0 along +x and every other particle along -x with a
/// constant body force `f`.
pub fn push_together(s: &mut Simulation, f: f64) {
    s.body_force = s
        .particles
        .id
        .iter()
        .map(|&id| {
            if id == 0 {
                Vec3::x() * f
            } else {
                -Vec3::x() * f
            }
        })
        .collect();
}
