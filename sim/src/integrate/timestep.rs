//! Automatic time step (docs/physics.md section 5). The explicit velocity-Verlet scheme is
//! limited by the contact spring, the one-body drag and the lubrication squeeze
//! resistance at `xi_min`; the implicit step only by the contact spring and by accuracy.
//! The step is a safety fraction of the tightest stability limit, capped by accuracy and,
//! with Brownian forces, by the thermal fraction and the velocity relaxation.
use crate::forces::drag;
use crate::forces::force_field::ForceField;
use crate::forces::repulsion::Repulsion;
use crate::input::integrator::Integrator;
use crate::input::scene_file::SceneFile;
use crate::input::thermal_scales::RELAXATION_STEP_LIMIT;
use crate::json_numbers::null_as_infinity;
use crate::state::particles::sphere_mass;
use serde::{Deserialize, Serialize};

/// Which stability limit set the time step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DtLimit {
    Contact,
    Drag,
    Lubrication,
    /// Strain per step capped at `xi_min` (implicit step).
    Accuracy,
    /// Brownian scenes, implicit step: a fraction of the contact limit that keeps the
    /// kinetic temperature within 2 % of kT (see [`THERMAL_FRACTION`]).
    Thermal,
    /// Brownian scenes, implicit step: [`RELAXATION_STEP_LIMIT`] velocity relaxation times
    /// of the smallest spheres, beyond which the stresses (sheared, and their fluctuations
    /// at rest) are biased.
    Relaxation,
    /// Set by the scene's `run.dt`.
    User,
}

/// The implicit Brownian step's cap as a fraction of the contact limit, chosen by the
/// pair-structure and equipartition tests of `sim/tests/brownian.rs` (thesis Table 4.1
/// units; docs/physics.md section 11). Two spheres' potential of mean force, 1 : 1:
/// at 0.075 of the contact limit the lubricated gaps hold 0.10 kT too much (a step at the
/// cut-off); at 0.0375 every shell is within 0.05 kT of the free level, for 1 : 1.4 too.
/// Kinetic temperature at phi 0.45: 0.974 kT at 0.3, 1.000 kT at 0.075 and below.
pub const THERMAL_FRACTION: f64 = 0.0375;

impl std::fmt::Display for DtLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            DtLimit::Contact => "contact",
            DtLimit::Drag => "drag",
            DtLimit::Lubrication => "lubrication",
            DtLimit::Accuracy => "accuracy",
            DtLimit::Thermal => "thermal",
            DtLimit::Relaxation => "relaxation",
            DtLimit::User => "user",
        };
        f.write_str(s)
    }
}

/// The critical steps of each term and the step chosen.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeStep {
    /// Chosen step.
    pub dt: f64,
    /// What set it.
    pub limit: DtLimit,
    /// Stability limit of the contact spring (infinite without contacts or repulsion), its
    /// stiffness `k_n` plus the repulsion's `A / kappa^2` at contact when that is on (see
    /// [`normal_stiffness`]). Explicit scheme: `2 sqrt(m_red / k_n)`, the undamped spring. Implicit step: the spring damped,
    /// implicitly, by the lubrication squeeze resistance `X = X11A(xi_min)` every
    /// overlapping pair carries, `(X + sqrt(X^2 + 4 k_n m_red)) / k_n` (see
    /// [`damped_spring_limit`]); the same with `k_t` and `Y11A(xi_min)` for friction.
    #[serde(deserialize_with = "null_as_infinity")]
    pub contact_critical: f64,
    /// `2 m / (6 pi eta a)`, explicit stability of the Stokes drag (infinite without drag).
    #[serde(deserialize_with = "null_as_infinity")]
    pub drag_critical: f64,
    /// `2 m_red / X11A(xi_min)`, explicit stability of the lubrication squeeze term.
    #[serde(deserialize_with = "null_as_infinity")]
    pub lubrication_critical: f64,
    /// `xi_min / gdot_max`, the implicit step's accuracy cap: the strain per step at most
    /// the inner lubrication gap.
    #[serde(deserialize_with = "null_as_infinity")]
    pub accuracy_limit: f64,
    /// The integrator the step was chosen for.
    pub integrator: Integrator,
}

/// Largest stable step of a spring `k` between masses of reduced mass `m_red` whose
/// damping `c` is integrated by backward Euler while the spring force is taken at the
/// drifted position: the step's amplification matrix has determinant
/// `m / (m + dt c) < 1` and trace `1 + (m - dt^2 k) / (m + dt c)`, stable while
/// `dt^2 k < 2 (2 m_red + dt c)`, i.e. `dt < (c + sqrt(c^2 + 4 k m_red)) / k`. Without
/// damping this is the explicit `2 sqrt(m_red / k)`. A network of such pairs has
/// stiffness and damping in the same proportion mode by mode, so the bound holds for it.
pub fn damped_spring_limit(m_red: f64, k: f64, c: f64) -> f64 {
    (c + (c * c + 4.0 * k * m_red).sqrt()) / k
}

