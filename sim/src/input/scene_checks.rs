//! Field-by-field validation of a scene file's sections (docs/physics.md section 1), before
//! anything is derived from them: the name, the particles (a mixture expanded, absent
//! number fractions made equal), the fluid (kT completed from a Peclet number), the force
//! terms and the run's settings. Each refusal names the field.
use crate::error::SimError;
use crate::input::composition;
use crate::input::scene_file::{MixtureSection, SceneFile};
use crate::input::scene_limits::{densest_phi, show, PHI_MAX};
use crate::input::thermal_scales;
use schema::scene_name;

/// Largest accepted `|sum of number fractions - 1|` (room for decimal round-off such as
/// `[0.1, 0.2, 0.7]`).
const FRACTION_SUM_TOLERANCE: f64 = 1e-9;

pub(crate) fn positive(field: &str, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SimError::field(
            field,
            format!("must be a positive finite number, got {}", show(v)),
        ))
    }
}

/// Checks the sections of `file`, filling in what validation completes (a mixture's
/// species, equal number fractions, kT from a Peclet number); returns the radius of the
/// Brownian scales: the smallest, or a mixture's colloid radius even when no colloids are
/// placed (alpha = 1), so that `fluid.peclet` is Pe_c at every composition.
pub fn check_sections(file: &mut SceneFile) -> Result<f64, SimError> {
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
    let densest = densest_phi(p);
    if !(p.phi > 0.0 && p.phi <= densest) {
        let measured = if densest > PHI_MAX {
            "for the thesis' colloid-grain mixtures"
        } else {
            "and jams at 0.645 (measured for radii 1 : 1, 1 : 1.4 and 1 : 3; only a crystal \
             is denser)"
        };
        return Err(SimError::field(
            "particles.phi",
            format!(
                "must lie in (0, {densest}]: the initial packing reaches {densest} {measured}, \
                 got {}",
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
    if file.fluid.kt > 0.0 && file.forces.lubrication && file.forces.xi_taper.is_none() {
        file.forces.xi_taper = Some(file.forces.xi_max);
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
    if !(f.taper_width().is_finite() && f.taper_width() >= 0.0) {
        return Err(SimError::field(
            "forces.xi_taper",
            format!(
                "must be >= 0 (0 = the sharp cut at forces.xi_max), got {}",
                show(f.taper_width())
            ),
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
    Ok(a_thermal)
}
