//! Colloid-grain mixtures given by their composition (thesis section 5.1,
//! docs/physics.md section 12): the grain share of the solid volume
//! `alpha = V_g / (V_c + V_g)` expands into the radii and number fractions of
//! `[particles]`, and with the thesis' protocol (particles added at fixed liquid volume to a
//! suspension of one species) into the volume fraction too.
//!
//! ```toml
//! [particles.mixture]
//! alpha = 0.7                                  # grain share of the solid volume
//! colloid_radii = [1.0, 1.4]                   # the defaults
//! grain_radii = [5.0, 7.0]
//! initial = { species = "grains", phi = 0.55 } # optional: phi follows from alpha
//! ```
//!
//! Within each species its radii share the species' volume equally (radii 1 : 1.4 at equal
//! volume, as the colloidal flow curves). A species of zero volume (`alpha` 0 or 1) is left
//! out. The expansion is written into `particles.radii`, `fractions` and `phi`, so a scene
//! written back out and read again expands to the same values, which are then checked.
use crate::error::SimError;
use crate::input::scene_file::{default_colloid_radii, ParticleSection};
pub use crate::input::scene_file::{InitialSuspension, MixtureSection, Species};
use crate::input::scene_limits::{densest_mixture_phi, show, PHI_MAX};
use crate::input::thermal_scales::peclet_number;
use serde::{Deserialize, Serialize};

/// Largest relative disagreement accepted between a written-out value and the expansion
/// (room for decimal round-off).
const AGREEMENT: f64 = 1e-9;

impl MixtureSection {
    /// Volume fraction after adding the other species at fixed liquid volume to the initial
    /// suspension at `phi0`: with `s` the initial species' share of the mixture's solid
    /// volume (`1 - alpha` for colloids, `alpha` for grains), the solid volume grows from
    /// `phi0` to `phi0 / s` per unit of initial volume while the liquid stays `1 - phi0`,
    /// so `phi = phi0 / (phi0 + (1 - phi0) s)` (thesis section 5.1: from 0.55, alpha = 0.1,
    /// 0.3, 0.5 give 0.576, 0.636, 0.71).
    pub fn fixed_liquid_phi(&self, initial: InitialSuspension) -> f64 {
        let share = match initial.species {
            Species::Colloids => 1.0 - self.alpha,
            Species::Grains => self.alpha,
        };
        initial.phi / (initial.phi + (1.0 - initial.phi) * share)
    }

    /// The colloid radius `a_c`: the smallest colloid radius (units a).
    pub fn colloid_radius(&self) -> f64 {
        self.colloid_radii
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
    }

    /// The grain radius `a_g`: the smallest grain radius (thesis: `a_g / a_c = 5`).
    pub fn grain_radius(&self) -> f64 {
        self.grain_radii
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
    }

    /// The radii and number fractions of the mixture: each radius `r` of a species of
    /// volume share `v` and `n` radii holds the volume `v / n`, so its number is
    /// proportional to `v / (n r^3)`.
    pub fn species(&self) -> (Vec<f64>, Vec<f64>) {
        let mut radii = Vec::new();
        let mut numbers = Vec::new();
        for (set, share) in [
            (&self.colloid_radii, 1.0 - self.alpha),
            (&self.grain_radii, self.alpha),
        ] {
            if share > 0.0 {
                for &r in set {
                    radii.push(r);
                    numbers.push(share / (set.len() as f64 * r.powi(3)));
                }
            }
        }
        let total: f64 = numbers.iter().sum();
        (radii, numbers.iter().map(|n| n / total).collect())
    }

