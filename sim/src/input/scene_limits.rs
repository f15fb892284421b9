//! What a scene may ask for: one table of the accepted range of every scene value whose
//! extreme makes a run impossible (a counter that saturates, an allocation that overflows,
//! a step that never ends) or meaningless (a state no packing reaches, a flow the bins
//! cannot resolve), each bound with its reason, and the few limits that involve several
//! values at once. [`crate::input::scene::Scene`] applies them after the field-by-field
//! checks (signs, finiteness), before anything is derived from the values; the cost of a
//! run is limited separately by [`crate::input::run_cost`].
use crate::error::SimError;
use crate::input::flow_profile::FlowProfile;
use crate::input::scene_file::{ParticleSection, SceneFile};

/// The accepted range `[min, max]` of one scene value, in its own units.
struct Range {
    field: &'static str,
    value: fn(&SceneFile) -> Option<f64>,
    min: f64,
    max: f64,
    /// Why values outside the range are refused.
    why: &'static str,
}

/// Densest volume fraction accepted: the densest the initial packing was measured to
/// reach (`cargo run --release -p sim --example densest_packing -- 24 0.005`, cubic box of
/// side 24, three seeds per phi, 2026-12-02, machine shared): radii 1 : 1.4 (the default)
/// packed at 0.640 (1 of 3 seeds, 17 s at N = 1128), 1 : 3 at 0.640 (2 of 3), 1 : 1 at
/// 0.630; at 0.645 every seed of every set jammed. Between 0.63 and 0.64 a packing may
/// still jam for some seeds and radii; the run then stops at once saying so. (0.74 is
/// reached only by the crystal, which a random packing never finds.)
pub const PHI_MAX: f64 = 0.64;

/// Densest volume fraction accepted for a colloid-grain mixture (`[particles.mixture]`):
/// radii five times apart pack denser than one species, the small spheres filling the large
/// ones' voids (thesis section 5.3). Measured with the run's packer and gap in the thesis'
/// box (`cargo run --release -p sim --example densest_packing -- 66 0.02 mixture ...`, seed
/// 1, the default species, 2026-12-05, machine shared): alpha 0.4 packed at 0.70 (not
/// 0.72), 0.6 at 0.671-0.73 (not 0.75), 0.7 at 0.70 and 0.72, 0.8 at 0.68 and 0.70, 0.9 at
/// 0.66 and 0.68, in 2-50 s (N 3300-20,000). Nearer one species less: alpha 0.95 packed
/// at 0.66 and jammed at 0.68, alpha 0.2 (box 46) did not pack at 0.688. A composition
/// that does not pack ends with the packer's error: within seconds when it jams, after its
/// iteration cap (3-7 minutes at N ~ 1e4-2e4) when it only fails to clear its overlaps.
pub const MIXTURE_PHI_MAX: f64 = 0.70;

/// The densest volume fraction accepted for `particles`: that of
/// [`densest_mixture_phi`] for a colloid-grain mixture, [`PHI_MAX`] otherwise.
pub fn densest_phi(particles: &ParticleSection) -> f64 {
    particles
        .mixture
        .as_ref()
        .map_or(PHI_MAX, |m| densest_mixture_phi(m.alpha))
}

/// The densest volume fraction accepted for a colloid-grain mixture of grain share
/// `alpha`: [`MIXTURE_PHI_MAX`] with both species present, [`PHI_MAX`] for one alone.
pub fn densest_mixture_phi(alpha: f64) -> f64 {
    if alpha > 0.0 && alpha < 1.0 {
        MIXTURE_PHI_MAX
    } else {
        PHI_MAX
    }
}

/// Largest ratio of the largest to the smallest radius: beyond it the cell list, sized by
/// the largest pair, holds thousands of small spheres per cell and the small spheres'
/// time step is the large ones' divided by the ratio to the power 3/2.
pub const RADII_RATIO_MAX: f64 = 100.0;

