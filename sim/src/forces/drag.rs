//! One-body Stokes drag towards the local streaming flow (thesis eqs 3.5, 3.6; docs/physics.md
//! sections 2 and 4) and the single-particle drag stresslet.
use crate::input::flow_profile::FlowProfile;
use crate::state::Vec3;
use std::f64::consts::PI;

/// Drag force and torque (3.5, 3.6) on a sphere of radius `a` at height `y` moving at
/// `(v, omega)` through the streaming flow `profile`. At rest (`v = omega = 0`) this is the
/// inflow term `D V_inf` of the implicit step (docs/physics.md section 5).
#[inline]
pub fn loads(
    eta: f64,
    a: f64,
    profile: &FlowProfile,
    y: f64,
    (v, omega): (&Vec3, &Vec3),
) -> (Vec3, Vec3) {
    let (u, du_dy) = profile.u_and_slope(y);
    (force(eta, a, u, v), torque(eta, a, du_dy, omega))
}

/// Translational drag `F = 6 pi eta a (U_inf(y) - v)` with `U_inf = (u(y), 0, 0)` (3.5).
#[inline]
pub fn force(eta: f64, a: f64, u_inf: f64, v: &Vec3) -> Vec3 {
    let c = translational_resistance(eta, a);
    Vec3::new(c * (u_inf - v.x), -c * v.y, -c * v.z)
}

/// Rotational drag `T = 8 pi eta a^3 (Omega_inf(y) - Omega)` with
/// `Omega_inf = (0, 0, -u'(y)/2)` (3.6).
#[inline]
pub fn torque(eta: f64, a: f64, du_dy: f64, omega: &Vec3) -> Vec3 {
    let c = rotational_resistance(eta, a);
    Vec3::new(-c * omega.x, -c * omega.y, c * (-0.5 * du_dy - omega.z))
}

/// xy component of the single-particle drag stresslet, `(20/3) pi eta a^3 E_xy` with
/// `E_xy = u'(y)/2` (docs/physics.md section 4), returned with the sign of the positive-in-compression
/// convention used for all stresses here (`sigma = -Cauchy stress`): `-(10/3) pi eta a^3 u'`.
#[inline]
pub fn stresslet_xy(eta: f64, a: f64, du_dy: f64) -> f64 {
    -(20.0 / 3.0) * PI * eta * a * a * a * 0.5 * du_dy
}

/// Drag relaxation time `m / (6 pi eta a)` of a sphere of mass `m` and radius `a`.
pub fn relaxation_time(mass: f64, eta: f64, a: f64) -> f64 {
    mass / translational_resistance(eta, a)
}

/// Translational drag resistance `6 pi eta a`: the drag force is this times
/// `U_inf - v` (3.5).
pub fn translational_resistance(eta: f64, a: f64) -> f64 {
    6.0 * PI * eta * a
}

/// Rotational drag resistance `8 pi eta a^3` (3.6).
pub fn rotational_resistance(eta: f64, a: f64) -> f64 {
    8.0 * PI * eta * a * a * a
}
