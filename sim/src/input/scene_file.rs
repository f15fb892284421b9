//! The scene file as written (TOML): its sections and their defaults (docs/physics.md
//! section 1), as read before validation. The file format only: [`Scene`] validates it and
//! derives what a run needs; [`composition`] expands a mixture's section.
//!
//! [`Scene`]: crate::input::scene::Scene
//! [`composition`]: crate::input::composition
use crate::forces::repulsion::Repulsion;
use crate::input::integrator::Integrator;
use crate::sampling::conventions::Conventions;
use serde::{Deserialize, Serialize};

/// The scene file as written by the user; every field but the box, `phi` and the
/// profile has the docs/physics.md section 1 default.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Name copied to the outputs (`scene_id`); letters, digits, `_`, `-`, `.` (see
    /// [`scene_name`](schema::scene_name)).
    #[serde(default = "default_name")]
    pub name: String,
    /// RNG seed of the initial packing.
    #[serde(default = "default_seed")]
    pub seed: u64,
    #[serde(rename = "box")]
    pub box_: BoxSection,
    pub particles: ParticleSection,
    pub fluid: FluidSection,
    #[serde(default)]
    pub forces: ForceSection,
    #[serde(default)]
    pub run: RunSection,
    /// Definitions of the observables (docs/physics.md section 6); the thesis' by default.
    #[serde(default)]
    pub observables: Conventions,
}

/// Fully periodic box, lengths in units of the small radius a.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSection {
    pub l_x: f64,
    pub l_y: f64,
    pub l_z: f64,
}

/// Particle population.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleSection {
    /// Global solid volume fraction; absent (0 until validation) only when
    /// `mixture.initial` sets it.
    #[serde(default)]
    pub phi: f64,
    /// Radii of the species (units a); 1 and 1.4 when neither these nor a `mixture` are
    /// given (an empty list until validation fills it in).
    #[serde(default)]
    pub radii: Vec<f64>,
    /// Number fractions of the species (must sum to 1); equal numbers of each radius when
    /// absent (an empty list until validation fills it in).
    #[serde(default)]
    pub fractions: Vec<f64>,
    /// Particle density (mass per a^3); 1 when neither this nor `stokes` is given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rho: Option<f64>,
    /// Target Stokes number `rho a^2 gdot_max / eta` (docs/physics.md section 1): sets `rho` from the
    /// profile's largest shear rate, so that scenes with different profiles share one St.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stokes: Option<f64>,
    /// A colloid-grain mixture by its composition, expanded into `radii`, `fractions` and
    /// (at fixed liquid volume) `phi` (see [`composition`](crate::input::composition)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mixture: Option<MixtureSection>,
}

/// Suspending fluid and its streaming velocity: either an inhomogeneous `profile` or a
/// homogeneous `shear_rate`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    /// Viscosity.
    #[serde(default = "one")]
    pub eta: f64,
    /// Streaming velocity `u(y)` along x (docs/physics.md section 2), an expression in y, L, pi.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub profile: String,
    /// Homogeneous simple shear at this rate (1/time) between Lees-Edwards images
    /// (docs/physics.md section 10), instead of a profile.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_rate: Option<f64>,
    /// Thermal energy `kT` of the Brownian forces (docs/physics.md section 11; units
    /// eta a^3 / time); 0 = non-Brownian, and then nothing of them is evaluated.
    #[serde(default, rename = "kT", skip_serializing_if = "is_zero")]
    pub kt: f64,
    /// Peclet number `6 pi eta a^3 gdot / kT` (a the small radius) of homogeneous shear:
    /// with `shear_rate` it sets `kT`, with `kT` the shear rate (see
    /// [`complete_from_peclet`](crate::input::thermal_scales::complete_from_peclet)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peclet: Option<f64>,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Which force terms are on, and their parameters.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSection {
    #[serde(default = "yes")]
    pub contact: bool,
    #[serde(default = "yes")]
    pub drag: bool,
    #[serde(default = "yes")]
    pub lubrication: bool,
    /// Normal contact stiffness.
    #[serde(default = "default_k_n")]
    pub k_n: f64,
    /// Contact friction coefficient (0 = frictionless, no tangential history kept).
    #[serde(default)]
    pub mu_p: f64,
    /// Lubrication inner regularisation of the dimensionless gap.
    #[serde(default = "default_xi_min")]
    pub xi_min: f64,
    /// Lubrication outer cut-off of the dimensionless gap.
    #[serde(default = "default_xi_max")]
    pub xi_max: f64,
    /// Width (in the dimensionless gap) of the taper beyond `xi_max` over which the
    /// lubrication resistance falls smoothly to zero; 0 = the seeds' sharp cut. Absent:
    /// `xi_max` in a Brownian scene (filled in when the scene is read, docs/physics.md
    /// section 11), 0 otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xi_taper: Option<f64>,
    /// Short-range repulsion `A / kT` (dimensionless; paper eq 4.2, thesis eq 4.4,
    /// docs/physics.md section 11): the amplitude `A = repulsion * fluid.kT`, so it needs
    /// `fluid.kT > 0`; 0 = off, and then nothing of it is evaluated.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub repulsion: f64,
}

