//! The force terms a scene switches on, with per-species-pair constants precomputed, and
//! the load of one pair and of one particle (docs/physics.md section 4).
use crate::forces::brownian_shell;
use crate::forces::contact::{ContactLaw, ContactMotion};
use crate::forces::drag;
use crate::forces::lubrication::{gap, LubricationCoefficients, PairResistance};
use crate::forces::pair_load::PairLoad;
use crate::forces::repulsion::Repulsion;
use crate::input::flow_profile::FlowProfile;
use crate::input::scene_file::SceneFile;
use crate::state::particles::Particles;
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;

/// Constants of one ordered species pair.
#[derive(Clone, Copy, Debug)]
pub struct PairConstants {
    /// `a_i + a_j`: contact distance.
    pub contact_distance: f64,
    /// Square of the interaction cut-off (lubrication `xi_max`, or contact; at least the
    /// structural Brownian stress's shell in a Brownian scene, and the repulsion's
    /// cut-off when it is on).
    pub reach_squared: f64,
    /// Lubrication prefactors, when lubrication is on.
    pub lubrication: Option<LubricationCoefficients>,
    /// The short-range repulsion, when `forces.repulsion > 0`; it acts on every pair
    /// inside the cut-off.
    pub repulsion: Option<Repulsion>,
    /// Smaller radius of the pair, the unit of its overlap ratio.
    pub a_min: f64,
}

/// A pair interaction's load and geometry.
#[derive(Clone, Copy, Debug)]
pub struct PairOutcome {
    pub load: PairLoad,
    /// The contact part of `load.force_i`: normal and tangential springs and the
    /// short-range repulsion, which is counted in the contact stress part; the rest of it
    /// is lubrication (docs/physics.md section 11, the stress parts).
    pub contact_force: Vec3,
    /// Minimum-image separation `x_j - x_i` (through the sliding images of a sheared box).
    pub r: Vec3,
    /// Unit vector `r / |r|` from i to j.
    pub n: Vec3,
    /// Overlap `a_i + a_j - |r|` (negative when apart).
    pub overlap: f64,
    /// The pair's lubrication resistance, when within the lubrication cut-off.
    pub resistance: Option<PairResistance>,
}

/// Force terms of a scene. A term that is off costs nothing: it is never evaluated.
#[derive(Clone, Debug)]
pub struct ForceField {
    pub eta: f64,
    /// Thermal energy (0 = non-Brownian); the Brownian loads are
    /// [`network_loads`](crate::forces::network_loads)'.
    pub kt: f64,
    pub contact: Option<ContactLaw>,
    pub drag: bool,
    n_species: usize,
    pairs: Vec<PairConstants>,
    /// Largest pair cut-off.
    pub max_cutoff: f64,
}

impl ForceField {
    /// Force terms and pair constants of a validated scene's file.
    pub fn from_file(file: &SceneFile) -> Self {
        let f = &file.forces;
        let eta = file.fluid.eta;
        let kt = file.fluid.kt;
        let radii = &file.particles.radii;
        let n_species = radii.len();
        let mut pairs = Vec::with_capacity(n_species * n_species);
        let mut max_cutoff: f64 = 0.0;
        for &a_i in radii {
            for &a_j in radii {
                let contact_distance = a_i + a_j;
                let lubrication = f
                    .lubrication
                    .then(|| LubricationCoefficients::new(a_i, a_j, eta, f.xi_min, f.xi_max))
                    .map(|l| l.with_taper(f.taper_width()));
                let mut reach = f.reach(contact_distance);
                if kt > 0.0 {
                    reach = reach.max(brownian_shell::reach(a_i, a_j));
                }
                max_cutoff = max_cutoff.max(reach);
                let repulsion =
                    (f.repulsion > 0.0).then(|| Repulsion::new(f.repulsion * kt, contact_distance));
                pairs.push(PairConstants {
                    contact_distance,
                    reach_squared: reach * reach,
                    lubrication,
                    repulsion,
                    a_min: a_i.min(a_j),
                });
            }
        }
        Self {
            eta,
            kt,
            contact: f.contact.then(|| ContactLaw::new(f.k_n, f.mu_p)),
            drag: f.drag,
            n_species,
            pairs,
            max_cutoff,
        }
    }

    /// Constants of the species pair (s_i, s_j).
    #[inline]
    pub fn constants(&self, s_i: u16, s_j: u16) -> &PairConstants {
        &self.pairs[s_i as usize * self.n_species + s_j as usize]
    }

