//! Automatic time step (docs/physics.md sections 5 and 11). The explicit velocity-Verlet
//! scheme is limited by the contact spring, the one-body drag and the lubrication squeeze
//! resistance at `xi_min`; the implicit step by the contact spring, the tangential
//! (friction) spring and accuracy. Each is a safety fraction of its stability limit; a
//! Brownian scene's implicit step is further capped by the time scales of the thermal
//! motion ([`BrownianLimits`]).
use crate::forces::drag;
use crate::forces::force_field::ForceField;
use crate::forces::lubrication::LubricationCoefficients;
use crate::forces::repulsion::{Repulsion, CUTOFF_KAPPAS};
use crate::input::integrator::Integrator;
use crate::input::scene_file::SceneFile;
use crate::input::thermal_scales::peclet_number;
use crate::integrate::brownian_limits::BrownianLimits;
use crate::json_numbers::null_as_infinity;
use crate::state::particles::sphere_mass;
use serde::{Deserialize, Serialize};

/// Which limit set the time step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DtLimit {
    /// The normal contact spring (with the repulsion's stiffness when it is on).
    Contact,
    /// The tangential contact spring of a frictional scene.
    Friction,
    Drag,
    Lubrication,
    /// Strain per step capped at `xi_min` (implicit step).
    Accuracy,
    /// Brownian scenes: a pair's relative diffusion per step against the gap width its
    /// forces vary over ([`BrownianLimits::diffusion`]).
    Diffusion,
    /// Brownian scenes: the velocity relaxation times ([`BrownianLimits::relaxation`]).
    Relaxation,
    /// Brownian scenes with a sharp lubrication cut-off: the squeeze relaxation of a pair
    /// at the cut-off ([`BrownianLimits::cutoff`]).
    Cutoff,
    /// The Brownian cap of code d2f2153 and before (a fixed fraction of the contact limit),
    /// read from their summaries; never chosen now.
    Thermal,
    /// Set by the scene's `run.dt`.
    User,
}

impl std::fmt::Display for DtLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            DtLimit::Contact => "contact",
            DtLimit::Friction => "friction",
            DtLimit::Drag => "drag",
            DtLimit::Lubrication => "lubrication",
            DtLimit::Accuracy => "accuracy",
            DtLimit::Diffusion => "diffusion",
            DtLimit::Relaxation => "relaxation",
            DtLimit::Cutoff => "cutoff",
            DtLimit::Thermal => "thermal",
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
    /// Stability limit of the tangential contact spring on the sliding mode's mass
    /// `m_t = TANGENTIAL_MASS_SHARE m_red` (rotation included), `damped_spring_limit(m_t, k_t,
    /// Y11A(xi_min))` (implicit) or `2 sqrt(m_t / k_t)` (explicit); infinite without
    /// friction. Part of `contact_critical` in summaries before it was split out.
    #[serde(default = "infinite", deserialize_with = "null_as_infinity")]
    pub friction_critical: f64,
    /// The Brownian limits of an implicit Brownian scene (each infinite where it does not
    /// apply; all infinite otherwise), before `run.dt_factor`.
    #[serde(default = "infinite", deserialize_with = "null_as_infinity")]
    pub diffusion_limit: f64,
    #[serde(default = "infinite", deserialize_with = "null_as_infinity")]
    pub relaxation_limit: f64,
    #[serde(default = "infinite", deserialize_with = "null_as_infinity")]
    pub cutoff_limit: f64,
    /// The integrator the step was chosen for.
    pub integrator: Integrator,
}

/// The effective mass of a touching pair's tangential (sliding) mode as a share of its
/// reduced mass `m_red`: a tangential force `F` on i (and `-F` on j), with its torques
/// `a n x F` on both, changes the contact points' relative sliding velocity at the rate
/// `F (1/m_i + 1/m_j + a_i^2/I_i + a_j^2/I_j)`, which with `I = 2/5 m a^2` is
/// `7/2 F / m_red`: the spring `k_t` oscillates at `sqrt(7 k_t / (2 m_red))`, not
/// `sqrt(k_t / m_red)`. Without the rotation the friction limit was 1.87x too long: dense
/// frictional grains sheared at 0.3 of it lost half their viscosity with kT (two seeds) and
/// about a fifth without (one seed; docs/physics.md section 11).
pub const TANGENTIAL_MASS_SHARE: f64 = 2.0 / 7.0;

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

fn infinite() -> f64 {
    f64::INFINITY
}

