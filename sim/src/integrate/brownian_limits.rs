//! The limits a Brownian scene puts on its (midpoint, implicit) step, each in a time scale
//! of the thermal motion and each with its own reason and safety fraction, chosen by the
//! equilibrium and convergence measurements of docs/physics.md section 11 in two unit
//! systems (thesis Table 4.1's and the shipped grids'):
//!
//! - **diffusion**: a pair's relative Brownian displacement in one step, `sqrt(2 D_rel dt)`
//!   with `D_rel = kT / (6 pi eta a_i) + kT / (6 pi eta a_j)`, at most
//!   `sqrt(DIFFUSION_FRACTION)` of the gap width over which the pair's lubrication switches
//!   off (the taper `xi_taper (a_i + a_j) / 2`): the midpoint step gives the drift
//!   `kT div R^-1` only where the mobility varies little over a step. Without lubrication
//!   the repulsion's Debye length takes the taper's place (at rest, A / kT = 100: the pair
//!   structure within 0.07 kT and the repulsion pressure within 3.3 % of a third of the
//!   step, `sim/tests/repulsion_equilibrium.rs`); with lubrication the
//!   Debye length is not needed (a conservative force, which the contact limit bounds: at
//!   A / kT = 100, 6.25x its step sampled the same structure at rest and eta_r within 2 %
//!   at Pe 1, docs/physics.md section 11). It scales as `1 / kT`, so it vanishes from the
//!   rule as `kT -> 0`.
//! - **relaxation**: `RELAXATION_FRACTION` of the velocity relaxation times, translational
//!   `m / (6 pi eta a)` and rotational `I / (8 pi eta a^3)`, of every species.
//! - **cut-off relaxation**, only with the seeds' sharp cut (`xi_taper = 0`): the squeeze
//!   mode of a pair at `xi_max` relaxes at `lambda = X11A(xi_max) / m_red + 6 pi eta a / m`;
//!   a step `CUTOFF_FRACTION / lambda` resolves it, and only a resolved step crosses the jump
//!   of the mobility there without a spurious drift.
//!
//! Each bounds an artefact of the thermal motion whose size is set by kT (measured at rest:
//! at most a few `n kT` of lubrication pressure, half a kT in the pair structure; sheared,
//! it grows with the step beyond a relaxation time). In homogeneous shear at Peclet number
//! `Pe = 6 pi eta a^3 gdot / kT` (`a` the smallest radius) the stresses are about `Pe`
//! times the thermal scale (`sigma_xy / (n kT) = eta_r Pe / (4.5 phi)`, 300 at phi 0.45,
//! eta_r 6, Pe 100), so the limits are relaxed by `max(1, Pe / PECLET_ONSET)`
//! ([`peclet_allowance`], [`PECLET_ONSET`]): the artefacts then stay a bounded share of
//! the stress. From [`RELAXATION_PECLET_END`] on the relaxation limit is dropped: the
//! step is then that of the same scene without kT wherever the diffusion limit allows it.
//! Where the flow has a profile the local Peclet number falls to zero at the
//! velocity extrema, and nothing is relaxed.
use crate::forces::drag;
use crate::forces::force_field::ForceField;
use crate::state::particles::{sphere_inertia, sphere_mass};

/// Largest squared relative displacement per step over the squared taper width (or, without
/// lubrication, the repulsion's Debye length). At rest in the shipped grids' units (phi
/// 0.45, taper 0.05, rho 0.5): at a ratio of 0.057 the pair structure is smooth across the
/// taper, the temperatures within 0.3 % of kT and the lubrication pressure zero within its
/// error; at 0.17 the lubrication pressure is 0.8 n kT and the translational temperature
/// 0.8 % hot.
pub const DIFFUSION_FRACTION: f64 = 0.05;

/// Largest step over the velocity relaxation times (translation and rotation). Sheared at
/// Pe = 1 (rho = 0.05, phi 0.45 and 0.50), at 3.2 translational relaxation times eta_r was
/// 15-25 % high and at 0.32 converged within 5-10 % (reports/brownian/README.md). Where it
/// binds unrelaxed (rho 0.1, Pe 1, three seeds), twice this fraction (0.35, the rule until
/// code c301e63) missed at phi 0.45: against a ninth of it eta_r -6.5 +- 6.1 %, the contact
/// part -9.4 +- 8.3 %, the structural Brownian stress -5.1 +- 3.0 %; this fraction reads
/// eta_r +0.6 +- 5.0 % and every part within 4.2 % there, and at phi 0.55 every part within
/// 1.3 % of a third of the old step; relaxed at Pe 4.6 (rho 0.5, phi 0.45) it brings the
/// hydrodynamic part from +6.4 +- 2.9 % to +2.7 +- 2.7 % (docs/physics.md section 11).
pub const RELAXATION_FRACTION: f64 = 0.175;

/// Largest step times the relaxation rate of a pair's squeeze mode at a sharp lubrication
/// cut-off. At rest (phi 0.45, rho 0.5 and 0.05) the jump of `-ln g` across the cut-off
/// follows `lambda dt`: 0.27 kT at 3.9, 0.14-0.17 at 1.2-1.3, 0.04 at 0.39.
pub const CUTOFF_FRACTION: f64 = 0.3;

