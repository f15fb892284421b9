//! One sample of the per-bin sums from which every observable of docs/physics.md section 6 is
//! built, under every convention at once: particle counts, velocities, streaming velocities,
//! solid volumes, pair stresslet sums (method of planes), drag stresslets, plane stresses at
//! the bin faces, drag forces, and the sums that give the velocity fluctuations (about the
//! local mean of section 6.3 and about an interpolated mean profile), and the parts of the
//! pair stress: contact springs, and the structural Brownian stress (section 11).
use crate::forces::{brownian_shell, drag};
use crate::integrate::simulation::Simulation;
use crate::sampling::binning::Bins;
use crate::sampling::local_velocity::LocalVelocity;
use nalgebra::Matrix3;

/// Half-width of the window of the local mean velocity `u*_i`, in mean radii (thesis
/// section 6.3: `+-0.1 a`).
pub const LOCAL_WINDOW: f64 = 0.1;

/// Field indices of a snapshot; a snapshot is `FIELDS x n_bins` numbers, field-major.
pub mod field {
    /// Particles whose centre lies in the bin.
    pub const COUNT: usize = 0;
    /// Sum of their x-velocities.
    pub const VX: usize = 1;
    /// Solid volume inside the slab (spherical caps).
    pub const VOLUME: usize = 2;
    /// Pair stresslet sums (method of planes), `S_ab = -F_a r_b`, components in the order
    /// of [`TENSOR`](super::TENSOR).
    pub const SXX: usize = 3;
    pub const SYY: usize = 4;
    pub const SZZ: usize = 5;
    pub const SXY: usize = 6;
    /// xy drag stresslet sum of the particles centred in the bin (the drag stresslet is
    /// traceless and has no other component).
    pub const SXY_DRAG: usize = 7;
    /// Sum of the x drag forces on the bin's particles.
    pub const DRAG_X: usize = 8;
    /// Sum of the squared x-velocities.
    pub const VX2: usize = 9;
    /// Interpolation sums of particles in the lower half of the bin, between the centres
    /// of bins k-1 and k at fraction t: `v (1-t)`, `v t`, `(1-t)^2`, `t (1-t)`, `t^2`.
    pub const LOWER: usize = 10;
    /// The same for the upper half, between the centres of bins k and k+1.
    pub const UPPER: usize = 15;
    /// Sum over pairs crossing the bin's lower face of `F_x sign(r_y)`, the x force on the
    /// particle below from the particle above (Cauchy traction times face area).
    pub const FACE_FX: usize = 20;
    /// Sum of the streaming velocities `u_inf(y_i)` of the bin's particles.
    pub const U_INF: usize = 21;
    /// Sum of `|v_x,i - u*_i|` over the bin's particles, `u*_i` the local mean velocity
    /// within [`LOCAL_WINDOW`](super::LOCAL_WINDOW) mean radii of `y_i`.
    pub const LOCAL_DU: usize = 22;
    /// The contact springs' part of the pair stresslet sums (xx, yy, zz, xy from here on,
    /// as `SXX..=SXY`); the rest of those sums is lubrication.
    pub const CONTACT: usize = 23;
    /// Structural Brownian stress sums (xx, yy, zz, xy from here on): `w n n^T` over the
    /// pairs in the shell, shared between bins like the stresslets, with the weight `w` of
    /// [`brownian_shell::weight`](crate::forces::brownian_shell::weight). Zero when kT = 0.
    pub const BROWNIAN: usize = 27;
    /// Number of fields.
    pub const FIELDS: usize = 31;
}

/// The stress components a snapshot keeps, in field order from `SXX`, `CONTACT` and
/// `BROWNIAN`: (row, column) of xx, yy, zz, xy.
pub const TENSOR: [(usize, usize); 4] = [(0, 0), (1, 1), (2, 2), (0, 1)];

/// Adds `frac` times the components [`TENSOR`] of `s` to the bin `k` of the four fields from
/// `base`.
#[inline]
fn add_tensor(out: &mut [f64], nb: usize, base: usize, k: usize, frac: f64, s: &Matrix3<f64>) {
    for (c, &(a, b)) in TENSOR.iter().enumerate() {
        out[(base + c) * nb + k] += frac * s[(a, b)];
    }
}

/// Takes snapshots of a simulation into per-bin sums; keeps its scratch buffers.
#[derive(Clone, Debug)]
pub struct Sampler {
    pub bins: Bins,
    /// Mean particle radius, the `a` of the local window.
    pub a_mean: f64,
    local: LocalVelocity,
}

impl Sampler {
    pub fn new(bins: Bins, a_mean: f64) -> Self {
        Self {
            bins,
            a_mean,
            local: LocalVelocity::default(),
        }
    }

    /// Adds one snapshot of `sim` into `out` (length `FIELDS * bins.count`). Its pair
    /// sums ([`PAIR_FIELDS`]) are the instantaneous ones, or, when `steps` holds the sums
    /// of the steps since the last snapshot (see [`StepPairSums`]), their mean, and
    /// `steps` is emptied.
    pub fn accumulate(&mut self, sim: &Simulation, steps: &mut StepPairSums, out: &mut [f64]) {
        let l_y = self.bins.width * self.bins.count as f64;
        let p = &sim.particles;
        let du = self
            .local
            .deviations(&p.pos, &p.vel, l_y, LOCAL_WINDOW * self.a_mean);
        accumulate_particles(sim, &self.bins, du, out);
        if steps.steps == 0 {
            accumulate_pairs(sim, &self.bins, out);
        } else {
            let nb = self.bins.count;
            let per_step = 1.0 / steps.steps as f64;
            for &f in &PAIR_FIELDS {
                let range = f * nb..(f + 1) * nb;
                for (o, s) in out[range.clone()].iter_mut().zip(&steps.sums[range]) {
                    *o += s * per_step;
                }
            }
            steps.clear();
        }
    }

