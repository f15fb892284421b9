//! Kim-Karrila near-field lubrication between two unequal spheres (thesis eqs 3.8-3.18,
//! docs/physics.md section 4), regularised at the inner gap `xi_min` and cut off at `xi_max`.
use crate::forces::pair_load::PairLoad;
use crate::Vec3;
use std::f64::consts::PI;

/// Gap-independent prefactors of the resistance functions for one ordered pair of radii
/// `(a_i, a_j)`, `beta = a_j / a_i`, `b = 1 / beta`. Multiply by `1/xi` (squeeze) or by
/// `L = ln(1/xi)` (log terms) to get the resistances (units: eta a, eta a^2, eta a^3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LubricationCoefficients {
    /// `6 pi eta a_i 2 beta^2 / (1+beta)^3`, the `1/xi` part of X11A (3.8).
    pub xa_singular: f64,
    /// `6 pi eta a_i beta (1 + 7 beta + beta^2) / (5 (1+beta)^3)`, the log part of X11A.
    pub xa_log: f64,
    /// `6 pi eta a_i 4 beta (2 + beta + 2 beta^2) / (15 (1+beta)^3)`, Y11A / L.
    pub ya: f64,
    /// `-4 pi eta a_i^2 beta (4 + beta) / (5 (1+beta)^2)`, Y11B / L.
    pub yb11: f64,
    /// `-4 pi eta a_j^2 b (4 + b) / (5 (1+b)^2)`, Y21B / L.
    pub yb21: f64,
    /// `8 pi eta a_i^3 2 beta / (5 (1+beta))`, Y11C / L.
    pub yc11: f64,
    /// `8 pi eta a_i^3 beta^2 / (10 (1+beta))`, Y12C / L (equal to Y21C / L).
    pub yc12: f64,
    /// `8 pi eta a_j^3 2 b / (5 (1+b))`, Y22C / L.
    pub yc22: f64,
    /// Inner regularisation of the dimensionless gap.
    pub xi_min: f64,
    /// Outer cut-off of the dimensionless gap.
    pub xi_max: f64,
}

impl LubricationCoefficients {
    /// Prefactors for radii `a_i`, `a_j` (units of a) in a fluid of viscosity `eta`.
    pub fn new(a_i: f64, a_j: f64, eta: f64, xi_min: f64, xi_max: f64) -> Self {
        let beta = a_j / a_i;
        let b = 1.0 / beta;
        let (bp1, invp1) = (1.0 + beta, 1.0 + b);
        let six = 6.0 * PI * eta * a_i;
        Self {
            xa_singular: six * 2.0 * beta * beta / bp1.powi(3),
            xa_log: six * beta * (1.0 + 7.0 * beta + beta * beta) / (5.0 * bp1.powi(3)),
            ya: six * 4.0 * beta * (2.0 + beta + 2.0 * beta * beta) / (15.0 * bp1.powi(3)),
            yb11: -4.0 * PI * eta * a_i * a_i * beta * (4.0 + beta) / (5.0 * bp1 * bp1),
            yb21: -4.0 * PI * eta * a_j * a_j * b * (4.0 + b) / (5.0 * invp1 * invp1),
            yc11: 8.0 * PI * eta * a_i.powi(3) * 2.0 * beta / (5.0 * bp1),
            yc12: 8.0 * PI * eta * a_i.powi(3) * beta * beta / (10.0 * bp1),
            yc22: 8.0 * PI * eta * a_j.powi(3) * 2.0 * b / (5.0 * invp1),
            xi_min,
            xi_max,
        }
    }

    /// Squeeze resistance `X11A(xi)` (3.8), with `xi` clamped below at `xi_min`.
    pub fn x11a(&self, xi: f64) -> f64 {
        let xi = xi.max(self.xi_min);
        self.xa_singular / xi + self.xa_log * (1.0 / xi).ln()
    }

    /// Lubrication load for a pair at dimensionless gap `xi` (any value below `xi_max`;
    /// values below `xi_min`, including overlaps, use `xi_min`), unit vector `n` from i to
    /// j, relative velocity `dv = v_j - v_i`, and spins `omega_i`, `omega_j`:
    /// force on i `(X11A N + Y11A T) dv + Y11B (omega_i x n) + Y21B (omega_j x n)`,
    /// torque on i `Y11B dv x n - T (Y11C omega_i + Y12C omega_j)` (3.13),
    /// torque on j `Y21B dv x n - T (Y21C omega_i + Y22C omega_j)` (3.14).
    /// Returns zero at or beyond `xi_max`.
    #[inline]
    pub fn load(&self, xi: f64, n: &Vec3, dv: &Vec3, omega_i: &Vec3, omega_j: &Vec3) -> PairLoad {
        if xi >= self.xi_max {
            return PairLoad::default();
        }
        let xi = xi.max(self.xi_min);
        let inv_xi = 1.0 / xi;
        let log = inv_xi.ln();
        let x11a = self.xa_singular * inv_xi + self.xa_log * log;
        let y11a = self.ya * log;
        let (y11b, y21b) = (self.yb11 * log, self.yb21 * log);
        let (y11c, y12c, y22c) = (self.yc11 * log, self.yc12 * log, self.yc22 * log);
        let dv_n = n.dot(dv);
        let dv_t = dv - n * dv_n;
        let force_i =
            n * (x11a * dv_n) + dv_t * y11a + omega_i.cross(n) * y11b + omega_j.cross(n) * y21b;
        let dv_x_n = dv.cross(n);
        let tangential = |w: Vec3| w - n * n.dot(&w);
        let torque_i = dv_x_n * y11b - tangential(omega_i * y11c + omega_j * y12c);
        let torque_j = dv_x_n * y21b - tangential(omega_i * y12c + omega_j * y22c);
        PairLoad {
            force_i,
            torque_i,
            torque_j,
        }
    }
}

/// Dimensionless gap `xi = 2 (|r| - (a_i + a_j)) / (a_i + a_j)` (docs/physics.md section 4).
#[inline]
pub fn gap(distance: f64, a_i: f64, a_j: f64) -> f64 {
    let sum = a_i + a_j;
    2.0 * (distance - sum) / sum
}