    /// Number of species.
    pub fn n_species(&self) -> usize {
        self.n_species
    }

    /// Interaction cut-off distance of the species pair.
    pub fn cutoff(&self, s_i: u16, s_j: u16) -> f64 {
        self.constants(s_i, s_j).reach_squared.sqrt()
    }

    /// Whether contacts carry a tangential spring (per-pair history).
    pub fn frictional(&self) -> bool {
        self.contact.is_some_and(|c| c.frictional())
    }

    /// Load of the pair (i, j), or `None` when they are beyond the cut-off: contact (and
    /// repulsion) plus lubrication at the current velocities; through a sliding y image of a sheared box,
    /// j moves with its image's velocity (docs/physics.md section 10). `spring` is the
    /// pair's tangential contact history (frictional scenes only), advanced by `dt`.
    #[inline]
    pub fn pair(
        &self,
        p: &Particles,
        pbox: &PeriodicBox,
        i: usize,
        j: usize,
        spring: Option<&mut Vec3>,
        dt: f64,
    ) -> Option<PairOutcome> {
        let mut out = self.pair_contact(p, pbox, i, j, spring, dt)?;
        if let Some(r) = &out.resistance {
            let dv = p.vel[j] - p.vel[i];
            out.load.add(&r.load(&out.n, &dv, &p.omega[i], &p.omega[j]));
        }
        Some(out)
    }

    /// The contact load of the pair (i, j) (springs and repulsion: the conservative,
    /// position-only part, which both integrators take as known) and its lubrication
    /// resistance, not applied
    /// to the particles' own motion (the implicit step integrates that itself,
    /// docs/physics.md section 5), or `None` beyond the cut-off. Across a sliding y image
    /// the load includes the lubrication of the image's extra velocity.
    #[inline]
    pub fn pair_contact(
        &self,
        p: &Particles,
        pbox: &PeriodicBox,
        i: usize,
        j: usize,
        spring: Option<&mut Vec3>,
        dt: f64,
    ) -> Option<PairOutcome> {
        let c = self.constants(p.species[i], p.species[j]);
        let (r, image) = pbox.image(&p.pos[i], &p.pos[j]);
        let d2 = r.norm_squared();
        if d2 >= c.reach_squared {
            if let Some(s) = spring {
                *s = Vec3::zeros();
            }
            return None;
        }
        let d = d2.sqrt();
        let n = r / d;
        let overlap = c.contact_distance - d;
        let resistance = c
            .lubrication
            .as_ref()
            .and_then(|lub| lub.resistance(gap(d, p.radius[i], p.radius[j])));
        let mut dv = p.vel[j] - p.vel[i];
        let mut load = PairLoad::default();
        let mut contact_load = PairLoad::default();
        if image != 0 {
            // The image's extra velocity is fixed by the positions: its lubrication load
            // is part of this known load (the resistance is linear in the motion).
            let shift = pbox.image_velocity(image);
            dv += shift;
            if let Some(r) = &resistance {
                load = r.load(&n, &shift, &Vec3::zeros(), &Vec3::zeros());
            }
        }
        if let Some(contact) = &self.contact {
            if overlap > 0.0 {
                contact_load.force_i = contact.normal(overlap, &n);
                if let Some(s) = spring {
                    let motion = ContactMotion {
                        delta: overlap,
                        n: &n,
                        dv: &dv,
                        omega: [&p.omega[i], &p.omega[j]],
                        radius: [p.radius[i], p.radius[j]],
                    };
                    let t = contact.tangential(s, &motion, dt);
                    contact_load.add(&t);
                }
            } else if let Some(s) = spring {
                *s = Vec3::zeros();
            }
        }
        if let Some(repulsion) = &c.repulsion {
            contact_load.force_i += repulsion.force_i(overlap, &n);
        }
        load.add(&contact_load);
        Some(PairOutcome {
            load,
            contact_force: contact_load.force_i,
            r,
            n,
            overlap,
            resistance,
        })
    }

    /// One-body load of particle i: Stokes drag and rotational drag towards the local
    /// streaming flow (3.5, 3.6); zero when drag is off.
    #[inline]
    pub fn one_body(&self, p: &Particles, profile: &FlowProfile, i: usize) -> (Vec3, Vec3) {
        if !self.drag {
            return (Vec3::zeros(), Vec3::zeros());
        }
        let motion = (&p.vel[i], &p.omega[i]);
        drag::loads(self.eta, p.radius[i], profile, p.pos[i].y, motion)
    }
}