/// The Brownian limits of a scene (each infinite where it does not apply).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrownianLimits {
    pub diffusion: f64,
    pub relaxation: f64,
    pub cutoff: f64,
}

/// The Peclet number from which the Brownian limits of a homogeneous shear grow with `Pe`.
/// Sheared at Pe 4.6, phi 0.55 (shipped units, two and three seeds): steps of 3 and 1.6
/// rotational relaxation times put the hydrodynamic part of eta_r 15.7 +- 1.8 and 9.7 +-
/// 1.3 % above a ninth of the latter; 0.54 relaxation times (this onset with a
/// `RELAXATION_FRACTION` of 0.35) 1.1 +- 1.3 %. At Pe 100, 3 relaxation times agreed with 1
/// within 0.5 +- 0.7 %: at a fixed step the error falls about as `1 / Pe`. At phi 0.45 and
/// Pe 4.6 the hydrodynamic part read 6.4 +- 2.9 % above the shortest step at 0.54
/// relaxation times and +2.7 +- 2.7 % at 0.27, the step this onset gives with today's
/// fraction (docs/physics.md section 11).
pub const PECLET_ONSET: f64 = 3.0;

/// The Peclet number of a homogeneous shear from which the velocity relaxation limit no
/// longer bounds the step. At Pe 100 in the lightest shipped units (rho 0.05, Stokes number
/// 5e-4, phi 0.45 and 0.55), 30 rotational relaxation times (0.1, the step without kT)
/// agree with 10 (docs/physics.md section 11, `grids/brownian_relaxation_pe100.toml`).
pub const RELAXATION_PECLET_END: f64 = 100.0;

/// The factor `max(1, Pe / PECLET_ONSET)` on the Brownian limits of a homogeneous shear at
/// Peclet number `peclet` (`None`: at rest or a flow with a profile, factor 1).
pub fn peclet_allowance(peclet: Option<f64>) -> f64 {
    peclet.map_or(1.0, |pe| (pe / PECLET_ONSET).max(1.0))
}

impl BrownianLimits {
    /// The limits of the species `radii` with `counts` particles each (absent species are
    /// left out) at particle density `rho` in the force field `field` (its thermal energy
    /// `field.kt > 0`), for a homogeneous shear at Peclet number `peclet` (see
    /// [`peclet_allowance`]), before any `run.dt_factor`.
    pub fn of(
        radii: &[f64],
        counts: &[usize],
        rho: f64,
        field: &ForceField,
        peclet: Option<f64>,
    ) -> Self {
        let (eta, kt) = (field.eta, field.kt);
        let mut limits = BrownianLimits {
            diffusion: f64::INFINITY,
            relaxation: f64::INFINITY,
            cutoff: f64::INFINITY,
        };
        let present = |s: usize| counts.get(s).is_none_or(|&n| n > 0);
        for (s_i, &a_i) in radii.iter().enumerate().filter(|(s, _)| present(*s)) {
            let m_i = sphere_mass(rho, a_i);
            if field.drag {
                let rotation = sphere_inertia(m_i, a_i) / drag::rotational_resistance(eta, a_i);
                let translation = drag::relaxation_time(m_i, eta, a_i);
                limits.relaxation = limits
                    .relaxation
                    .min(RELAXATION_FRACTION * translation.min(rotation));
            }
            for (s_j, &a_j) in radii.iter().enumerate().filter(|(s, _)| present(*s)) {
                let c = field.constants(s_i as u16, s_j as u16);
                let mobility = 1.0 / drag::translational_resistance(eta, a_i)
                    + 1.0 / drag::translational_resistance(eta, a_j);
                let d_rel = kt * mobility;
                let mut width = f64::INFINITY;
                if let Some(l) = &c.lubrication {
                    width = width.min(l.xi_taper * 0.5 * (a_i + a_j));
                    if l.xi_taper == 0.0 {
                        let m_j = sphere_mass(rho, a_j);
                        let m_red = m_i * m_j / (m_i + m_j);
                        let one_body = if field.drag {
                            1.0 / drag::relaxation_time(m_i, eta, a_i)
                        } else {
                            0.0
                        };
                        let rate = l.x11a(l.xi_max) / m_red + one_body;
                        limits.cutoff = limits.cutoff.min(CUTOFF_FRACTION / rate);
                    }
                }
                if let (None, Some(r)) = (&c.lubrication, &c.repulsion) {
                    width = r.kappa;
                }
                if width > 0.0 && width.is_finite() {
                    let dt = DIFFUSION_FRACTION * width * width / (2.0 * d_rel);
                    limits.diffusion = limits.diffusion.min(dt);
                }
            }
        }
        let allowance = peclet_allowance(peclet);
        let relaxation = if peclet.is_some_and(|pe| pe >= RELAXATION_PECLET_END) {
            f64::INFINITY
        } else {
            limits.relaxation * allowance
        };
        BrownianLimits {
            diffusion: limits.diffusion * allowance,
            relaxation,
            cutoff: limits.cutoff * allowance,
        }
    }
}