impl ForceSection {
    /// The lubrication taper's width (`xi_taper`, 0 when absent).
    pub fn taper_width(&self) -> f64 {
        self.xi_taper.unwrap_or(0.0)
    }

    /// Interaction range of a pair at contact distance `a_i + a_j` (units a): the
    /// lubrication cut-off `(a_i + a_j)(1 + (xi_max + xi_taper) / 2)`, where the gap
    /// `xi = 2 (r - a_i - a_j) / (a_i + a_j)` reaches the taper's end (docs/physics.md
    /// section 4),
    /// or the contact distance without lubrication; with the repulsion on, at least its
    /// cut-off `1.1 (a_i + a_j)`, a gap of 10 Debye lengths ([`Repulsion::reach`]).
    pub fn reach(&self, contact_distance: f64) -> f64 {
        let reach = if self.lubrication {
            contact_distance * (1.0 + 0.5 * (self.xi_max + self.taper_width()))
        } else {
            contact_distance
        };
        if self.repulsion > 0.0 {
            reach.max(Repulsion::reach(contact_distance))
        } else {
            reach
        }
    }
}

/// Time step, sampling, steady-state detection and averaging.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    /// Time integrator, `"implicit"` (default) or `"explicit"` (docs/physics.md section 5).
    #[serde(default)]
    pub integrator: Integrator,
    /// Relative residual at which the implicit step's solve stops.
    #[serde(default = "default_solver_tolerance")]
    pub solver_tolerance: f64,
    /// Fixed time step; absent = automatic (docs/physics.md section 5).
    #[serde(default)]
    pub dt: Option<f64>,
    /// Fraction of the tightest explicit stability limit used by the automatic dt.
    #[serde(default = "default_dt_safety")]
    pub dt_safety: f64,
    /// Multiplier applied to the automatic dt (stability studies; 1 = as chosen).
    #[serde(default = "one")]
    pub dt_factor: f64,
    /// Verlet-list skin (units a).
    #[serde(default = "default_skin")]
    pub skin: f64,
    /// Bin width along y (units a); must divide L_y.
    #[serde(default = "default_bin_width")]
    pub bin_width: f64,
    /// Strain between two snapshots.
    #[serde(default = "default_sample_strain")]
    pub sample_strain: f64,
    /// Strain of one steady-state detection window.
    #[serde(default = "one")]
    pub window_strain: f64,
    /// Strain budget to reach the steady state.
    #[serde(default = "default_max_strain")]
    pub max_strain: f64,
    /// Steady when, for u, sigma_xy and phi_loc, the mean over bins of the squared
    /// z-score of the linear trend over the last 4 windows is below this (about 1 for
    /// pure noise).
    #[serde(default = "default_steady_chi2")]
    pub steady_chi2: f64,
    /// Snapshots averaged in the steady state (seeds: 1000).
    #[serde(default = "default_snapshots")]
    pub snapshots: usize,
    /// Blocks for the standard errors (batch means over the snapshots).
    #[serde(default = "default_blocks")]
    pub blocks: usize,
    /// Wall-clock seconds between checkpoints.
    #[serde(default = "default_checkpoint_s")]
    pub checkpoint_every_s: f64,
}

