//! Sums pair and one-body loads into every particle's force and torque, in parallel over
//! contiguous chunks of the half neighbour list, with a fixed chunking so that the same
//! thread count always gives the same bits (docs/physics.md section 3).
use crate::forces::force_field::ForceField;
use crate::input::flow_profile::FlowProfile;
use crate::integrate::particles::Particles;
use crate::integrate::periodic_box::PeriodicBox;
use crate::neighbours::verlet_list::VerletList;
use crate::Vec3;
use rayon::prelude::*;

/// Below this many particles the pair loop runs on one thread: the per-step fork and the
/// buffer reduction cost more than they save.
pub const PARALLEL_MIN_PARTICLES: usize = 2048;

/// Overlap statistics of one force evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactStats {
    /// Number of overlapping pairs.
    pub contacts: usize,
    /// Sum of overlaps (units a).
    pub overlap_sum: f64,
    /// Largest overlap relative to the smaller radius of its pair.
    pub max_overlap_ratio: f64,
    /// The pair with the largest overlap ratio.
    pub max_pair: (usize, usize),
}

impl ContactStats {
    fn record(&mut self, overlap: f64, a_min: f64, i: usize, j: usize) {
        if overlap > 0.0 {
            self.contacts += 1;
            self.overlap_sum += overlap;
            let ratio = overlap / a_min;
            if ratio > self.max_overlap_ratio {
                self.max_overlap_ratio = ratio;
                self.max_pair = (i, j);
            }
        }
    }

    fn merge(&mut self, other: &ContactStats) {
        self.contacts += other.contacts;
        self.overlap_sum += other.overlap_sum;
        if other.max_overlap_ratio > self.max_overlap_ratio {
            self.max_overlap_ratio = other.max_overlap_ratio;
            self.max_pair = other.max_pair;
        }
    }

    /// Mean overlap over contacts (units a), 0 without contacts.
    pub fn mean_overlap(&self) -> f64 {
        if self.contacts == 0 {
            0.0
        } else {
            self.overlap_sum / self.contacts as f64
        }
    }
}

/// Force and torque buffers of the chunks after the first, reused every step (no
/// allocation per step).
#[derive(Default)]
pub struct ForceAccumulator {
    buffers: Vec<(Vec<Vec3>, Vec<Vec3>)>,
    bounds: Vec<usize>,
}

impl ForceAccumulator {
    /// Splits the particles into `chunks` contiguous ranges holding about equal numbers of
    /// pairs.
    fn split(&mut self, list: &VerletList, chunks: usize) {
        let n = list.start.len() - 1;
        let total = list.len();
        self.bounds.clear();
        self.bounds.push(0);
        let mut i = 0;
        for k in 1..chunks {
            let target = total * k / chunks;
            while i < n && list.start[i] < target {
                i += 1;
            }
            self.bounds.push(i);
        }
        self.bounds.push(n);
    }