    fn validate(&self) -> Result<(), SimError> {
        let field =
            |name: &str, m: String| SimError::field(&format!("particles.mixture.{name}"), m);
        if !(0.0..=1.0).contains(&self.alpha) {
            return Err(field(
                "alpha",
                format!(
                    "is the grain share of the solid volume and must lie in [0, 1], got {}",
                    show(self.alpha)
                ),
            ));
        }
        for (name, set) in [
            ("colloid_radii", &self.colloid_radii),
            ("grain_radii", &self.grain_radii),
        ] {
            if set.is_empty() || set.iter().any(|r| !(r.is_finite() && *r > 0.0)) {
                return Err(field(
                    name,
                    format!("needs at least one positive finite radius, got {set:?}"),
                ));
            }
        }
        let largest_colloid = self.colloid_radii.iter().cloned().fold(0.0, f64::max);
        if self.grain_radius() <= largest_colloid {
            return Err(field(
                "grain_radii",
                format!(
                    "every grain must be larger than every colloid, got grains {:?} and \
                     colloids {:?}",
                    self.grain_radii, self.colloid_radii
                ),
            ));
        }
        if let Some(initial) = self.initial {
            if !(initial.phi > 0.0 && initial.phi <= PHI_MAX) {
                return Err(field(
                    "initial.phi",
                    format!("must lie in (0, {PHI_MAX}], got {}", show(initial.phi)),
                ));
            }
            let phi = self.fixed_liquid_phi(initial);
            let densest = densest_mixture_phi(self.alpha);
            if phi > densest {
                return Err(field(
                    "alpha",
                    format!(
                        "adding {} at fixed liquid volume to {} at phi = {} gives phi = {}, \
                         beyond the densest packing the runs start from ({densest})",
                        initial.species.other().name(),
                        initial.species.name(),
                        initial.phi,
                        show(phi)
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Whether `a` and `b` agree to the written-out round-off.
fn agree(a: f64, b: f64) -> bool {
    (a - b).abs() <= AGREEMENT * b.abs().max(1e-300)
}

/// Expands `particles.mixture` (when present) into `particles.radii`, `fractions` and,
/// with an initial suspension, `phi`. Values already there must be the expansion's (a
/// scene written back out), or the error says which field to drop. Without a mixture,
/// absent radii become the default pair 1 : 1.4.
pub fn expand(particles: &mut ParticleSection) -> Result<(), SimError> {
    let Some(mixture) = particles.mixture.clone() else {
        if particles.radii.is_empty() {
            particles.radii = default_colloid_radii();
        }
        return Ok(());
    };
    mixture.validate()?;
    let (radii, fractions) = mixture.species();
    for (name, given, expanded) in [
        ("radii", &particles.radii, &radii),
        ("fractions", &particles.fractions, &fractions),
    ] {
        let same =
            given.len() == expanded.len() && given.iter().zip(expanded).all(|(a, b)| agree(*a, *b));
        if !given.is_empty() && !same {
            return Err(SimError::field(
                &format!("particles.{name}"),
                format!(
                    "are set by particles.mixture; give the mixture or the species, not both \
                     (or give them as the mixture expands: {expanded:?})"
                ),
            ));
        }
    }
    if let Some(initial) = mixture.initial {
        let phi = mixture.fixed_liquid_phi(initial);
        if particles.phi != 0.0 && !agree(particles.phi, phi) {
            return Err(SimError::field(
                "particles.phi",
                format!(
                    "is set by particles.mixture.initial (alpha = {} added at fixed liquid \
                     volume gives phi = {phi}), got {}; drop one of them",
                    mixture.alpha, particles.phi
                ),
            ));
        }
        particles.phi = phi;
    }
    particles.radii = radii;
    particles.fractions = fractions;
    Ok(())
}

/// What a mixture's scene realises and its Peclet numbers (thesis section 5.1): the
/// integer particle counts set the composition actually run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Composition {
    /// Grain share of the solid volume asked for.
    pub alpha: f64,
    /// Grain share of the solid volume of the particles placed.
    pub alpha_actual: f64,
    /// Colloid radius `a_c` ([`MixtureSection::colloid_radius`], units a).
    pub a_c: f64,
    /// Grain radius `a_g` ([`MixtureSection::grain_radius`]).
    pub a_g: f64,
    /// Mixture radius `a_cg = (1 - alpha) a_c + alpha a_g` (thesis section 5.2).
    pub a_cg: f64,
    /// `Pe_c = 6 pi eta a_c^3 gdot / kT` of a sheared Brownian scene.
    pub peclet_c: Option<f64>,
    /// `Pe_cg = 6 pi eta a_cg^3 gdot / kT`, with which the thesis' viscosity minima align.
    pub peclet_cg: Option<f64>,
}

impl Composition {
    /// The composition of a mixture section whose species have `counts` particles (in the
    /// order of [`MixtureSection::species`]), in fluid of viscosity `eta` sheared at
    /// `gdot` (0 = no flow) at thermal energy `kt` (0 = non-Brownian).
    pub fn of(mixture: &MixtureSection, counts: &[usize], eta: f64, gdot: f64, kt: f64) -> Self {
        let (a_c, a_g) = (mixture.colloid_radius(), mixture.grain_radius());
        let (radii, _) = mixture.species();
        let volume = |grains: bool| -> f64 {
            radii
                .iter()
                .zip(counts)
                .filter(|(&r, _)| (r >= a_g) == grains)
                .map(|(r, &c)| c as f64 * r.powi(3))
                .sum()
        };
        let (v_c, v_g) = (volume(false), volume(true));
        let a_cg = (1.0 - mixture.alpha) * a_c + mixture.alpha * a_g;
        let peclet = |a: f64| (kt > 0.0 && gdot > 0.0).then(|| peclet_number(eta, a, gdot, kt));
        Composition {
            alpha: mixture.alpha,
            alpha_actual: v_g / (v_c + v_g),
            a_c,
            a_g,
            a_cg,
            peclet_c: peclet(a_c),
            peclet_cg: peclet(a_cg),
        }
    }

    /// Refuses a mixture of both species (`0 < alpha < 1`) whose `n_particles` place only
    /// one of them: its runs would be of the other alone, reported under the nominal alpha.
    pub fn check(&self, n_particles: usize) -> Result<(), SimError> {
        let placed = if self.alpha_actual == 0.0 {
            "no grain"
        } else if self.alpha_actual == 1.0 {
            "no colloid"
        } else {
            return Ok(());
        };
        if self.alpha == 0.0 || self.alpha == 1.0 {
            return Ok(());
        }
        Err(SimError::field(
            "particles.mixture.alpha",
            format!(
                "{} places {placed} among the box's {n_particles} particles (their counts \
                 round it to {}): enlarge the box or choose an alpha further from 0 and 1",
                self.alpha, self.alpha_actual
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scene_file::default_grain_radii;

    fn mixture(alpha: f64, initial: Option<(Species, f64)>) -> MixtureSection {
        MixtureSection {
            alpha,
            colloid_radii: default_colloid_radii(),
            grain_radii: default_grain_radii(),
            initial: initial.map(|(species, phi)| InitialSuspension { species, phi }),
        }
    }

    #[test]
    fn fixed_liquid_volume_gives_the_thesis_volume_fractions() {
        // Thesis section 5.1, grains added to colloids at 0.55 (three digits as printed),
        // and the mirror: colloids added to grains, alpha = 0.7 -> 0.636 (issue 29).
        for (alpha, phi) in [(0.1, 0.576), (0.2, 0.604), (0.3, 0.636), (0.4, 0.671)] {
            let m = mixture(alpha, Some((Species::Colloids, 0.55)));
            let got = m.fixed_liquid_phi(m.initial.unwrap());
            assert!(
                (got - phi).abs() < 6e-4,
                "alpha {alpha}: {got} against {phi}"
            );
        }
        let m = mixture(0.7, Some((Species::Grains, 0.55)));
        assert!((m.fixed_liquid_phi(m.initial.unwrap()) - 0.636).abs() < 6e-4);
        // Nothing added, nothing changes.
        let m = mixture(0.0, Some((Species::Colloids, 0.55)));
        assert_eq!(m.fixed_liquid_phi(m.initial.unwrap()), 0.55);
    }

    #[test]
    fn each_radius_holds_an_equal_share_of_its_species_volume() {
        let (radii, fractions) = mixture(0.7, None).species();
        assert_eq!(radii, vec![1.0, 1.4, 5.0, 7.0]);
        let volumes: Vec<f64> = radii
            .iter()
            .zip(&fractions)
            .map(|(r, f)| f * r.powi(3))
            .collect();
        let total: f64 = volumes.iter().sum();
        for (v, share) in volumes.iter().zip([0.15, 0.15, 0.35, 0.35]) {
            assert!((v / total - share).abs() < 1e-12, "{volumes:?}");
        }
        assert!((fractions.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // A species of zero volume is left out.
        assert_eq!(mixture(0.0, None).species().0, vec![1.0, 1.4]);
        assert_eq!(mixture(1.0, None).species().0, vec![5.0, 7.0]);
    }

    #[test]
    fn the_mixture_radius_and_peclet_numbers_follow_alpha() {
        // 1e7 particles in the number fractions of alpha = 0.4: rounding the counts moves
        // the realised grain share by far less than 1e-3.
        let m = mixture(0.4, None);
        let (_, fractions) = m.species();
        let counts: Vec<usize> = fractions
            .iter()
            .map(|f| (f * 1e7).round() as usize)
            .collect();
        let c = Composition::of(&m, &counts, 1.0, 0.01, 0.01 * 6.0 * std::f64::consts::PI);
        assert!((c.alpha_actual - 0.4).abs() < 1e-3, "{c:?}");
        assert!((c.a_cg - (0.6 * 1.0 + 0.4 * 5.0)).abs() < 1e-12);
        assert!((c.peclet_c.unwrap() - 1.0).abs() < 1e-12);
        assert!((c.peclet_cg.unwrap() - 2.6f64.powi(3)).abs() < 1e-9);
        assert_eq!(Composition::of(&m, &counts, 1.0, 0.0, 0.1).peclet_cg, None);
    }
}
