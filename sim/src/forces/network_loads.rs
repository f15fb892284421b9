//! Loads on every particle that come from the resistance network of one step, worked out
//! range by range on the network's ranges of particles (each range's rows written by one
//! thread, as in the implicit solve): the Brownian loads (one-body and pairwise, thesis
//! eqs 3.20-3.24) and, for the explicit step of a Brownian scene, the dissipative loads of
//! drag and lubrication at the current motion (3.5, 3.6, 3.13, 3.14).
use crate::forces::force_field::ForceField;
use crate::forces::resistance_network::{Motion, ResistanceNetwork, ResistancePair};
use crate::forces::thermal_noise::ThermalNoise;
use crate::input::flow_profile::FlowProfile;
use crate::state::particle_ranges::each_range;
use crate::state::particles::Particles;
use crate::state::Vec3;

/// One step's draw of Brownian loads: the keyed noise, the particles (identities and
/// radii) and the step.
#[derive(Clone, Copy)]
pub struct Draw<'a> {
    pub noise: &'a ThermalNoise,
    pub particles: &'a Particles,
    pub step: u64,
}

/// Sets `out` (force, torque per particle) to the Brownian loads of the draw: the one-body
/// loads of every particle when `drag_eta` (the fluid viscosity) is given, plus each
/// lubricated pair's loads (equal and opposite forces) on both of its particles. The
/// network's crossings must be indexed.
pub fn brownian_loads(
    draw: Draw,
    network: &ResistanceNetwork,
    drag_eta: Option<f64>,
    out: &mut [Motion],
) {
    let p = draw.particles;
    each_range(&network.bounds, out, &|k, first, out: &mut [Motion]| {
        for (m, o) in out.iter_mut().enumerate() {
            let i = first + m;
            *o = match drag_eta {
                Some(eta) => {
                    let (f, t) = draw
                        .noise
                        .one_body_load(eta, p.radius[i], p.id[i], draw.step);
                    [f, t]
                }
                None => [Vec3::zeros(); 2],
            };
        }
        add_pair_loads(draw, network, k, (1.0, &|_| true), out);
    });
}

/// Adds `sign` times the Brownian loads of the draw of the network's pairs for which
/// `selected` holds to `out` (force, torque per particle): the corrections of the
/// midpoint step for the pairs that enter or leave the cut-off within it. The network's
/// crossings must be indexed.
pub fn add_selected_pair_loads(
    draw: Draw,
    network: &ResistanceNetwork,
    sign: f64,
    selected: &(impl Fn(&ResistancePair) -> bool + Sync),
    out: &mut [Motion],
) {
    each_range(&network.bounds, out, &|k, _, out: &mut [Motion]| {
        add_pair_loads(draw, network, k, (sign, selected), out);
    });
}

/// The pair part of [`brownian_loads`] on range `k`, for the selected pairs, times the
/// sign.
fn add_pair_loads(
    draw: Draw,
    network: &ResistanceNetwork,
    k: usize,
    (sign, selected): (f64, &impl Fn(&ResistancePair) -> bool),
    out: &mut [Motion],
) {
    let p = draw.particles;
    network.visit(k, |pair, i, j| {
        if !selected(pair) {
            return;
        }
        let ids = (p.id[pair.i as usize], p.id[pair.j as usize]);
        let load = draw
            .noise
            .pair_load(&pair.resistance, &pair.n, ids, draw.step);
        if let Some(i) = i {
            out[i][0] += load.force_i * sign;
            out[i][1] += load.torque_i * sign;
        }
        if let Some(j) = j {
            out[j][0] -= load.force_i * sign;
            out[j][1] += load.torque_j * sign;
        }
    });
}

