//! Scene files (TOML): the box, particles, fluid, force terms and run length, validated
//! field by field, with the derived quantities a run needs (N, Stokes number, bins).
use crate::error::SimError;
use crate::forces::repulsion::Repulsion;
use crate::input::composition::{self, Composition, MixtureSection};
use crate::input::flow_profile::FlowProfile;
use crate::input::integrator::Integrator;
use crate::input::memory_estimate;
use crate::input::run_cost::RunCost;
use crate::input::scene_limits::{self, show, PHI_MAX};
use crate::input::thermal_scales::{self, ThermalScales};
use crate::integrate::timestep::TimeStep;
use crate::sampling::conventions::Conventions;
use crate::state::particles::sphere_volume;
use schema::scene_name;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The scene file as written by the user; every field but the box, `phi` and the
/// profile has the docs/physics.md section 1 default.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Name copied to the outputs (`scene_id`); letters, digits, `_`, `-`, `.` (see
    /// [`scene_name`]).
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
    /// (at fixed liquid volume) `phi` (see [`composition`]).
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
    /// [`thermal_scales::complete_from_peclet`]).
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
    /// Short-range repulsion `A / kT` (dimensionless; paper eq 4.2, thesis eq 4.4,
    /// docs/physics.md section 11): the amplitude `A = repulsion * fluid.kT`, so it needs
    /// `fluid.kT > 0`; 0 = off, and then nothing of it is evaluated.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub repulsion: f64,
}