/// Fewest largest diameters `2 a_max` along each box axis, for mixtures of very different
/// sizes (thesis chapter 5: grains 5-7 times the colloids). The minimum-image limit, twice
/// the largest pair's reach plus the skin, is checked where the scene is built
/// (`Scene::from_file`) and allows about 2.1 diameters; a box that narrow holds two grains
/// across, whose structure is then set by their own periodic images. 2.5 is the most the
/// shipped 8-wide boxes of radius 1.4 (2.9 diameters) allow; thesis-sized mixtures need
/// several times more for their statistics, which this bound does not judge.
pub const BOX_DIAMETERS_MIN: f64 = 2.5;

/// Most species (radii): the force field holds constants for every pair of species.
pub const SPECIES_MAX: usize = 64;

/// Most bins along y: each bin holds per-snapshot sums of every observable, and a bin
/// much narrower than a particle holds no particle centre in most snapshots.
pub const BINS_MAX: f64 = 10_000.0;

/// Most snapshots in one steady-state window (`window_strain / sample_strain`): the
/// window's snapshot counter must fill within a run.
pub const SAMPLES_PER_WINDOW_MAX: f64 = 1e6;

/// Smallest accepted ratio of the range of the bin-averaged streaming velocity to its
/// range over y. A sine averaged over bins of a quarter of its wavelength keeps 0.9 of its
/// range, over half a wavelength 0.64 (or 0, depending on the phase); averaged over a whole
/// wavelength nothing: the bins then see no flow at all.
pub const BIN_RESOLUTION_MIN: f64 = 0.5;

/// Quadrature points per bin of the bin-averaged velocity.
const POINTS_PER_BIN: usize = 16;

const RANGES: &[Range] = &[
    Range {
        field: "box.l_x",
        value: |f| Some(f.box_.l_x),
        min: 0.0,
        max: 1e5,
        why: "a box beyond 1e5 a holds more particles than any machine's memory, or so few \
              that the box is empty",
    },
    Range {
        field: "box.l_y",
        value: |f| Some(f.box_.l_y),
        min: 0.0,
        max: 1e5,
        why: "a box beyond 1e5 a holds more particles than any machine's memory, or so few \
              that the box is empty",
    },
    Range {
        field: "box.l_z",
        value: |f| Some(f.box_.l_z),
        min: 0.0,
        max: 1e5,
        why: "a box beyond 1e5 a holds more particles than any machine's memory, or so few \
              that the box is empty",
    },
    Range {
        field: "forces.k_n",
        value: |f| Some(f.forces.k_n),
        min: 1e-2,
        max: 1e8,
        why: "the contact step 2 sqrt(m / k_n) shrinks as 1 / sqrt(k_n): the studied \
              stiffnesses are 1e3-1e6 (README, Stability), and outside [1e-2, 1e8] spheres \
              either pass through each other or the run needs billions of steps",
    },
    Range {
        field: "forces.xi_min",
        value: |f| Some(f.forces.xi_min),
        min: 1e-8,
        max: f64::INFINITY,
        why: "the implicit step's strain per step is capped at xi_min, so the steps per unit \
              strain are 1 / xi_min; the studied values are 1e-5-1e-2",
    },
    Range {
        field: "run.dt_factor",
        value: |f| Some(f.run.dt_factor),
        min: 1e-3,
        max: 1e3,
        why: "it multiplies the automatic step: below 1e-3 a run takes a thousand times its \
              steps, above 1e3 every stability limit is exceeded",
    },
    Range {
        field: "run.dt",
        value: |f| f.run.dt,
        min: 1e-12,
        max: f64::INFINITY,
        why: "a step below 1e-12 advances no strain in any run length",
    },
    Range {
        field: "run.dt_safety",
        value: |f| Some(f.run.dt_safety),
        min: 1e-3,
        max: 1.0,
        why: "it is the fraction of the tightest stability limit the automatic step uses: \
              above 1 the step is beyond that limit by definition",
    },
    Range {
        field: "run.max_strain",
        value: |f| Some(f.run.max_strain),
        min: 0.0,
        max: 1e6,
        why: "the seeds reach a steady state within strain 30",
    },
    Range {
        field: "run.snapshots",
        value: |f| Some(f.run.snapshots as f64),
        min: 1.0,
        max: 1e8,
        why: "the seeds average 1000 snapshots; the snapshot counters are sized for 1e8",
    },
    Range {
        field: "run.blocks",
        value: |f| Some(f.run.blocks as f64),
        min: 2.0,
        max: 1e4,
        why: "every block holds the sums of every observable in every bin",
    },
];