/// Normal stiffness of a pair at contact: the spring's `k_n` (when contacts are on) plus
/// the repulsion's `A / kappa^2` at `|r| = a_i + a_j` (when it is on; docs/physics.md
/// section 11). Zero when neither is on.
pub fn normal_stiffness(k_n: Option<f64>, repulsion: Option<Repulsion>) -> f64 {
    let spring = k_n.unwrap_or(0.0);
    match repulsion {
        Some(r) => spring + r.contact_stiffness(),
        None => spring,
    }
}

/// Gaps at which [`repulsion_limit`] evaluates the damped spring, per Debye length.
const REPULSION_GAPS_PER_KAPPA: usize = 20;

/// The implicit step's stability limit of the repulsion (docs/physics.md section 11): the
/// smallest damped-spring limit over surface gaps `0 <= h <= 10 kappa`, the stiffness
/// `A exp(-h / kappa) / kappa^2` (plus `k_n` at contact) damped by the squeeze resistance
/// at that gap (none beyond the lubrication's reach). The damper weakens faster than the
/// stiffness as the gap opens, so the worst gap is not at contact (0.21-1.0 of the contact
/// value for unit spheres). `mean_radius` is `(a_i + a_j) / 2`.
fn repulsion_limit(
    m_red: f64,
    k_n: f64,
    r: &Repulsion,
    lubrication: Option<&LubricationCoefficients>,
    mean_radius: f64,
) -> f64 {
    let steps = CUTOFF_KAPPAS as usize * REPULSION_GAPS_PER_KAPPA;
    (0..=steps)
        .map(|k| {
            let h = r.kappa * k as f64 / REPULSION_GAPS_PER_KAPPA as f64;
            let stiffness =
                r.contact_stiffness() * (-h / r.kappa).exp() + if k == 0 { k_n } else { 0.0 };
            let damping = lubrication
                .and_then(|l| l.resistance(h / mean_radius))
                .map_or(0.0, |res| res.x11a);
            damped_spring_limit(m_red, stiffness, damping)
        })
        .fold(f64::INFINITY, f64::min)
}

impl TimeStep {
    /// Critical steps over every species pair, and the step the scene asks for: `run.dt`
    /// if given, else `dt_safety * dt_factor` times the tightest stability limit of the
    /// scene's integrator (explicit: contact, friction, drag, lubrication; implicit:
    /// contact and friction), the implicit one capped by `dt_factor * accuracy_limit` and,
    /// with Brownian forces, by `dt_factor` times each of the [`BrownianLimits`].
    /// The Brownian limits look only at the species present (`counts` particles of each;
    /// a mixture at alpha = 1 lists colloid radii it places none of).
    pub fn choose(
        file: &SceneFile,
        (rho, gdot_max): (f64, f64),
        counts: &[usize],
        field: &ForceField,
    ) -> TimeStep {
        let eta = file.fluid.eta;
        let radii = &file.particles.radii;
        let mass = |a: f64| sphere_mass(rho, a);
        let implicit = file.run.integrator == Integrator::Implicit;
        let (mut contact, mut friction) = (f64::INFINITY, f64::INFINITY);
        let (mut drag, mut lub) = (f64::INFINITY, f64::INFINITY);
        for (s_i, &a_i) in radii.iter().enumerate() {
            if field.drag {
                drag = drag.min(2.0 * drag::relaxation_time(mass(a_i), eta, a_i));
            }
            for (s_j, &a_j) in radii.iter().enumerate() {
                let m_red = mass(a_i) * mass(a_j) / (mass(a_i) + mass(a_j));
                let constants = field.constants(s_i as u16, s_j as u16);
                let lubrication = constants.lubrication.as_ref();
                let damper = lubrication
                    .filter(|_| implicit)
                    .and_then(|l| l.resistance(l.xi_min))
                    .unwrap_or_default();
                let k_n = field.contact.map_or(0.0, |c| c.k_n);
                let pair_contact = match (&constants.repulsion, implicit) {
                    (Some(r), true) => {
                        repulsion_limit(m_red, k_n, r, lubrication, 0.5 * (a_i + a_j))
                    }
                    _ => {
                        let k_normal =
                            normal_stiffness(field.contact.map(|c| c.k_n), constants.repulsion);
                        if k_normal > 0.0 {
                            damped_spring_limit(m_red, k_normal, damper.x11a)
                        } else {
                            f64::INFINITY
                        }
                    }
                };
                contact = contact.min(pair_contact);
                if let Some(c) = field.contact.filter(|c| c.frictional()) {
                    let m_tangential = TANGENTIAL_MASS_SHARE * m_red;
                    friction = friction.min(damped_spring_limit(m_tangential, c.k_t, damper.y11a));
                }
                if let Some(l) = lubrication {
                    lub = lub.min(2.0 * m_red / l.x11a(l.xi_min));
                }
            }
        }
        let run = &file.run;
        let mut candidates = vec![(contact, DtLimit::Contact), (friction, DtLimit::Friction)];
        if !implicit {
            candidates.extend([(drag, DtLimit::Drag), (lub, DtLimit::Lubrication)]);
        }
        let (stable, stable_limit) = tightest(&candidates);
        let (mut dt, mut limit) = (stable * run.dt_safety * run.dt_factor, stable_limit);
        let accuracy = file.forces.xi_min / gdot_max;
        let a_min = radii.iter().copied().fold(f64::INFINITY, f64::min);
        let peclet = file
            .fluid
            .shear_rate
            .map(|gdot| peclet_number(eta, a_min, gdot, field.kt));
        let brownian = (implicit && field.kt > 0.0)
            .then(|| BrownianLimits::of(radii, counts, rho, field, peclet));
        if implicit {
            let mut caps = vec![(accuracy, DtLimit::Accuracy)];
            if let Some(b) = &brownian {
                caps.extend([
                    (b.diffusion, DtLimit::Diffusion),
                    (b.relaxation, DtLimit::Relaxation),
                    (b.cutoff, DtLimit::Cutoff),
                ]);
            }
            let (cap, cap_limit) = tightest(&caps);
            if cap * run.dt_factor < dt {
                (dt, limit) = (cap * run.dt_factor, cap_limit);
            }
        }
        if let Some(user) = run.dt {
            (dt, limit) = (user, DtLimit::User);
        }
        let b = brownian.unwrap_or(BrownianLimits {
            diffusion: f64::INFINITY,
            relaxation: f64::INFINITY,
            cutoff: f64::INFINITY,
        });
        TimeStep {
            dt,
            limit,
            contact_critical: contact,
            drag_critical: drag,
            lubrication_critical: lub,
            accuracy_limit: accuracy,
            friction_critical: friction,
            diffusion_limit: b.diffusion,
            relaxation_limit: b.relaxation,
            cutoff_limit: b.cutoff,
            integrator: run.integrator,
        }
    }

