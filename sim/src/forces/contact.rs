//! Linear-spring contact between overlapping spheres (thesis eqs 3.3, 3.4; docs/physics.md section 4).
use crate::forces::pair_load::PairLoad;
use crate::state::Vec3;

/// Contact law parameters: normal stiffness `k_n` (force per unit overlap, units eta a /
/// time in the default unit system), tangential stiffness `k_t = 2/7 k_n`, and the
/// Coulomb friction coefficient `mu_p` (0 = frictionless: no tangential spring at all).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    pub k_n: f64,
    pub k_t: f64,
    pub mu_p: f64,
}

/// A touching pair as the tangential law sees it: overlap `delta = a_i + a_j - |r|` (units
/// a), unit vector `n` from i to j, relative velocity `dv = v_j - v_i`, the spins of i and
/// j and their radii.
#[derive(Clone, Copy)]
pub struct ContactMotion<'a> {
    pub delta: f64,
    pub n: &'a Vec3,
    pub dv: &'a Vec3,
    pub omega: [&'a Vec3; 2],
    pub radius: [f64; 2],
}

impl ContactLaw {
    /// Contact law with `k_t = 2/7 k_n` (docs/physics.md section 1).
    pub fn new(k_n: f64, mu_p: f64) -> Self {
        Self {
            k_n,
            k_t: 2.0 / 7.0 * k_n,
            mu_p,
        }
    }

    /// Whether the law has a tangential part that needs per-pair history.
    pub fn frictional(&self) -> bool {
        self.mu_p > 0.0
    }

    /// Normal contact force on i for overlap `delta = a_i + a_j - |r| > 0` along the unit
    /// vector `n` from i to j: `F_i = -k_n delta n` (3.3), repulsive.
    #[inline]
    pub fn normal(&self, delta: f64, n: &Vec3) -> Vec3 {
        -self.k_n * delta * n
    }

    /// Frictional (tangential) part (3.4). `spring` is the accumulated tangential
    /// displacement of i relative to j (units a), updated in place: rotated into the
    /// current tangent plane, advanced by the relative surface velocity times `dt`, and
    /// shortened so that `k_t |spring| <= mu_p k_n delta` (sliding). Returns the
    /// tangential force `-k_t spring` on i and the torques `a_i n x F`, `a_j n x F`.
    pub fn tangential(&self, spring: &mut Vec3, contact: &ContactMotion, dt: f64) -> PairLoad {
        let ContactMotion {
            delta,
            n,
            dv,
            omega: [omega_i, omega_j],
            radius: [a_i, a_j],
        } = *contact;
        // Surface velocity of i's contact point relative to j's, with dv = v_j - v_i.
        let slip = -dv + (omega_i * a_i + omega_j * a_j).cross(n);
        let slip_t = slip - n * n.dot(&slip);
        let norm_before = spring.norm();
        *spring -= n * n.dot(spring);
        let norm_after = spring.norm();
        if norm_after > 0.0 {
            *spring *= norm_before / norm_after;
        }
        *spring += slip_t * dt;
        let cap = self.mu_p * self.k_n * delta / self.k_t;
        let len = spring.norm();
        if len > cap {
            *spring *= cap / len;
        }
        let force_i = -self.k_t * *spring;
        let nxf = n.cross(&force_i);
        PairLoad {
            force_i,
            torque_i: nxf * a_i,
            torque_j: nxf * a_j,
        }
    }
}
