//! Short-range electrostatic repulsion between every pair of spheres (paper eq 4.2,
//! thesis eq 4.4; docs/physics.md section 11):
//!
//! `F^R = (A / kappa) exp(((a_i + a_j) - |r|) / kappa) n`,   `kappa = 0.01 (a_i + a_j)`,
//!
//! on j along the unit vector `n` from i to j (and `-F^R` on i), with the energy
//! `A = forces.repulsion * fluid.kT` (units eta a^3 / time). It is conservative (the potential is
//! `A exp(-h / kappa)` at surface gap `h`), position-only, and grows exponentially inside
//! an overlap, where the contact spring acts as well.
use crate::state::Vec3;

/// Debye length over the contact distance: `kappa = KAPPA_FRACTION (a_i + a_j)`.
pub const KAPPA_FRACTION: f64 = 0.01;

/// Surface gap, in Debye lengths, beyond which the repulsion is cut: there the force is
/// `e^-10 = 4.5e-5` of its contact value and the potential `4.5e-5 A` (0.045 kT at the
/// seeds' largest `A = 1000 kT`). A pair's interaction cut-off is at least this far.
pub const CUTOFF_KAPPAS: f64 = 10.0;

/// The repulsion of one species pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Repulsion {
    /// `A / kappa`: the force at contact (units of force, eta a^2 / time).
    pub contact_force: f64,
    /// Debye length `kappa = 0.01 (a_i + a_j)` (units a).
    pub kappa: f64,
}

impl Repulsion {
    /// The repulsion of amplitude `a` (the energy `A`) between spheres at contact distance
    /// `a_i + a_j`.
    pub fn new(a: f64, contact_distance: f64) -> Self {
        let kappa = KAPPA_FRACTION * contact_distance;
        Self {
            contact_force: a / kappa,
            kappa,
        }
    }

    /// Centre distance up to which the repulsion acts (units a): the contact distance
    /// plus `CUTOFF_KAPPAS` Debye lengths, `1.1 (a_i + a_j)`.
    pub fn reach(contact_distance: f64) -> f64 {
        contact_distance * (1.0 + CUTOFF_KAPPAS * KAPPA_FRACTION)
    }

    /// Force on i for the overlap `delta = a_i + a_j - |r|` (negative when apart) along
    /// the unit vector `n` from i to j: `-(A / kappa) exp(delta / kappa) n`, repulsive.
    #[inline]
    pub fn force_i(&self, delta: f64, n: &Vec3) -> Vec3 {
        -self.contact_force * (delta / self.kappa).exp() * n
    }

    /// Stiffness `-dF/d|r|` at contact, `A / kappa^2` (force per unit length); larger by
    /// `exp(delta / kappa)` inside an overlap `delta`.
    pub fn contact_stiffness(&self) -> f64 {
        self.contact_force / self.kappa
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scene::Scene;
    use crate::integrate::simulation::Simulation;
    use crate::state::particles::Particles;

    /// The stress parts take the contact part from `PairOutcome::contact_force`
    /// (sampling/snapshot.rs): without lubrication the whole pair load must be in it.
    #[test]
    fn the_repulsion_is_counted_in_the_contact_part_of_the_pair_load() {
        let text = "[box]\nl_x = 12\nl_y = 12\nl_z = 12\n[particles]\nphi = 0.3\n\
                    radii = [1.0]\n[fluid]\nkT = 0.004\n[forces]\nrepulsion = 1000\n\
                    lubrication = false\n";
        let scene = Scene::from_toml(text, false).unwrap();
        let x_i = Vec3::new(3.0, 6.0, 6.0);
        let pos = vec![x_i, x_i + Vec3::x() * 2.03];
        let p = Particles::at_rest(pos, vec![1.0; 2], vec![0; 2], 1.0);
        let sim = Simulation::new(&scene, p).unwrap();
        let o = sim
            .field
            .pair(&sim.particles, &sim.pbox, 0, 1, None, 0.0)
            .expect("inside the cut-off");
        let expected = 200.0 * (-1.5f64).exp();
        assert!((o.load.force_i.norm() - expected).abs() < 1e-12 * expected);
        assert_eq!(o.contact_force, o.load.force_i);
    }

    #[test]
    fn the_force_at_contact_is_a_over_kappa_and_pushes_apart() {
        let (a, sigma) = (17.0, 2.4);
        let r = Repulsion::new(a, sigma);
        let kappa = 0.024;
        assert!((r.kappa - kappa).abs() < 1e-15);
        let n = Vec3::new(0.6, 0.0, 0.8);
        let f = r.force_i(0.0, &n);
        assert!((f + n * (a / kappa)).norm() < 1e-12 * a / kappa, "{f}");
        // On i it points away from j: against n.
        assert!(f.dot(&n) < 0.0);
        assert!((r.contact_stiffness() - a / (kappa * kappa)).abs() < 1e-9 * r.contact_stiffness());
    }

    #[test]
    fn the_force_falls_by_e_per_debye_length_of_gap() {
        let r = Repulsion::new(1.0, 2.0);
        let n = Vec3::x();
        for k in 0..12 {
            let gap = k as f64 * r.kappa;
            let ratio = r.force_i(-gap - r.kappa, &n).x / r.force_i(-gap, &n).x;
            assert!(
                (ratio - (-1.0f64).exp()).abs() < 1e-12,
                "gap {gap}: {ratio}"
            );
        }
        // Inside an overlap it grows by the same factor per kappa.
        let inside = r.force_i(r.kappa, &n).x / r.force_i(0.0, &n).x;
        assert!((inside - 1.0f64.exp()).abs() < 1e-12);
        // At the cut-off: e^-10 of the contact value.
        let edge = Repulsion::reach(2.0) - 2.0;
        let at_edge = r.force_i(-edge, &n).x / r.force_i(0.0, &n).x;
        assert!((at_edge - (-10.0f64).exp()).abs() < 1e-15, "{at_edge}");
    }
}