/// Adds to `p.force` and `p.torque` the dissipative loads at the current velocities and
/// spins: minus the network's `R V` (lubrication) and the field's one-body drag towards
/// the streaming `profile`. `motion` and `scratch` are work space (one entry per particle).
pub fn add_dissipative_loads(
    network: &ResistanceNetwork,
    field: &ForceField,
    profile: &FlowProfile,
    p: &mut Particles,
    (motion, scratch): (&mut Vec<Motion>, &mut Vec<Motion>),
) {
    let n = p.len();
    motion.resize(n, Motion::default());
    scratch.resize(n, Motion::default());
    for (m, (v, w)) in motion.iter_mut().zip(p.vel.iter().zip(&p.omega)) {
        *m = [*v, *w];
    }
    let motion: &[Motion] = motion;
    let state: &Particles = p;
    each_range(&network.bounds, &mut scratch[..], &|k, first, out| {
        network.product_on(k, motion, out);
        for (m, o) in out.iter_mut().enumerate() {
            let (f, t) = field.one_body(state, profile, first + m);
            *o = [f - o[0], t - o[1]];
        }
    });
    for ((f, t), o) in p
        .force
        .iter_mut()
        .zip(p.torque.iter_mut())
        .zip(scratch.iter())
    {
        *f += o[0];
        *t += o[1];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::drag;
    use crate::forces::lubrication::LubricationCoefficients;
    use nalgebra::{DMatrix, DVector};

    /// Five spheres of radii 1 and 1.4 with six lubricated pairs (one of them between the
    /// two ranges 0..3 and 3..5), at gaps from below xi_min to near xi_max.
    fn cluster() -> (Particles, ResistanceNetwork) {
        let radius = vec![1.0, 1.4, 1.0, 1.4, 1.0];
        let pos = vec![Vec3::zeros(); 5];
        let mut p = Particles::at_rest(pos, radius.clone(), vec![0, 1, 0, 1, 0], 0.1);
        p.id = vec![7, 2, 9, 4, 0];
        let mut net = ResistanceNetwork::default();
        net.reset(&[0, 3, 5]);
        let pairs = [
            (0, 1, 5e-4),
            (0, 2, 2e-3),
            (1, 2, 0.01),
            (1, 3, 0.03),
            (2, 4, 0.049),
            (3, 4, 0.005),
        ];
        for (m, &(i, j, xi)) in pairs.iter().enumerate() {
            let lub = LubricationCoefficients::new(radius[i], radius[j], 0.1, 1e-3, 0.05);
            let n = Vec3::new(1.0, 0.3 * m as f64, -0.2 * m as f64 + 0.1).normalize();
            let k = usize::from(i >= 3);
            net.ranges[k].push(ResistancePair {
                i: i as u32,
                j: j as u32,
                n,
                resistance: lub.resistance(xi).unwrap(),
            });
        }
        net.index_crossings();
        (p, net)
    }

    /// The total random load of a cluster over 1e6 draws has covariance
    /// `(2 kT / dt) (D + R)`, with `R` assembled independently from the network's product
    /// (column by column on unit motions) and `D` the drag: every entry within 5 of its
    /// standard errors `sqrt((C_aa C_bb + C_ab^2) / n)` (n = 1e6: 0.14 % of the diagonal).
    #[test]
    fn cluster_noise_has_the_covariance_of_the_resistance() {
        let (p, net) = cluster();
        let (kt, dt, eta) = (0.3, 0.01, 0.1);
        let noise = ThermalNoise::new(kt, dt, 8);
        let dim = 6 * p.len();
        let mut expected = DMatrix::<f64>::zeros(dim, dim);
        let mut out = vec![Motion::default(); p.len()];
        for c in 0..dim {
            let mut motion = vec![Motion::default(); p.len()];
            motion[c / 6][(c % 6) / 3][c % 3] = 1.0;
            for k in 0..2 {
                let (a, b) = (net.bounds[k], net.bounds[k + 1]);
                net.product_on(k, &motion, &mut out[a..b]);
            }
            for (m, o) in out.iter().enumerate() {
                for r in 0..6 {
                    expected[(6 * m + r, c)] = o[r / 3][r % 3];
                }
            }
            let (m, rotation) = (c / 6, (c % 6) >= 3);
            let a = p.radius[m];
            expected[(c, c)] += if rotation {
                drag::rotational_resistance(eta, a)
            } else {
                drag::translational_resistance(eta, a)
            };
        }
        expected *= 2.0 * kt / dt;
        let draws = 1_000_000u64;
        let mut outer = DMatrix::<f64>::zeros(dim, dim);
        let mut v = DVector::<f64>::zeros(dim);
        for step in 0..draws {
            let draw = Draw {
                noise: &noise,
                particles: &p,
                step,
            };
            brownian_loads(draw, &net, Some(eta), &mut out);
            for (m, o) in out.iter().enumerate() {
                for r in 0..6 {
                    v[6 * m + r] = o[r / 3][r % 3];
                }
            }
            outer.ger(1.0, &v, &v, 1.0);
        }
        let n = draws as f64;
        let sampled = outer / n;
        for a in 0..dim {
            for b in 0..dim {
                let se =
                    ((expected[(a, a)] * expected[(b, b)] + expected[(a, b)].powi(2)) / n).sqrt();
                assert!(
                    (sampled[(a, b)] - expected[(a, b)]).abs() < 5.0 * se,
                    "entry ({a}, {b}): sampled {:e}, expected {:e}, se {se:e}",
                    sampled[(a, b)],
                    expected[(a, b)]
                );
            }
        }
    }
}
