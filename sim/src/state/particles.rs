//! Particle state as contiguous arrays (structure of arrays).
use crate::state::Vec3;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Volume `4/3 pi a^3` of a sphere of radius `a`.
#[inline]
pub fn sphere_volume(a: f64) -> f64 {
    4.0 / 3.0 * PI * a.powi(3)
}

/// Mass `4/3 pi rho a^3` of a sphere of density `rho` and radius `a` (eq 3.1).
#[inline]
pub fn sphere_mass(rho: f64, a: f64) -> f64 {
    4.0 / 3.0 * PI * rho * a.powi(3)
}

/// Moment of inertia `(2/5) m a^2` of a solid sphere (eq 3.2).
#[inline]
pub fn sphere_inertia(mass: f64, radius: f64) -> f64 {
    0.4 * mass * radius * radius
}

/// Positions, velocities, spins and accumulated loads of every particle, plus the
/// per-particle constants the integrator needs.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Particles {
    /// Centre positions inside the box (units a).
    pub pos: Vec<Vec3>,
    /// Translational velocities.
    pub vel: Vec<Vec3>,
    /// Angular velocities.
    pub omega: Vec<Vec3>,
    /// Total force on each particle at the current positions.
    pub force: Vec<Vec3>,
    /// Total torque on each particle.
    pub torque: Vec<Vec3>,
    /// Radius of each particle.
    pub radius: Vec<f64>,
    /// Species index (into the scene's radii) of each particle.
    pub species: Vec<u16>,
    /// Mass `4/3 pi rho a^3` (eq 3.1).
    pub mass: Vec<f64>,
    /// Identity of each particle (its index in the initial configuration): the arrays
    /// are re-sorted in space for memory locality, identities stay.
    pub id: Vec<u32>,
}

impl Particles {
    /// Particles at rest at `pos` with radii and species given, density `rho`.
    pub fn at_rest(pos: Vec<Vec3>, radius: Vec<f64>, species: Vec<u16>, rho: f64) -> Self {
        let n = pos.len();
        let mass = radius.iter().map(|&a| sphere_mass(rho, a)).collect();
        Self {
            pos,
            vel: vec![Vec3::zeros(); n],
            omega: vec![Vec3::zeros(); n],
            force: vec![Vec3::zeros(); n],
            torque: vec![Vec3::zeros(); n],
            radius,
            species,
            mass,
            id: (0..n as u32).collect(),
        }
    }

    /// Reorders every per-particle array: new index k holds old particle `order[k]`.
    pub fn permute(&mut self, order: &[u32]) {
        fn apply<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
            *v = order.iter().map(|&o| v[o as usize]).collect();
        }
        apply(&mut self.pos, order);
        apply(&mut self.vel, order);
        apply(&mut self.omega, order);
        apply(&mut self.force, order);
        apply(&mut self.torque, order);
        apply(&mut self.radius, order);
        apply(&mut self.species, order);
        apply(&mut self.mass, order);
        apply(&mut self.id, order);
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Moment of inertia `(2/5) m a^2` of particle i (eq 3.2).
    #[inline]
    pub fn inertia(&self, i: usize) -> f64 {
        sphere_inertia(self.mass[i], self.radius[i])
    }

    /// Total kinetic energy, translational plus rotational.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.len())
            .map(|i| {
                0.5 * self.mass[i] * self.vel[i].norm_squared()
                    + 0.5 * self.inertia(i) * self.omega[i].norm_squared()
            })
            .sum()
    }

    /// Translational and rotational kinetic temperatures over `kt`:
    /// `sum m v^2 / (3 N kT)` and `sum I omega^2 / (3 N kT)` (1 is equipartition).
    pub fn kinetic_temperatures(&self, kt: f64) -> (f64, f64) {
        self.kinetic_temperatures_of(kt, |_| true)
    }

    /// [`Self::kinetic_temperatures`] of the particles whose radius `selected` accepts
    /// (one species of a mixture); `(NaN, NaN)` when it accepts none.
    pub fn kinetic_temperatures_of(&self, kt: f64, selected: impl Fn(f64) -> bool) -> (f64, f64) {
        let (mut trans, mut rot, mut n) = (0.0, 0.0, 0usize);
        for i in (0..self.len()).filter(|&i| selected(self.radius[i])) {
            trans += self.mass[i] * self.vel[i].norm_squared();
            rot += self.inertia(i) * self.omega[i].norm_squared();
            n += 1;
        }
        let dof = 3.0 * n as f64 * kt;
        (trans / dof, rot / dof)
    }

    /// Total solid volume.
    pub fn solid_volume(&self) -> f64 {
        self.radius.iter().map(|&a| sphere_volume(a)).sum()
    }
}
