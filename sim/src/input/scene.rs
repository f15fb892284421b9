//! Scene files (TOML): the box, particles, fluid, force terms and run length, validated
//! field by field, with the derived quantities a run needs (N, Stokes number, bins).
use crate::error::SimError;
use crate::forces::force_field::ForceField;
use crate::input::composition::Composition;
use crate::input::flow_profile::FlowProfile;
use crate::input::memory_estimate;
use crate::input::run_cost::RunCost;
use crate::input::scene_checks::{self, positive};
use crate::input::scene_limits;
use crate::input::thermal_scales::{self, ThermalScales};
use crate::integrate::timestep::TimeStep;
use crate::state::particles::sphere_volume;
use std::path::Path;

pub use crate::input::scene_file::{
    BoxSection, FluidSection, ForceSection, MixtureSection, ParticleSection, RunSection, SceneFile,
};

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
    /// The force terms and pair constants, built once here for the time step and the run.
    pub force_field: ForceField,
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

/// Bins along y: `l_y / bin_width`, which must be a whole number of at least 3.
fn bin_count(l_y: f64, bin_width: f64) -> Result<usize, SimError> {
    let bins = l_y / bin_width;
    let n_bins = bins.round() as usize;
    if n_bins < 3 || (bins - bins.round()).abs() > 1e-6 * bins {
        return Err(SimError::field(
            "run.bin_width",
            format!("must divide box.l_y into at least 3 bins: {l_y} / {bin_width} = {bins}"),
        ));
    }
    Ok(n_bins)
}

/// The largest pair interaction distance of `file`'s particles, once the box is checked to
/// hold it: twice of it plus the skin along every axis (the minimum-image convention), and
/// three times along y in a sheared box (three neighbour cells).
fn check_box_reach(file: &SceneFile) -> Result<f64, SimError> {
    let (b, p, f, r) = (&file.box_, &file.particles, &file.forces, &file.run);
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
    Ok(interaction_range)
}

/// The particles of each species in a box of `volume` at the section's volume fraction
/// and number fractions; at least 2 in all.
fn particle_counts(p: &ParticleSection, volume: f64) -> Result<Vec<usize>, SimError> {
    let fraction_sum: f64 = p.fractions.iter().sum();
    let fractions: Vec<f64> = p.fractions.iter().map(|x| x / fraction_sum).collect();
    let mean_particle_volume: f64 = fractions
        .iter()
        .zip(&p.radii)
        .map(|(x, &a)| x * sphere_volume(a))
        .sum();
    let n_total = (p.phi * volume / mean_particle_volume).round() as usize;
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
    Ok(counts)
}