impl ForceSection {
    /// Interaction range of a pair at contact distance `a_i + a_j` (units a): the
    /// lubrication cut-off `(a_i + a_j)(1 + xi_max / 2)`, where the gap
    /// `xi = 2 (r - a_i - a_j) / (a_i + a_j)` reaches `xi_max` (docs/physics.md section 4),
    /// or the contact distance without lubrication; with the repulsion on, at least its
    /// cut-off `1.1 (a_i + a_j)`, a gap of 10 Debye lengths ([`Repulsion::reach`]).
    pub fn reach(&self, contact_distance: f64) -> f64 {
        let reach = if self.lubrication {
            contact_distance * (1.0 + 0.5 * self.xi_max)
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

/// A validated scene with its derived quantities.
#[derive(Clone, Debug)]
pub struct Scene {
    pub file: SceneFile,
    pub profile: FlowProfile,
    /// Box lengths `[L_x, L_y, L_z]`.
    pub box_len: [f64; 3],
    /// Number of particles of each species.
    pub counts: Vec<usize>,
    /// Volume fraction actually realised by the integer particle counts.
    pub phi_actual: f64,
    /// Number of bins along y.
    pub n_bins: usize,
    /// Largest pair interaction distance (contact or lubrication cut-off), units a.
    pub interaction_range: f64,
    /// Particle density, given or derived from the target Stokes number.
    pub rho: f64,
    /// Stokes number `rho a^2 gdot_max / eta` with a the small radius (docs/physics.md section 1).
    pub stokes: f64,
    /// The time step the scene runs with (docs/physics.md section 5), chosen once here.
    pub timestep: TimeStep,
    /// Estimated peak memory of a run (bytes, see [`memory_estimate`]).
    pub memory_bytes: f64,
    /// Non-fatal problems (Stokes number too large, ...).
    pub warnings: Vec<String>,
    /// Time scales of the Brownian forces, when `fluid.kT > 0`.
    pub thermal: Option<ThermalScales>,
    /// The realised composition and Peclet numbers of a `particles.mixture` scene.
    pub composition: Option<Composition>,
}

/// Largest accepted `|sum of number fractions - 1|` (room for decimal round-off such as
/// `[0.1, 0.2, 0.7]`).
const FRACTION_SUM_TOLERANCE: f64 = 1e-9;

fn positive(field: &str, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SimError::field(
            field,
            format!("must be a positive finite number, got {}", show(v)),
        ))
    }
}

/// The streaming flow of the fluid section: the inhomogeneous `profile` (which must shear
/// somewhere), or homogeneous simple shear at `shear_rate`; exactly one of them.
fn streaming_flow(fluid: &FluidSection, l_y: f64) -> Result<FlowProfile, SimError> {
    match (fluid.profile.is_empty(), fluid.shear_rate) {
        (false, Some(_)) => Err(SimError::field(
            "fluid.shear_rate",
            "give either fluid.profile (inhomogeneous flow) or fluid.shear_rate (homogeneous \
             shear), not both",
        )),
        (true, None) if fluid.kt > 0.0 => FlowProfile::new("0", l_y),
        (true, None) => Err(SimError::field(
            "fluid",
            "needs a streaming flow: fluid.profile = \"0.1*sin(2*pi*y/L)\" (inhomogeneous) \
             or fluid.shear_rate = 0.01 (homogeneous shear), or a thermal energy fluid.kT > 0 \
             (an equilibrium Brownian run)",
        )),
        (true, Some(gdot)) => {
            positive("fluid.shear_rate", gdot)?;
            Ok(FlowProfile::simple_shear(gdot, l_y))
        }
        (false, None) => {
            let profile = FlowProfile::new(&fluid.profile, l_y)?;
            if profile.max_abs_shear_rate() == 0.0 && fluid.kt == 0.0 {
                return Err(SimError::field(
                    "fluid.profile",
                    format!(
                        "`{}` has no shear (max |u'| = 0): the run's clock is the strain, which \
                         would never advance; give a profile whose shear rate is not zero \
                         everywhere, or a thermal energy fluid.kT > 0 (then the clock is the \
                         Brownian time)",
                        fluid.profile
                    ),
                ));
            }
            Ok(profile)
        }
    }
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

impl Scene {
    /// Reads and validates a scene file.
    pub fn from_path(path: &Path, strict: bool) -> Result<Scene, SimError> {
        let text = std::fs::read_to_string(path).map_err(|e| SimError::SceneFile {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_toml(&text, strict).map_err(|e| match e {
            SimError::SceneFile { message, .. } => SimError::SceneFile {
                path: path.display().to_string(),
                message,
            },
            other => other,
        })
    }

    /// Parses and validates scene text. With `strict`, warnings (docs/physics.md section 1: Stokes
    /// number >= 0.1) are errors.
    pub fn from_toml(text: &str, strict: bool) -> Result<Scene, SimError> {
        let file: SceneFile = toml::from_str(text).map_err(|e| SimError::SceneFile {
            path: "<text>".into(),
            message: e.to_string(),
        })?;
        Self::from_file(file, strict)
    }

    /// Validates a parsed scene; absent number fractions become equal fractions of the
    /// radii given.
    pub fn from_file(mut file: SceneFile, strict: bool) -> Result<Scene, SimError> {
        scene_name::check(&file.name).map_err(|m| SimError::field("name", m))?;
        composition::expand(&mut file.particles)?;
        if file.particles.fractions.is_empty() {
            let n = file.particles.radii.len();
            file.particles.fractions = vec![1.0 / n as f64; n];
        }
        let b = &file.box_;
        positive("box.l_x", b.l_x)?;
        positive("box.l_y", b.l_y)?;
        positive("box.l_z", b.l_z)?;
        let p = &file.particles;
        if p.phi == 0.0 {
            return Err(SimError::field(
                "particles.phi",
                format!(
                    "is missing: give the solid volume fraction (0, {PHI_MAX}], or a \
                     particles.mixture with an initial suspension that sets it"
                ),
            ));
        }
        if !(p.phi > 0.0 && p.phi <= PHI_MAX) {
            return Err(SimError::field(
                "particles.phi",
                format!(
                    "must lie in (0, {PHI_MAX}]: the initial packing reaches {PHI_MAX} and \
                     jams at 0.645 (measured for radii 1 : 1, 1 : 1.4 and 1 : 3; only a \
                     crystal is denser), got {}",
                    show(p.phi)
                ),
            ));
        }
        if p.radii.is_empty() || p.radii.len() != p.fractions.len() {
            return Err(SimError::field(
                "particles.fractions",
                format!(
                    "needs one number fraction per radius ({} radii, {} fractions)",
                    p.radii.len(),
                    p.fractions.len()
                ),
            ));
        }
        for (k, &a) in p.radii.iter().enumerate() {
            positive(&format!("particles.radii[{k}]"), a)?;
        }
        let fraction_sum: f64 = p.fractions.iter().sum();
        if p.fractions.iter().any(|f| !(f.is_finite() && *f >= 0.0))
            || (fraction_sum - 1.0).abs() > FRACTION_SUM_TOLERANCE
        {
            return Err(SimError::field(
                "particles.fractions",
                format!(
                    "number fractions must be non-negative and sum to 1, got {:?} (sum {fraction_sum})",
                    p.fractions
                ),
            ));
        }
        positive("fluid.eta", file.fluid.eta)?;
        let a_min = p.radii.iter().cloned().fold(f64::INFINITY, f64::min);
        // The thermal scales' radius: the smallest, or a mixture's colloid radius even
        // when no colloids are placed (alpha = 1), so that `fluid.peclet` is Pe_c at every
        // composition.
        let a_thermal = p
            .mixture
            .as_ref()
            .map_or(a_min, MixtureSection::colloid_radius);
        thermal_scales::complete_from_peclet(&mut file.fluid, a_thermal)?;
        if !(file.fluid.kt.is_finite() && file.fluid.kt >= 0.0) {
            return Err(SimError::field(
                "fluid.kT",
                format!("must be >= 0 (0 = non-Brownian), got {}", file.fluid.kt),
            ));
        }
        let f = &file.forces;
        if !(f.contact || f.drag || f.lubrication) {
            return Err(SimError::field(
                "forces",
                "contact, drag and lubrication are all off: nothing couples the particles to \
                 the flow or limits the time step; switch at least one on",
            ));
        }
        positive("forces.k_n", f.k_n)?;
        if !(f.mu_p.is_finite() && f.mu_p >= 0.0) {
            return Err(SimError::field(
                "forces.mu_p",
                format!("must be >= 0, got {}", f.mu_p),
            ));
        }
        positive("forces.xi_min", f.xi_min)?;
        positive("forces.xi_max", f.xi_max)?;
        if f.xi_min >= f.xi_max {
            return Err(SimError::field(
                "forces.xi_min",
                format!("must be below forces.xi_max ({} >= {})", f.xi_min, f.xi_max),
            ));
        }
        if !(f.repulsion.is_finite() && f.repulsion >= 0.0) {
            return Err(SimError::field(
                "forces.repulsion",
                format!("must be >= 0 (A / kT; 0 = off), got {}", show(f.repulsion)),
            ));
        }
        if f.repulsion > 0.0 && file.fluid.kt == 0.0 {
            return Err(SimError::field(
                "forces.repulsion",
                format!(
                    "is A / kT and needs fluid.kT > 0 (the amplitude is A = repulsion * kT), \
                     got repulsion = {} with kT = 0",
                    f.repulsion
                ),
            ));
        }
        let r = &file.run;
        if let Some(dt) = r.dt {
            positive("run.dt", dt)?;
        }
        positive("run.dt_safety", r.dt_safety)?;
        if !(r.solver_tolerance > 0.0 && r.solver_tolerance <= 1e-3) {
            return Err(SimError::field(
                "run.solver_tolerance",
                format!("must be in (0, 1e-3], got {}", r.solver_tolerance),
            ));
        }
        positive("run.dt_factor", r.dt_factor)?;
        if !(r.skin.is_finite() && r.skin >= 0.0) {
            return Err(SimError::field(
                "run.skin",
                format!("must be >= 0, got {}", r.skin),
            ));
        }
        positive("run.bin_width", r.bin_width)?;
        positive("run.sample_strain", r.sample_strain)?;
        positive("run.window_strain", r.window_strain)?;
        positive("run.max_strain", r.max_strain)?;
        positive("run.steady_chi2", r.steady_chi2)?;
        positive("run.checkpoint_every_s", r.checkpoint_every_s)?;
        if r.blocks < 2 || r.snapshots < r.blocks {
            return Err(SimError::field(
                "run.blocks",
                format!(
                    "need 2 <= blocks <= snapshots, got blocks = {}, snapshots = {}",
                    r.blocks, r.snapshots
                ),
            ));
        }
        scene_limits::check(&file)?;
        let bins = b.l_y / r.bin_width;
        let n_bins = bins.round() as usize;
        if n_bins < 3 || (bins - bins.round()).abs() > 1e-6 * bins {
            return Err(SimError::field(
                "run.bin_width",
                format!(
                    "must divide box.l_y into at least 3 bins: {} / {} = {bins}",
                    b.l_y, r.bin_width
                ),
            ));
        }
        let profile = streaming_flow(&file.fluid, b.l_y)?;
        scene_limits::check_bin_resolution(&profile, n_bins)?;
        let gdot_max = profile.max_abs_shear_rate();

        let a_max = p.radii.iter().cloned().fold(0.0, f64::max);
        let interaction_range = f.reach(2.0 * a_max);
        let needed = 2.0 * (interaction_range + r.skin);
        if file.fluid.shear_rate.is_some() && b.l_y < 1.5 * needed {
            return Err(SimError::field(
                "box.l_y",
                format!(
                    "{} is shorter than three times the interaction range plus skin ({:.3}): \
                     a sheared box needs three neighbour cells along y",
                    b.l_y,
                    1.5 * needed
                ),
            ));
        }
        for (name, l) in [("box.l_x", b.l_x), ("box.l_y", b.l_y), ("box.l_z", b.l_z)] {
            if l < needed {
                return Err(SimError::field(
                    name,
                    format!(
                        "{l} is shorter than twice the interaction range plus skin ({needed:.3}): \
                     the minimum-image convention would count a pair twice"
                    ),
                ));
            }
        }

        let fractions: Vec<f64> = p.fractions.iter().map(|x| x / fraction_sum).collect();
        let volume = b.l_x * b.l_y * b.l_z;
        let mean_particle_volume: f64 = fractions
            .iter()
            .zip(&p.radii)
            .map(|(x, &a)| x * sphere_volume(a))
            .sum();
        let n_total = (p.phi * volume / mean_particle_volume).round() as usize;
        let memory_bytes =
            memory_estimate::run_bytes(n_total, [b.l_x, b.l_y, b.l_z], interaction_range + r.skin);
        let counts: Vec<usize> = if p.mixture.is_some() {
            // Each species rounded on its own, so that its volume is the nearest its
            // particles allow: a grain of radius 7 holds the volume of 343 colloids, and
            // the rule below would put the count's round-off on it.
            let n_exact = p.phi * volume / mean_particle_volume;
            fractions
                .iter()
                .map(|x| (x * n_exact).round() as usize)
                .collect()
        } else {
            let mut counts: Vec<usize> = fractions
                .iter()
                .map(|x| (x * n_total as f64).round() as usize)
                .collect();
            let assigned: usize = counts.iter().sum();
            let last = counts.len() - 1;
            counts[last] = (counts[last] + n_total).saturating_sub(assigned);
            counts
        };
        let n: usize = counts.iter().sum();
        if n < 2 {
            return Err(SimError::field(
                "particles.phi",
                format!(
                    "the box holds fewer than 2 particles at phi = {} (volume {volume})",
                    p.phi
                ),
            ));
        }
        let solid: f64 = counts
            .iter()
            .zip(&p.radii)
            .map(|(&c, &a)| c as f64 * sphere_volume(a))
            .sum();
        let phi_actual = solid / volume;

        let rho = match (p.rho, p.stokes) {
            (Some(_), Some(_)) => {
                return Err(SimError::field(
                    "particles.stokes",
                    "give either particles.rho or particles.stokes, not both (stokes sets rho)",
                ))
            }
            (Some(rho), None) => {
                positive("particles.rho", rho)?;
                rho
            }
            (None, Some(_)) if gdot_max == 0.0 => {
                return Err(SimError::field(
                    "particles.stokes",
                    "a scene without shear has no Stokes number: give particles.rho",
                ))
            }
            (None, Some(st)) => {
                positive("particles.stokes", st)?;
                st * file.fluid.eta / (a_min * a_min * gdot_max)
            }
            (None, None) => 1.0,
        };
        let stokes = rho * a_min * a_min * gdot_max / file.fluid.eta;
        let mut warnings = Vec::new();
        if stokes >= 0.1 {
            let msg = format!(
                "Stokes number rho a^2 gdot_max / eta = {stokes:.3} >= 0.1: inertia is not negligible (thesis 4.2.4)");
            if strict {
                let field = if p.stokes.is_some() {
                    "particles.stokes"
                } else {
                    "particles.rho"
                };
                return Err(SimError::field(field, msg));
            }
            warnings.push(msg);
        }
        let thermal = (file.fluid.kt > 0.0)
            .then(|| ThermalScales::new(file.fluid.kt, file.fluid.eta, rho, a_thermal, gdot_max));
        if let Some(w) = thermal.as_ref().and_then(ThermalScales::warning) {
            warnings.push(w);
        }
        if let Some(w) = thermal
            .as_ref()
            .and_then(|t| thermal_scales::soft_contact_warning(t.kt, file.forces.k_n, a_min))
        {
            warnings.push(w);
        }
        let composition = file
            .particles
            .mixture
            .as_ref()
            .map(|m| Composition::of(m, &counts, file.fluid.eta, gdot_max, file.fluid.kt));
        let timestep = TimeStep::for_file(&file, rho, gdot_max);
        let relaxation = TimeStep::relaxation_time(&file, rho);
        if let Some(w) = thermal
            .is_some()
            .then(|| thermal_scales::unresolved_relaxation_warning(timestep.dt, relaxation))
            .flatten()
        {
            warnings.push(w);
        }
        let mut scene = Scene {
            thermal,
            composition,
            timestep,
            box_len: [b.l_x, b.l_y, b.l_z],
            counts,
            phi_actual,
            n_bins,
            interaction_range,
            rho,
            stokes,
            memory_bytes,
            warnings,
            profile,
            file,
        };
        let cost = RunCost::new(&scene);
        scene.warnings.extend(cost.check()?);
        Ok(scene)
    }

    /// Total number of particles.
    pub fn n_particles(&self) -> usize {
        self.counts.iter().sum()
    }

    /// Radius of every particle, species by species (species 0 first).
    pub fn particle_radii(&self) -> Vec<f64> {
        let radii = &self.file.particles.radii;
        self.counts
            .iter()
            .zip(radii)
            .flat_map(|(&c, &a)| std::iter::repeat_n(a, c))
            .collect()
    }

    /// Species index of every particle, in the order of [`Scene::particle_radii`].
    pub fn particle_species(&self) -> Vec<u16> {
        self.counts
            .iter()
            .enumerate()
            .flat_map(|(s, &c)| std::iter::repeat_n(s as u16, c))
            .collect()
    }

    /// Number-weighted mean radius, the `a` of Theta (docs/physics.md section 6).
    pub fn mean_radius(&self) -> f64 {
        let radii = self.particle_radii();
        radii.iter().sum::<f64>() / radii.len() as f64
    }

    /// The imposed rate of a homogeneous-shear scene (docs/physics.md section 10), `None`
    /// for a profile.
    pub fn shear_rate(&self) -> Option<f64> {
        self.file.fluid.shear_rate
    }

    /// Largest shear rate of the streaming profile.
    pub fn gdot_max(&self) -> f64 {
        self.profile.max_abs_shear_rate()
    }

    /// Time steps per unit of the run's clock (strain, or Brownian time without flow; see
    /// [`Scene::clock_rate`]).
    pub fn steps_per_strain(&self) -> f64 {
        1.0 / (self.clock_rate() * self.timestep.dt)
    }

    /// The rate of the run's clock, in which its lengths (`run.sample_strain`,
    /// `window_strain`, `max_strain`) are counted: the largest shear rate (the clock is the
    /// strain), or without flow `1 / tau_B` (the clock counts Brownian times).
    pub fn clock_rate(&self) -> f64 {
        match (self.gdot_max(), &self.thermal) {
            (0.0, Some(t)) => 1.0 / t.tau_b,
            (g, _) => g,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(particles: &str) -> Result<Scene, SimError> {
        Scene::from_toml(
            &format!(
                "[box]\nl_x = 8.0\nl_y = 12.0\nl_z = 8.0\n[particles]\nphi = 0.5\n{particles}\n\
                 [fluid]\nprofile = \"0.1*sin(2*pi*y/L)\"\n"
            ),
            false,
        )
    }

    #[test]
    fn absent_fractions_are_equal_numbers_of_the_radii_given() {
        let one = scene("radii = [1.0]").unwrap();
        assert_eq!(one.file.particles.fractions, vec![1.0]);
        assert_eq!(one.counts.len(), 1);
        let three = scene("radii = [1.0, 1.2, 1.4]").unwrap();
        assert_eq!(three.file.particles.fractions, vec![1.0 / 3.0; 3]);
        let (lo, hi) = (
            three.counts.iter().min().unwrap(),
            three.counts.iter().max().unwrap(),
        );
        assert!(hi - lo <= 1, "{:?}", three.counts);
        // The default radii keep the fractions they always had.
        assert_eq!(scene("").unwrap().file.particles.fractions, vec![0.5, 0.5]);
    }

    #[test]
    fn a_box_of_fewer_than_the_minimum_grain_diameters_is_refused_naming_the_axis() {
        // Grains of radius 7 in an 8 x 12 x 8 box: 0.57 diameters along x.
        let message = scene("radii = [1.0, 1.4, 5.0, 7.0]")
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("box.l_x") && message.contains("diameters of the largest radius"),
            "{message}"
        );
        // Radius 1.4 in the same box: 2.86 diameters, at or above the minimum.
        assert!(scene("radii = [1.0, 1.4]").is_ok());
        // Radius 1.7: 8 / 3.4 = 2.35 diameters along x, below 2.5.
        let below = scene("radii = [1.0, 1.7]").unwrap_err().to_string();
        assert!(
            below.contains("box.l_x") && below.contains("2.35"),
            "{below}"
        );
    }

    #[test]
    fn fractions_must_sum_to_one() {
        let message = scene("fractions = [0.3, 0.3]").unwrap_err().to_string();
        assert!(
            message.contains("sum to 1") && message.contains("sum 0.6"),
            "{message}"
        );
        assert!(scene("radii = [1.0, 1.2, 1.4]\nfractions = [0.1, 0.2, 0.7]").is_ok());
    }
}
