//! Kinetic temperatures of each species of a Brownian run over kT (docs/physics.md section
//! 11), in blocks of averaging snapshots: translation from the velocity relative to the
//! streaming flow, `m |v - u_inf(y) x|^2 / (3 kT)`, rotation from the spin relative to
//! the flow's, `I |omega - Omega_inf(y)|^2 / (3 kT)` with `Omega_inf = -u'(y)/2 z`. For a
//! suspension at rest or in homogeneous shear the streaming flow is the mean flow, and
//! each is 1 at equilibrium (equipartition); in an inhomogeneous flow the particles' slip
//! against `u_inf` adds to them.
use crate::integrate::simulation::Simulation;
use crate::sampling::block_sums::Estimate;
use crate::state::Vec3;
use serde::{Deserialize, Serialize};

/// One species' kinetic temperatures over kT, with standard errors from the blocks.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpeciesTemperature {
    /// The species' radius (units a).
    pub radius: f64,
    pub translation: Estimate,
    pub rotation: Estimate,
}

/// Sums of the temperatures per species and block, and the snapshots in each block.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SpeciesTemperatureSums {
    /// `sums[species][block] = [translation, rotation]`.
    sums: Vec<Vec<[f64; 2]>>,
    snapshots: Vec<u64>,
}

impl SpeciesTemperatureSums {
    /// Adds one snapshot of `sim` (thermal energy `kt`) to block `block` of `blocks`, for
    /// `species` species.
    pub fn add(
        &mut self,
        sim: &Simulation,
        kt: f64,
        block: usize,
        (species, blocks): (usize, usize),
    ) {
        if self.sums.is_empty() {
            self.sums = vec![vec![[0.0; 2]; blocks]; species];
        }
        // An extended run has more blocks than it started with.
        for s in &mut self.sums {
            s.resize(blocks.max(s.len()), [0.0; 2]);
        }
        self.snapshots.resize(blocks.max(self.snapshots.len()), 0);
        let p = &sim.particles;
        let mut energy = vec![[0.0; 2]; species];
        let mut count = vec![0usize; species];
        for i in 0..p.len() {
            let (u, slope) = sim.profile.u_and_slope(p.pos[i].y);
            let v = p.vel[i] - Vec3::new(u, 0.0, 0.0);
            let w = p.omega[i] - Vec3::new(0.0, 0.0, -0.5 * slope);
            let s = p.species[i] as usize;
            energy[s][0] += p.mass[i] * v.norm_squared();
            energy[s][1] += p.inertia(i) * w.norm_squared();
            count[s] += 1;
        }
        for s in 0..species {
            if count[s] > 0 {
                let dof = 3.0 * count[s] as f64 * kt;
                self.sums[s][block][0] += energy[s][0] / dof;
                self.sums[s][block][1] += energy[s][1] / dof;
            }
        }
        self.snapshots[block] += 1;
    }

    /// Mean and standard error (over the blocks) of each species' temperatures, for the
    /// species radii `radii`; empty when nothing was added.
    pub fn estimates(&self, radii: &[f64]) -> Vec<SpeciesTemperature> {
        let filled: Vec<usize> = (0..self.snapshots.len())
            .filter(|&b| self.snapshots[b] > 0)
            .collect();
        if filled.is_empty() {
            return Vec::new();
        }
        let estimate = |values: Vec<f64>| Estimate::of_blocks(&values);
        radii
            .iter()
            .zip(&self.sums)
            .map(|(&radius, sums)| {
                let per_block = |k: usize| {
                    filled
                        .iter()
                        .map(|&b| sums[b][k] / self.snapshots[b] as f64)
                        .collect()
                };
                SpeciesTemperature {
                    radius,
                    translation: estimate(per_block(0)),
                    rotation: estimate(per_block(1)),
                }
            })
            .collect()
    }
}