    /// Adds the pair sums of `sim`'s present state to `steps`: called by the Brownian
    /// step at its midpoint (see [`StepPairSums`]).
    pub fn add_step_pairs(&self, sim: &Simulation, steps: &mut StepPairSums) {
        steps.sums.resize(field::FIELDS * self.bins.count, 0.0);
        accumulate_pairs(sim, &self.bins, &mut steps.sums);
        steps.steps += 1;
    }
}

/// The fields of a snapshot summed over pairs: the pair stresslets, the face tractions,
/// their contact part and the structural Brownian stress.
pub const PAIR_FIELDS: [usize; 13] = {
    use field::*;
    [
        SXX,
        SYY,
        SZZ,
        SXY,
        FACE_FX,
        CONTACT,
        CONTACT + 1,
        CONTACT + 2,
        CONTACT + 3,
        BROWNIAN,
        BROWNIAN + 1,
        BROWNIAN + 2,
        BROWNIAN + 3,
    ]
};

/// The pair sums of a Brownian run's steps since its last snapshot (docs/physics.md
/// section 11). The implicit Brownian step's stiff lubricated modes flip their end-of-step
/// velocity `V' = 2 W - V` every step, so a snapshot of the lubrication stress at `V'`
/// is dominated by that flip; its mean over the steps, each at the step's midpoint with
/// the step's mean velocity `W` (the dissipative loads the trapezoidal rule applied), is
/// the time average of the stress the dynamics exerted, without it. Kept in the run's
/// checkpoint, so a resumed run averages the same steps.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize, PartialEq)]
pub struct StepPairSums {
    /// `FIELDS * n_bins` sums (only [`PAIR_FIELDS`] are filled), field-major.
    pub sums: Vec<f64>,
    /// Steps summed.
    pub steps: u64,
}

impl StepPairSums {
    /// Forgets the steps summed, keeping the memory.
    pub fn clear(&mut self) {
        self.sums.iter_mut().for_each(|x| *x = 0.0);
        self.steps = 0;
    }
}

/// Adds the per-particle sums of one snapshot of `sim` into `out`, with
/// `local_du[i] = |v_x,i - u*_i|`.
fn accumulate_particles(sim: &Simulation, bins: &Bins, local_du: &[f64], out: &mut [f64]) {
    use field::*;
    let nb = bins.count;
    let p = &sim.particles;
    let eta = sim.field.eta;
    for (i, &local_du) in local_du.iter().enumerate() {
        let (y, a, vx) = (p.pos[i].y, p.radius[i], p.vel[i].x);
        let k = bins.index(y);
        let u_inf = sim.profile.u(y);
        out[COUNT * nb + k] += 1.0;
        out[VX * nb + k] += vx;
        out[VX2 * nb + k] += vx * vx;
        out[U_INF * nb + k] += u_inf;
        out[LOCAL_DU * nb + k] += local_du;
        bins.add_sphere_volume(y, a, &mut out[VOLUME * nb..(VOLUME + 1) * nb]);
        if sim.field.drag {
            let du = sim.profile.du_dy(y);
            out[DRAG_X * nb + k] += drag::force(eta, a, u_inf, &p.vel[i]).x;
            out[SXY_DRAG * nb + k] += drag::stresslet_xy(eta, a, du);
        }
        let centre = bins.centre(k);
        let (base, t) = if y < centre {
            (LOWER, (y - centre + bins.width) / bins.width)
        } else {
            (UPPER, (y - centre) / bins.width)
        };
        let s = 1.0 - t;
        for (f, v) in [vx * s, vx * t, s * s, t * s, t * t]
            .into_iter()
            .enumerate()
        {
            out[(base + f) * nb + k] += v;
        }
    }
}

/// Adds the sums over the pairs of `sim` ([`PAIR_FIELDS`]) into `out`.
fn accumulate_pairs(sim: &Simulation, bins: &Bins, out: &mut [f64]) {
    use field::*;
    let nb = bins.count;
    let p = &sim.particles;
    let frictional = sim.field.frictional();
    for i in 0..p.len() {
        for q in sim.list.start[i]..sim.list.start[i + 1] {
            let j = sim.list.neighbours[q] as usize;
            let mut spring = if frictional {
                Some(sim.springs[q])
            } else {
                None
            };
            let Some(o) = sim.field.pair(p, &sim.pbox, i, j, spring.as_mut(), 0.0) else {
                continue;
            };
            let s = o.load.stresslet(&o.r);
            let contact = -o.contact_force * o.r.transpose();
            let brownian = sim
                .kt()
                .and_then(|kt| brownian_shell::weight(kt, p.radius[i], p.radius[j], o.r.norm()))
                .map(|w| w * o.n * o.n.transpose());
            let y_i = p.pos[i].y;
            bins.share_segment(y_i, o.r.y, |k, frac| {
                add_tensor(out, nb, SXX, k, frac, &s);
                add_tensor(out, nb, CONTACT, k, frac, &contact);
                if let Some(b) = &brownian {
                    add_tensor(out, nb, BROWNIAN, k, frac, b);
                }
            });
            let (lo, hi) = if o.r.y > 0.0 {
                (y_i, y_i + o.r.y)
            } else {
                (y_i + o.r.y, y_i)
            };
            let below_from_above = o.load.force_i.x * o.r.y.signum();
            bins.for_each_face(lo, hi, |k| out[FACE_FX * nb + k] += below_from_above);
        }
    }
}