/// The particle density: `particles.rho`, or the one that gives the target Stokes number
/// `particles.stokes` at the profile's largest shear rate `gdot_max` (smallest radius
/// `a_min`, fluid viscosity `eta`); 1 when neither is given.
fn density(p: &ParticleSection, eta: f64, a_min: f64, gdot_max: f64) -> Result<f64, SimError> {
    Ok(match (p.rho, p.stokes) {
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
            st * eta / (a_min * a_min * gdot_max)
        }
        (None, None) => 1.0,
    })
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
        let a_thermal = scene_checks::check_sections(&mut file)?;
        let (b, p, r) = (&file.box_, &file.particles, &file.run);
        let a_min = p.radii.iter().cloned().fold(f64::INFINITY, f64::min);
        scene_limits::check(&file)?;
        let n_bins = bin_count(b.l_y, r.bin_width)?;
        let profile = streaming_flow(&file.fluid, b.l_y)?;
        scene_limits::check_bin_resolution(&profile, n_bins)?;
        let gdot_max = profile.max_abs_shear_rate();

        let interaction_range = check_box_reach(&file)?;
        let volume = b.l_x * b.l_y * b.l_z;
        let counts = particle_counts(p, volume)?;
        let memory_bytes = memory_estimate::run_bytes(
            counts.iter().sum(),
            [b.l_x, b.l_y, b.l_z],
            interaction_range + r.skin,
        );
        let solid: f64 = counts
            .iter()
            .zip(&p.radii)
            .map(|(&c, &a)| c as f64 * sphere_volume(a))
            .sum();
        let phi_actual = solid / volume;

        let rho = density(p, file.fluid.eta, a_min, gdot_max)?;
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
        if let Some(w) = thermal
            .as_ref()
            .and_then(|t| thermal_scales::inertia_warning(t.kt, file.fluid.eta, rho, a_min))
        {
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
            .map(|m| Composition::of(m, &counts, file.fluid.eta, gdot_max, file.fluid.kt))
            .map(|c| c.check(counts.iter().sum()).map(|()| c))
            .transpose()?;
        let force_field = ForceField::from_file(&file);
        let timestep = TimeStep::choose(&file, (rho, gdot_max), &counts, &force_field);
        if let Some(w) = timestep.brownian_warning() {
            warnings.push(w);
        }
        let mut scene = Scene {
            thermal,
            composition,
            force_field,
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
        scene.warnings.extend(scene.cost().check()?);
        Ok(scene)
    }

    /// Fails when the run of this scene needs more memory than this machine has (see
    /// [`Scene::memory_bytes`]); passes when the machine's memory is unknown.
    pub fn check_fits_here(&self) -> Result<(), SimError> {
        match memory_estimate::physical_bytes().filter(|&machine| self.memory_bytes > machine) {
            None => Ok(()),
            Some(machine) => {
                let [l_x, l_y, l_z] = self.box_len;
                Err(SimError::field(
                    "box",
                    format!(
                        "{} particles (phi = {} in a box of {l_x} x {l_y} x {l_z}) need about {} \
                         of memory, more than this machine's {}; use a smaller box",
                        self.n_particles(),
                        self.file.particles.phi,
                        memory_estimate::describe(self.memory_bytes),
                        memory_estimate::describe(machine)
                    ),
                ))
            }
        }
    }

    /// The cost of a run of this scene at its time step ([`RunCost`]).
    pub fn cost(&self) -> RunCost {
        RunCost::new(
            self.steps_per_strain(),
            self.n_particles(),
            &self.file.run,
            self.thermal.is_some(),
        )
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
        self.clock_and_rate().1
    }

    /// What the run's clock counts (see [`Scene::clock_rate`]).
    pub fn clock(&self) -> Clock {
        self.clock_and_rate().0
    }

    fn clock_and_rate(&self) -> (Clock, f64) {
        match (self.gdot_max(), &self.thermal) {
            (0.0, Some(t)) => (Clock::BrownianTimes, 1.0 / t.tau_b),
            (g, _) => (Clock::Strain, g),
        }
    }
}

/// What a run's clock counts: the strain under flow, Brownian times `tau_B` without it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    Strain,
    BrownianTimes,
}

impl Clock {
    /// A reading of the clock for a log: `strain 1.25` or `12.00 tau_B`.
    pub fn show(self, value: f64) -> String {
        match self {
            Clock::Strain => format!("strain {value:.2}"),
            Clock::BrownianTimes => format!("{value:.2} tau_B"),
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

    /// A scene too large for any host is a valid scene (reading it does not depend on the
    /// host); the host's check refuses it, and passes a small one.
    #[test]
    fn the_host_check_is_separate_from_reading() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/scenes");
        let large = Scene::from_path(
            std::path::Path::new(&format!("{dir}/bad/box_too_large_for_memory.toml")),
            true,
        )
        .expect("a scene of 4e8 particles is read");
        assert!(large.memory_bytes > 4e11, "{}", large.memory_bytes);
        if memory_estimate::physical_bytes().is_some_and(|m| m < large.memory_bytes) {
            let message = large.check_fits_here().unwrap_err().to_string();
            assert!(message.contains("more than this machine's"), "{message}");
        }
        let quick = Scene::from_path(
            std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/quick.toml")),
            true,
        )
        .unwrap();
        assert!(quick.check_fits_here().is_ok());
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