    /// Sets `p.force` and `p.torque` to the total load on every particle: one-body terms
    /// plus every listed pair within its cut-off. `springs` holds one tangential spring
    /// per listed pair in frictional scenes and is empty otherwise.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &mut self,
        field: &ForceField,
        p: &mut Particles,
        list: &VerletList,
        springs: &mut [Vec3],
        pbox: &PeriodicBox,
        profile: &FlowProfile,
        dt: f64,
    ) -> ContactStats {
        let chunks = if p.len() < PARALLEL_MIN_PARTICLES {
            1
        } else {
            rayon::current_num_threads().max(1)
        };
        let n = p.len();
        // The state is read while the load arrays are written: move them out (no copy).
        let mut force = std::mem::take(&mut p.force);
        let mut torque = std::mem::take(&mut p.torque);
        let state: &Particles = p;
        let stats = if chunks == 1 {
            for i in 0..n {
                (force[i], torque[i]) = field.one_body(state, profile, i);
            }
            pair_range(
                field,
                state,
                list,
                springs,
                pbox,
                dt,
                0..n,
                0,
                &mut force,
                &mut torque,
            )
        } else {
            self.parallel(
                field,
                state,
                list,
                springs,
                pbox,
                profile,
                dt,
                chunks,
                &mut force,
                &mut torque,
            )
        };
        p.force = force;
        p.torque = torque;
        stats
    }

    /// Parallel evaluation. The one-body loads are written first; then chunk 0 adds its
    /// pairs straight into the output while chunk k >= 1 sums into its own buffer, which
    /// only needs to cover particles from its first row on (a half list has j > i).
    /// Finally each particle adds the buffers in chunk order.
    #[allow(clippy::too_many_arguments)]
    fn parallel(
        &mut self,
        field: &ForceField,
        state: &Particles,
        list: &VerletList,
        springs: &mut [Vec3],
        pbox: &PeriodicBox,
        profile: &FlowProfile,
        dt: f64,
        chunks: usize,
        force: &mut [Vec3],
        torque: &mut [Vec3],
    ) -> ContactStats {
        let n = state.len();
        self.split(list, chunks);
        self.buffers.resize_with(chunks - 1, Default::default);
        force
            .par_iter_mut()
            .zip(torque.par_iter_mut())
            .enumerate()
            .with_min_len(256)
            .for_each(|(i, (f, t))| {
                (*f, *t) = field.one_body(state, profile, i);
            });
        let bounds = &self.bounds;
        let mut spring_parts: Vec<&mut [Vec3]> = Vec::with_capacity(chunks);
        let mut rest = springs;
        for k in 0..chunks {
            let len = if rest.is_empty() {
                0
            } else {
                list.start[bounds[k + 1]] - list.start[bounds[k]]
            };
            let (head, tail) = rest.split_at_mut(len);
            spring_parts.push(head);
            rest = tail;
        }
        let mut targets: Vec<(&mut [Vec3], &mut [Vec3], usize)> = Vec::with_capacity(chunks);
        targets.push((&mut *force, &mut *torque, 0));
        for (k, (bf, bt)) in self.buffers.iter_mut().enumerate() {
            let offset = bounds[k + 1];
            bf.clear();
            bf.resize(n - offset, Vec3::zeros());
            bt.clear();
            bt.resize(n - offset, Vec3::zeros());
            targets.push((bf.as_mut_slice(), bt.as_mut_slice(), offset));
        }
        let stats: Vec<ContactStats> = targets
            .into_par_iter()
            .zip(spring_parts.into_par_iter())
            .enumerate()
            .map(|(k, ((f, t, offset), part))| {
                pair_range(
                    field,
                    state,
                    list,
                    part,
                    pbox,
                    dt,
                    bounds[k]..bounds[k + 1],
                    offset,
                    f,
                    t,
                )
            })
            .collect();
        let buffers = &self.buffers;
        let first = bounds[1];
        force[first..]
            .par_iter_mut()
            .zip(torque[first..].par_iter_mut())
            .enumerate()
            .with_min_len(256)
            .for_each(|(r, (f, t))| {
                let i = first + r;
                for (k, (bf, bt)) in buffers.iter().enumerate() {
                    let offset = bounds[k + 1];
                    if i < offset {
                        break;
                    }
                    *f += bf[i - offset];
                    *t += bt[i - offset];
                }
            });
        let mut total = ContactStats::default();
        for s in &stats {
            total.merge(s);
        }
        total
    }
}

/// Adds the loads of the pairs whose first particle lies in `rows` into `force`/`torque`,
/// which hold particles from index `offset` on.
#[allow(clippy::too_many_arguments)]
fn pair_range(
    field: &ForceField,
    p: &Particles,
    list: &VerletList,
    springs: &mut [Vec3],
    pbox: &PeriodicBox,
    dt: f64,
    rows: std::ops::Range<usize>,
    offset: usize,
    force: &mut [Vec3],
    torque: &mut [Vec3],
) -> ContactStats {
    let mut stats = ContactStats::default();
    let frictional = !springs.is_empty();
    let first_pair = list.start[rows.start];
    for i in rows {
        for q in list.start[i]..list.start[i + 1] {
            let j = list.neighbours[q] as usize;
            let spring = if frictional {
                Some(&mut springs[q - first_pair])
            } else {
                None
            };
            if let Some(out) = field.pair(p, pbox, i, j, spring, dt) {
                force[i - offset] += out.load.force_i;
                force[j - offset] -= out.load.force_i;
                torque[i - offset] += out.load.torque_i;
                torque[j - offset] += out.load.torque_j;
                stats.record(
                    out.overlap,
                    field.constants(p.species[i], p.species[j]).a_min,
                    i,
                    j,
                );
            }
        }
    }
    stats
}
