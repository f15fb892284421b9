//! The initial state of a run: the scene's particles in a random non-overlapping packing
//! at rest, drawn from the scene's seed (docs/physics.md section 3).
use crate::error::SimError;
use crate::input::packing::random_packing_watched;
use crate::input::scene::Scene;
use crate::state::particles::Particles;
use crate::state::Vec3;
use rand::SeedableRng;

/// Smallest gap left between particles by the initial packing, as a fraction of the
/// pair's mean radius: every centre distance >= 1.002 (a_i + a_j), as the LAMMPS peer's
/// generator, so no pair starts inside the regularised lubrication range.
pub const PACKING_GAP: f64 = 4e-3;

/// The initial state: a random non-overlapping packing at rest, from the scene's seed.
pub fn initial_particles(scene: &Scene) -> Result<Particles, SimError> {
    initial_particles_watched(scene, &mut |_| true)
}

/// [`initial_particles`], the packing watched by `watch` (see
/// [`random_packing_watched`]: it is told the overlapping pairs left, and stops the
/// packing by returning false).
pub fn initial_particles_watched(
    scene: &Scene,
    watch: &mut dyn FnMut(usize) -> bool,
) -> Result<Particles, SimError> {
    let radius = scene.particle_radii();
    let mut rng = rand::rngs::StdRng::seed_from_u64(scene.file.seed);
    let pos = random_packing_watched(&radius, scene.box_len, &mut rng, PACKING_GAP, watch)?;
    Ok(Particles::at_rest(
        pos.into_iter().map(Vec3::from).collect(),
        radius,
        scene.particle_species(),
        scene.rho,
    ))
}