fn default_name() -> String {
    "scene".into()
}
fn default_seed() -> u64 {
    1
}
fn one() -> f64 {
    1.0
}
fn yes() -> bool {
    true
}
fn default_k_n() -> f64 {
    1e4
}
fn default_xi_min() -> f64 {
    1e-3
}
fn default_xi_max() -> f64 {
    0.05
}
fn default_solver_tolerance() -> f64 {
    1e-4
}
fn default_dt_safety() -> f64 {
    0.3
}
fn default_skin() -> f64 {
    0.1
}
fn default_bin_width() -> f64 {
    2.0
}
fn default_sample_strain() -> f64 {
    0.01
}
fn default_max_strain() -> f64 {
    30.0
}
fn default_steady_chi2() -> f64 {
    3.0
}
fn default_snapshots() -> usize {
    1000
}
fn default_blocks() -> usize {
    20
}
fn default_checkpoint_s() -> f64 {
    60.0
}

impl Default for ForceSection {
    fn default() -> Self {
        toml::from_str("").expect("all force fields have defaults")
    }
}

impl Default for RunSection {
    fn default() -> Self {
        toml::from_str("").expect("all run fields have defaults")
    }
}

/// The `[particles.mixture]` table.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MixtureSection {
    /// Grain share of the solid volume `alpha = V_g / (V_c + V_g)`, in [0, 1].
    pub alpha: f64,
    /// Radii of the colloids (units a).
    #[serde(default = "default_colloid_radii")]
    pub colloid_radii: Vec<f64>,
    /// Radii of the grains (units a), each larger than every colloid radius.
    #[serde(default = "default_grain_radii")]
    pub grain_radii: Vec<f64>,
    /// The suspension the other species is added to at fixed liquid volume; absent: the
    /// mixture is made at the given `particles.phi`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<InitialSuspension>,
}

pub(crate) fn default_colloid_radii() -> Vec<f64> {
    vec![1.0, 1.4]
}
pub(crate) fn default_grain_radii() -> Vec<f64> {
    vec![5.0, 7.0]
}

/// One of the two species of a mixture.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Species {
    Colloids,
    Grains,
}

impl Species {
    /// The name as written in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Species::Colloids => "colloids",
            Species::Grains => "grains",
        }
    }

    /// The species added to a suspension of this one.
    pub fn other(self) -> Species {
        match self {
            Species::Colloids => Species::Grains,
            Species::Grains => Species::Colloids,
        }
    }
}

/// A suspension of one species at volume fraction `phi`, to which the other is added at
/// fixed liquid volume.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InitialSuspension {
    pub species: Species,
    pub phi: f64,
}

impl SceneFile {
    /// A scene with box `[l_x, l_y, l_z]`, volume fraction `phi` and flow `profile`, every
    /// other field at its default: for scenes built in code (benchmarks, sweeps), which then
    /// set the fields they change.
    pub fn with_defaults(name: &str, box_len: [f64; 3], phi: f64, profile: &str) -> SceneFile {
        let mut table = toml::Table::new();
        table.insert("name".into(), name.into());
        let mut box_ = toml::Table::new();
        for (key, value) in ["l_x", "l_y", "l_z"].iter().zip(box_len) {
            box_.insert((*key).into(), value.into());
        }
        table.insert("box".into(), box_.into());
        let mut particles = toml::Table::new();
        particles.insert("phi".into(), phi.into());
        table.insert("particles".into(), particles.into());
        let mut fluid = toml::Table::new();
        fluid.insert("profile".into(), profile.into());
        table.insert("fluid".into(), fluid.into());
        toml::Value::Table(table)
            .try_into()
            .expect("every field without a default is given")
    }
}