/// Normal stiffness of a pair at contact that the contact stability limit uses: the
/// spring's `k_n` (when contacts are on) plus the repulsion's `A / kappa^2` at
/// `|r| = a_i + a_j` (when it is on; docs/physics.md section 11). Inside an overlap
/// `delta` the repulsion is stiffer, by `exp(delta / kappa)`. For the explicit step this
/// is the stiffest gap `h >= 0`; for the implicit one, whose lubrication damper weakens as
/// the gap opens, the worst gap's damped limit is 0.21-1.0 of this one's, above the
/// Brownian step's [`THERMAL_FRACTION`] of it. Zero when neither is on.
pub fn normal_stiffness(k_n: Option<f64>, repulsion: Option<Repulsion>) -> f64 {
    let spring = k_n.unwrap_or(0.0);
    match repulsion {
        Some(r) => spring + r.contact_stiffness(),
        None => spring,
    }
}

impl TimeStep {
    /// Critical steps over every species pair, and the step the scene asks for: `run.dt`
    /// if given, else `dt_safety * dt_factor` times the tightest stability limit of the
    /// scene's integrator (explicit: contact, drag, lubrication; implicit: contact), the
    /// implicit one capped by `dt_factor * accuracy_limit` and, with Brownian forces, by
    /// `dt_factor` times [`THERMAL_FRACTION`] of the contact limit and by `dt_factor` times
    /// [`RELAXATION_STEP_LIMIT`] times the smallest spheres' velocity relaxation time
    /// `m / (6 pi eta a)`.
    pub fn choose(file: &SceneFile, rho: f64, gdot_max: f64, field: &ForceField) -> TimeStep {
        let eta = file.fluid.eta;
        let radii = &file.particles.radii;
        let mass = |a: f64| sphere_mass(rho, a);
        let (mut contact, mut drag, mut lub) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        for (s_i, &a_i) in radii.iter().enumerate() {
            if field.drag {
                drag = drag.min(2.0 * drag::relaxation_time(mass(a_i), eta, a_i));
            }
            for (s_j, &a_j) in radii.iter().enumerate() {
                let m_red = mass(a_i) * mass(a_j) / (mass(a_i) + mass(a_j));
                let constants = field.constants(s_i as u16, s_j as u16);
                let lubrication = &constants.lubrication;
                let (mut normal, mut tangential) = (0.0, 0.0);
                if let (Integrator::Implicit, Some(l)) = (file.run.integrator, lubrication) {
                    let r = l.resistance(l.xi_min).unwrap_or_default();
                    (normal, tangential) = (r.x11a, r.y11a);
                }
                let k_normal = normal_stiffness(field.contact.map(|c| c.k_n), constants.repulsion);
                if k_normal > 0.0 {
                    contact = contact.min(damped_spring_limit(m_red, k_normal, normal));
                }
                if let Some(c) = field.contact.filter(|c| c.frictional()) {
                    contact = contact.min(damped_spring_limit(m_red, c.k_t, tangential));
                }
                if let Some(l) = lubrication {
                    lub = lub.min(2.0 * m_red / l.x11a(l.xi_min));
                }
            }
        }
        let run = &file.run;
        let (mut dt, mut limit) = (contact, DtLimit::Contact);
        let accuracy = file.forces.xi_min / gdot_max;
        if run.integrator == Integrator::Explicit {
            if drag < dt {
                (dt, limit) = (drag, DtLimit::Drag);
            }
            if lub < dt {
                (dt, limit) = (lub, DtLimit::Lubrication);
            }
        }
        dt *= run.dt_safety * run.dt_factor;
        if run.integrator == Integrator::Implicit && accuracy * run.dt_factor < dt {
            (dt, limit) = (accuracy * run.dt_factor, DtLimit::Accuracy);
        }
        let brownian = run.integrator == Integrator::Implicit && file.fluid.kt > 0.0;
        let thermal = THERMAL_FRACTION * contact * run.dt_factor;
        if brownian && thermal < dt {
            (dt, limit) = (thermal, DtLimit::Thermal);
        }
        let relaxed = RELAXATION_STEP_LIMIT * Self::relaxation_time(file, rho) * run.dt_factor;
        if brownian && relaxed < dt {
            (dt, limit) = (relaxed, DtLimit::Relaxation);
        }
        if let Some(user) = run.dt {
            (dt, limit) = (user, DtLimit::User);
        }
        TimeStep {
            dt,
            limit,
            contact_critical: contact,
            drag_critical: drag,
            lubrication_critical: lub,
            accuracy_limit: accuracy,
            integrator: run.integrator,
        }
    }

    /// Velocity relaxation time `m / (6 pi eta a)` of the scene's smallest spheres at
    /// particle density `rho`: the unit of the Brownian cap ([`DtLimit::Relaxation`]) and of
    /// its warning.
    pub fn relaxation_time(file: &SceneFile, rho: f64) -> f64 {
        file.particles
            .radii
            .iter()
            .map(|&a| drag::relaxation_time(sphere_mass(rho, a), file.fluid.eta, a))
            .fold(f64::INFINITY, f64::min)
    }
}