    /// The warning when the step of an implicit Brownian scene exceeds one of its
    /// [`BrownianLimits`] by more than [`BROWNIAN_LIMIT_TOLERANCE`] (only a step the scene
    /// sets can: `run.dt`, or `run.dt_factor` above 1), naming the limit and the factor to
    /// cut the step by.
    pub fn brownian_warning(&self) -> Option<String> {
        let (limit, name, what) = [
            (self.diffusion_limit, "diffusion", "a pair's Brownian displacement per step against the gap width its forces vary over"),
            (self.relaxation_limit, "relaxation", "the velocity relaxation times"),
            (self.cutoff_limit, "cutoff", "the squeeze relaxation of a pair at the sharp lubrication cut-off"),
        ]
        .into_iter()
        .min_by(|a, b| (self.dt / b.0).total_cmp(&(self.dt / a.0)))?;
        (self.dt > limit * (1.0 + BROWNIAN_LIMIT_TOLERANCE)).then(|| {
            format!(
                "the step {:.3e} is {:.2}x the Brownian {name} limit {limit:.3e} ({what}): the \
                 equilibrium structure and the stresses come out biased (docs/physics.md \
                 section 11); cut the step {:.2}x (run.dt, run.dt_factor), or leave it to the \
                 automatic step",
                self.dt,
                self.dt / limit,
                self.dt / limit
            )
        })
    }
}

/// How far a step the scene sets may exceed a Brownian limit before
/// [`TimeStep::brownian_warning`] speaks (relative, 1 %): a step written out to a few
/// digits, or one limit's step carried to a scene whose limit is a little shorter, is the
/// limit itself. The limits' constants were chosen by convergence in steps 3x apart
/// (docs/physics.md section 11); 1 % is far inside that resolution.
pub const BROWNIAN_LIMIT_TOLERANCE: f64 = 0.01;

/// The smallest of `candidates` and which limit it is (the first on a tie; infinite
/// `Contact` when empty).
fn tightest(candidates: &[(f64, DtLimit)]) -> (f64, DtLimit) {
    candidates
        .iter()
        .copied()
        .fold((f64::INFINITY, DtLimit::Contact), |best, c| {
            if c.0 < best.0 {
                c
            } else {
                best
            }
        })
}
