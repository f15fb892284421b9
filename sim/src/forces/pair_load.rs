//! What one pair interaction puts on its two particles.
use crate::state::Vec3;
use nalgebra::Matrix3;

/// Force and torques of one pair law. The force on j is `-force_i` (equal and opposite,
/// docs/physics.md section 9); torques are not opposite in general (lubrication 3.13, 3.14).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairLoad {
    /// Force on particle i from particle j (units eta a^2 / time, or k_n a).
    pub force_i: Vec3,
    /// Torque on particle i.
    pub torque_i: Vec3,
    /// Torque on particle j.
    pub torque_j: Vec3,
}

impl PairLoad {
    /// Sum of two loads on the same pair.
    pub fn add(&mut self, other: &PairLoad) {
        self.force_i += other.force_i;
        self.torque_i += other.torque_i;
        self.torque_j += other.torque_j;
    }

    /// Pair stresslet `S = -F_ij (x) r_ij` (docs/physics.md section 4), with `F_ij` the force on i
    /// from j and `r_ij = x_j - x_i`: `S[(a, b)] = -F_a r_b`. Positive trace in
    /// compression (a repulsive contact gives `S = k delta |r| n n^T`).
    pub fn stresslet(&self, r_ij: &Vec3) -> Matrix3<f64> {
        -self.force_i * r_ij.transpose()
    }
}
