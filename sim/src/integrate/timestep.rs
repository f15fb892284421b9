//! Automatic stable time step (docs/physics.md section 5): the explicit velocity-Verlet scheme is
//! limited by the contact spring, the one-body drag and the lubrication squeeze
//! resistance at `xi_min`; the step is a safety fraction of the tightest limit.
use crate::forces::force_field::ForceField;
use crate::input::scene::Scene;
use serde::Serialize;
use std::f64::consts::PI;

/// Which stability limit set the time step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DtLimit {
    Contact,
    Drag,
    Lubrication,
    /// Set by the scene's `run.dt`.
    User,
}

impl std::fmt::Display for DtLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            DtLimit::Contact => "contact",
            DtLimit::Drag => "drag",
            DtLimit::Lubrication => "lubrication",
            DtLimit::User => "user",
        };
        f.write_str(s)
    }
}

/// The critical steps of each term and the step chosen.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TimeStep {
    /// Chosen step.
    pub dt: f64,
    /// What set it.
    pub limit: DtLimit,
    /// `2 sqrt(m_red / k_n)`, the stability limit of an undamped contact spring (infinite without contacts).
    pub contact_critical: f64,
    /// `2 m / (6 pi eta a)`, explicit stability of the Stokes drag (infinite without drag).
    pub drag_critical: f64,
    /// `2 m_red / X11A(xi_min)`, explicit stability of the lubrication squeeze term.
    pub lubrication_critical: f64,
}

impl TimeStep {
    /// Critical steps over every species pair, and the step the scene asks for:
    /// `run.dt` if given, else `dt_safety * dt_factor * min(critical steps)`.
    pub fn choose(scene: &Scene, field: &ForceField) -> TimeStep {
        let rho = scene.rho;
        let eta = scene.file.fluid.eta;
        let radii = &scene.file.particles.radii;
        let mass = |a: f64| 4.0 / 3.0 * PI * rho * a.powi(3);
        let (mut contact, mut drag, mut lub) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        for (s_i, &a_i) in radii.iter().enumerate() {
            if field.drag {
                drag = drag.min(2.0 * mass(a_i) / (6.0 * PI * eta * a_i));
            }
            for (s_j, &a_j) in radii.iter().enumerate() {
                let m_red = mass(a_i) * mass(a_j) / (mass(a_i) + mass(a_j));
                if let Some(c) = &field.contact {
                    contact = contact.min(2.0 * (m_red / c.k_n).sqrt());
                }
                if let Some(l) = &field.constants(s_i as u16, s_j as u16).lubrication {
                    lub = lub.min(2.0 * m_red / l.x11a(l.xi_min));
                }
            }
        }
        let run = &scene.file.run;
        let (mut dt, mut limit) = (contact, DtLimit::Contact);
        if drag < dt {
            (dt, limit) = (drag, DtLimit::Drag);
        }
        if lub < dt {
            (dt, limit) = (lub, DtLimit::Lubrication);
        }
        dt *= run.dt_safety * run.dt_factor;
        if let Some(user) = run.dt {
            (dt, limit) = (user, DtLimit::User);
        }
        TimeStep {
            dt,
            limit,
            contact_critical: contact,
            drag_critical: drag,
            lubrication_critical: lub,
        }
    }

    /// The step `scene` will run with (its force field built from the scene).
    pub fn for_scene(scene: &Scene) -> TimeStep {
        Self::choose(scene, &ForceField::from_scene(scene))
    }

    /// Steps per unit strain (strain = largest shear rate of the profile x time).
    pub fn steps_per_strain(&self, scene: &Scene) -> f64 {
        1.0 / (scene.gdot_max() * self.dt)
    }
}