/// `value` in a message: plain for moderate magnitudes, in e-notation for extreme ones
/// (`1e300`, not 301 digits).
pub fn show(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude != 0.0 && !(1e-3..1e5).contains(&magnitude) {
        format!("{value:e}")
    } else {
        format!("{value:?}")
    }
}

fn outside(field: &str, value: f64, min: f64, max: f64, why: &str) -> SimError {
    let range = match (min > 0.0, max.is_finite()) {
        (true, true) => format!("[{}, {}]", show(min), show(max)),
        (false, true) => format!("at most {}", show(max)),
        _ => format!("at least {}", show(min)),
    };
    SimError::field(
        field,
        format!(
            "{} is outside the accepted range ({range}): {why}",
            show(value)
        ),
    )
}

/// Checks every value of [`RANGES`] and the limits that involve several values: the
/// species, the radii ratio, the number of bins and the snapshots per steady-state window.
pub fn check(file: &SceneFile) -> Result<(), SimError> {
    for r in RANGES {
        if let Some(v) = (r.value)(file) {
            if !(v >= r.min && v <= r.max) {
                return Err(outside(r.field, v, r.min, r.max, r.why));
            }
        }
    }
    let radii = &file.particles.radii;
    if radii.len() > SPECIES_MAX {
        return Err(SimError::field(
            "particles.radii",
            format!(
                "lists {} radii, more than {SPECIES_MAX}: the force field holds constants for \
                 every pair of species; describe a size distribution by at most {SPECIES_MAX} \
                 species",
                radii.len()
            ),
        ));
    }
    let a_max = radii.iter().cloned().fold(0.0, f64::max);
    let a_min = radii.iter().cloned().fold(f64::INFINITY, f64::min);
    if a_max / a_min > RADII_RATIO_MAX {
        return Err(outside(
            "particles.radii",
            a_max / a_min,
            1.0,
            RADII_RATIO_MAX,
            "the ratio of the largest to the smallest radius makes the small spheres' step \
             and the cell list's size unworkable",
        ));
    }
    check_box_holds_the_largest_pair(file, a_max)?;
    let r = &file.run;
    let bins = file.box_.l_y / r.bin_width;
    if bins > BINS_MAX {
        return Err(SimError::field(
            "run.bin_width",
            format!(
                "{} makes {} bins of box.l_y = {}, more than {}: a bin much narrower than a \
                 particle holds no centre in most snapshots",
                show(r.bin_width),
                show(bins),
                show(file.box_.l_y),
                show(BINS_MAX)
            ),
        ));
    }
    let per_window = r.window_strain / r.sample_strain;
    if !(1.0..=SAMPLES_PER_WINDOW_MAX).contains(&per_window) {
        return Err(SimError::field(
            "run.window_strain",
            format!(
                "run.window_strain / run.sample_strain = {} / {} = {} snapshots per \
                 steady-state window; it must lie in [1, {}] (the seeds: 100)",
                show(r.window_strain),
                show(r.sample_strain),
                show(per_window),
                show(SAMPLES_PER_WINDOW_MAX)
            ),
        ));
    }
    Ok(())
}

