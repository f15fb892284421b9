//! Kim-Karrila near-field lubrication between two unequal spheres (thesis eqs 3.8-3.18,
//! docs/physics.md section 4), regularised at the inner gap `xi_min` and cut off at
//! `xi_max`, sharply (the seeds' model) or over a smooth taper beyond it (Brownian scenes,
//! docs/physics.md section 11).
use crate::forces::pair_load::PairLoad;
use crate::state::Vec3;
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
    /// Outer cut-off of the dimensionless gap: the Kim-Karrila functions hold up to it.
    pub xi_max: f64,
    /// Width of the taper beyond `xi_max` over which the resistance falls smoothly to zero
    /// (0: the seeds' sharp cut at `xi_max`).
    pub xi_taper: f64,
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
            xi_taper: 0.0,
        }
    }

    /// The same pair with the resistance tapered to zero over `width` beyond `xi_max`
    /// (see [`Self::taper`]).
    pub fn with_taper(self, width: f64) -> Self {
        Self {
            xi_taper: width,
            ..self
        }
    }

    /// The gap at which the resistance vanishes: `xi_max + xi_taper`.
    pub fn xi_end(&self) -> f64 {
        self.xi_max + self.xi_taper
    }

    /// The factor on every resistance function at gap `xi`: 1 up to `xi_max`, then the
    /// smooth step `1 - 3 t^2 + 2 t^3` of `t = (xi - xi_max) / xi_taper`, 0 from `xi_end`:
    /// continuous with a continuous slope at both ends, so that the mobility of a pair
    /// has no jump at the cut-off (docs/physics.md section 11). A common factor keeps
    /// every pair block positive semi-definite and its rank-two tangential structure.
    #[inline]
    pub fn taper(&self, xi: f64) -> f64 {
        if xi <= self.xi_max {
            1.0
        } else if xi >= self.xi_end() {
            0.0
        } else {
            let t = (xi - self.xi_max) / self.xi_taper;
            1.0 - t * t * (3.0 - 2.0 * t)
        }
    }

    /// Squeeze resistance `X11A(xi)` (3.8), with `xi` clamped below at `xi_min`.
    pub fn x11a(&self, xi: f64) -> f64 {
        let xi = xi.max(self.xi_min);
        self.xa_singular / xi + self.xa_log * (1.0 / xi).ln()
    }

    /// The pair's resistance functions at dimensionless gap `xi` (values below `xi_min`,
    /// including overlaps, use `xi_min`), or `None` at or beyond `xi_end`: the squeeze term
    /// (3.8) and the log terms `Y11A`, `Y11B`, `Y21B`, `Y11C`, `Y12C`, `Y22C`, times the
    /// [`Self::taper`] beyond `xi_max`.
    #[inline]
    pub fn resistance(&self, xi: f64) -> Option<PairResistance> {
        if xi >= self.xi_end() {
            return None;
        }
        let s = self.taper(xi);
        let xi = xi.max(self.xi_min);
        let inv_xi = 1.0 / xi;
        let log = s * inv_xi.ln();
        Some(PairResistance {
            x11a: s * self.xa_singular * inv_xi + self.xa_log * log,
            y11a: self.ya * log,
            y11b: self.yb11 * log,
            y21b: self.yb21 * log,
            y11c: self.yc11 * log,
            y12c: self.yc12 * log,
            y22c: self.yc22 * log,
        })
    }

    /// Lubrication load at gap `xi` (see [`PairResistance::load`]); zero at or beyond
    /// `xi_end`.
    #[inline]
    pub fn load(&self, xi: f64, n: &Vec3, dv: &Vec3, omega_i: &Vec3, omega_j: &Vec3) -> PairLoad {
        self.resistance(xi)
            .map_or_else(PairLoad::default, |r| r.load(n, dv, omega_i, omega_j))
    }
}

/// The resistance functions of one pair at its current gap (units eta a, eta a^2, eta a^3):
/// the linear map from the pair's relative motion to its lubrication load (3.13, 3.14).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairResistance {
    pub x11a: f64,
    pub y11a: f64,
    pub y11b: f64,
    pub y21b: f64,
    pub y11c: f64,
    pub y12c: f64,
    pub y22c: f64,
}

impl PairResistance {
    /// Lubrication load for unit vector `n` from i to j, relative velocity `dv = v_j - v_i`
    /// and spins `omega_i`, `omega_j`:
    /// force on i `(X11A N + Y11A T) dv + Y11B (omega_i x n) + Y21B (omega_j x n)`,
    /// torque on i `Y11B dv x n - T (Y11C omega_i + Y12C omega_j)` (3.13),
    /// torque on j `Y21B dv x n - T (Y21C omega_i + Y22C omega_j)` (3.14).
    /// Linear in the motion: the load is `-R` times it, `R` symmetric positive
    /// semi-definite (docs/physics.md section 4).
    #[inline]
    pub fn load(&self, n: &Vec3, dv: &Vec3, omega_i: &Vec3, omega_j: &Vec3) -> PairLoad {
        let dv_n = n.dot(dv);
        let dv_t = dv - n * dv_n;
        let force_i = n * (self.x11a * dv_n)
            + dv_t * self.y11a
            + omega_i.cross(n) * self.y11b
            + omega_j.cross(n) * self.y21b;
        let dv_x_n = dv.cross(n);
        let tangential = |w: Vec3| w - n * n.dot(&w);
        let torque_i = dv_x_n * self.y11b - tangential(omega_i * self.y11c + omega_j * self.y12c);
        let torque_j = dv_x_n * self.y21b - tangential(omega_i * self.y12c + omega_j * self.y22c);
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