/// Fails when an axis of the box is shorter than [`BOX_DIAMETERS_MIN`] diameters of the
/// largest species `a_max`, naming the axis' field.
fn check_box_holds_the_largest_pair(file: &SceneFile, a_max: f64) -> Result<(), SimError> {
    let b = &file.box_;
    for (field, l) in [("box.l_x", b.l_x), ("box.l_y", b.l_y), ("box.l_z", b.l_z)] {
        let diameters = l / (2.0 * a_max);
        if diameters < BOX_DIAMETERS_MIN {
            return Err(SimError::field(
                field,
                format!(
                    "{} holds {:.2} diameters of the largest radius {}, fewer than \
                     {BOX_DIAMETERS_MIN}: the largest spheres would be ordered by their own \
                     periodic images",
                    show(l),
                    diameters,
                    show(a_max)
                ),
            ));
        }
    }
    Ok(())
}

/// Fails when nothing drives the particles: drag off in a profile flow, whose only
/// coupling to `fluid.profile` is the drag (the run would end with P <= 0 in every bin).
/// Checked by a run and by `--check`, not by the scene: scenes without drag are how the
/// other force terms are tested in isolation. A scene at rest (a Brownian suspension
/// without flow, `gdot_max` = 0: its flow's largest shear rate) has no flow to drive and
/// passes.
pub fn check_driven(file: &SceneFile, gdot_max: f64) -> Result<(), SimError> {
    if !file.forces.drag && file.fluid.shear_rate.is_none() && gdot_max > 0.0 {
        return Err(SimError::field(
            "forces.drag",
            "is off, but the drag is what drives a profile flow: without it the particles \
             never feel fluid.profile (P <= 0 everywhere); switch it on, or use \
             fluid.shear_rate for flow driven by the Lees-Edwards images",
        ));
    }
    Ok(())
}

/// Fails when `n_bins` bins of `profile` average its velocity away (see
/// [`BIN_RESOLUTION_MIN`]): a wavelength at or below the bin width.
pub fn check_bin_resolution(profile: &FlowProfile, n_bins: usize) -> Result<(), SimError> {
    let width = profile.l_y() / n_bins as f64;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut mean_lo, mut mean_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..n_bins {
        let mut sum = 0.0;
        for q in 0..POINTS_PER_BIN {
            let u = profile.u(width * (k as f64 + (q as f64 + 0.5) / POINTS_PER_BIN as f64));
            (lo, hi) = (lo.min(u), hi.max(u));
            sum += u;
        }
        let mean = sum / POINTS_PER_BIN as f64;
        (mean_lo, mean_hi) = (mean_lo.min(mean), mean_hi.max(mean));
    }
    let kept = (mean_hi - mean_lo) / (hi - lo);
    if kept < BIN_RESOLUTION_MIN {
        return Err(SimError::field(
            "run.bin_width",
            format!(
                "{} is too wide for the profile `{}`: averaged over the bins its velocity keeps \
                 {:.0} % of its range (at least {:.0} % needed), so the bins would see \
                 (almost) no flow; use bins narrower than a quarter of its shortest wavelength",
                show(width),
                profile.expr(),
                100.0 * kept,
                100.0 * BIN_RESOLUTION_MIN
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extreme_values_are_shown_in_e_notation() {
        assert_eq!(show(1e300), "1e300");
        assert_eq!(show(1e-300), "1e-300");
        assert_eq!(show(12.0), "12.0");
        assert_eq!(show(0.05), "0.05");
        assert_eq!(show(1e8), "1e8");
        assert_eq!(show(f64::INFINITY), "inf");
    }

    #[test]
    fn a_wavelength_of_one_bin_is_refused_and_four_bins_accepted() {
        let l_y = 24.0;
        let one_bin = FlowProfile::new("0.1*cos(24*pi*y/L)", l_y).unwrap();
        let message = check_bin_resolution(&one_bin, 12).unwrap_err().to_string();
        assert!(message.contains("too wide for the profile"), "{message}");
        let four_bins = FlowProfile::new("0.1*cos(6*pi*y/L)", l_y).unwrap();
        assert!(check_bin_resolution(&four_bins, 12).is_ok());
        assert!(check_bin_resolution(&FlowProfile::simple_shear(0.01, l_y), 3).is_ok());
    }
}
