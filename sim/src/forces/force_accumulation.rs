//! Sums pair and one-body loads into every particle's force and torque, in parallel over
//! contiguous ranges of the half neighbour list, with fixed ranges so that the same
//! thread count always gives the same bits (docs/physics.md section 3).
use crate::forces::force_field::ForceField;
use crate::forces::range_buffers::{zero_buffer, RangeBuffers, RangeTarget};
use crate::forces::resistance_network::{ResistanceNetwork, ResistancePair};
use crate::input::flow_profile::FlowProfile;
use crate::neighbours::verlet_list::VerletList;
use crate::state::particle_ranges::each_range;
use crate::state::particles::Particles;
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;
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

/// What every pair load of one evaluation reads besides the particles: the force laws,
/// the neighbour list, the box, the streaming flow, and the time `spring_dt` by which the
/// tangential contact springs advance.
#[derive(Clone, Copy)]
pub struct PairContext<'a> {
    pub field: &'a ForceField,
    pub list: &'a VerletList,
    pub pbox: &'a PeriodicBox,
    pub profile: &'a FlowProfile,
    pub spring_dt: f64,
}

/// Range bounds and buffers of the parallel pair loop, reused every step (no allocation
/// per step).
#[derive(Default)]
pub struct ForceAccumulator {
    buffers: RangeBuffers,
    bounds: Vec<usize>,
}

impl ForceAccumulator {
    /// Splits the particles into contiguous ranges of about equal work, one per thread
    /// (one range below [`PARALLEL_MIN_PARTICLES`]): the pairs each lists, plus, with
    /// `crossings` (for the implicit solve, in which a range also evaluates the pairs that
    /// cross into it from earlier ranges), those pairs, counted on the Verlet list at the
    /// cuts of an equal split. Returns the number of ranges.
    pub fn split(&mut self, list: &VerletList, crossings: bool) -> usize {
        let n = list.start.len() - 1;
        let ranges = if n < PARALLEL_MIN_PARTICLES {
            1
        } else {
            rayon::current_num_threads().max(1)
        };
        self.cut(list, ranges, 0, |_| 0);
        if crossings {
            let extra = self.bounds[1..ranges]
                .iter()
                .map(|&b| list.crossing[b])
                .sum();
            self.cut(list, ranges, extra, |b| list.crossing[b]);
        }
        ranges
    }

    /// The ranges of the last [`ForceAccumulator::split`]: range k holds particles
    /// `bounds[k]..bounds[k + 1]`.
    pub fn bounds(&self) -> &[usize] {
        &self.bounds
    }

    /// Sets the bounds so that each range holds `(pairs + extra) / ranges` of the listed
    /// pairs plus the `crossing(b)` pairs that enter it at its first cut `b`.
    fn cut(
        &mut self,
        list: &VerletList,
        ranges: usize,
        extra: usize,
        crossing: impl Fn(usize) -> usize,
    ) {
        let n = list.start.len() - 1;
        let total = list.len() + extra;
        self.bounds.clear();
        self.bounds.push(0);
        let (mut i, mut entered) = (0, 0);
        for k in 1..ranges {
            let target = total * k / ranges;
            while i < n && list.start[i] + entered < target {
                i += 1;
            }
            self.bounds.push(i);
            entered += crossing(i);
        }
        self.bounds.push(n);
    }

    /// The explicit step's loads: sets `p.force` and `p.torque` to the total load on
    /// every particle, the one-body terms plus every listed pair within its cut-off
    /// (contact and lubrication). `springs` holds one tangential spring per listed pair
    /// in frictional scenes and is empty otherwise.
    pub fn all_loads(
        &mut self,
        pairs: &PairContext,
        p: &mut Particles,
        springs: &mut [Vec3],
    ) -> ContactStats {
        self.evaluate(pairs, p, springs, None)
    }

    /// The implicit step's loads: sets `p.force` and `p.torque` to the loads known before
    /// the solve (contacts, and the lubrication of a sliding image's extra velocity; no
    /// drag, no lubrication of the particles' own motion), and fills `network` with every
    /// pair's lubrication resistance instead. `springs` as in [`Self::all_loads`].
    pub fn known_loads(
        &mut self,
        pairs: &PairContext,
        p: &mut Particles,
        springs: &mut [Vec3],
        network: &mut ResistanceNetwork,
    ) -> ContactStats {
        self.evaluate(pairs, p, springs, Some(network))
    }

    /// [`Self::all_loads`] without a network, [`Self::known_loads`] with one.
    fn evaluate(
        &mut self,
        pairs: &PairContext,
        p: &mut Particles,
        springs: &mut [Vec3],
        mut network: Option<&mut ResistanceNetwork>,
    ) -> ContactStats {
        let ranges = self.split(pairs.list, network.is_some());
        if let Some(net) = network.as_deref_mut() {
            net.reset(&self.bounds);
        }
        let n = p.len();
        // The state is read while the load arrays are written: move them out (no copy).
        let mut force = std::mem::take(&mut p.force);
        let mut torque = std::mem::take(&mut p.torque);
        let state: &Particles = p;
        let one_body = network.is_none();
        let (field, profile, list) = (pairs.field, pairs.profile, pairs.list);
        each_range(
            &self.bounds,
            (&mut force[..], &mut torque[..]),
            &|_, first, (force, torque)| {
                for (m, (f, t)) in force.iter_mut().zip(torque.iter_mut()).enumerate() {
                    (*f, *t) = if one_body {
                        field.one_body(state, profile, first + m)
                    } else {
                        (Vec3::zeros(), Vec3::zeros())
                    };
                }
            },
        );
        let bounds = &self.bounds;
        let mut spring_parts: Vec<&mut [Vec3]> = Vec::with_capacity(ranges);
        let mut rest = springs;
        for k in 0..ranges {
            let len = if rest.is_empty() {
                0
            } else {
                list.start[bounds[k + 1]] - list.start[bounds[k]]
            };
            let (head, tail) = rest.split_at_mut(len);
            spring_parts.push(head);
            rest = tail;
        }
        let mut records: Vec<Option<&mut Vec<ResistancePair>>> = match network {
            Some(net) => net.ranges.iter_mut().map(Some).collect(),
            None => (0..ranges).map(|_| None).collect(),
        };
        let stats = if ranges == 1 {
            let mut total = ContactStats::default();
            pair_range(
                pairs,
                state,
                spring_parts.pop().unwrap_or_default(),
                (0..n, (&mut force, &mut torque, 0)),
                records.pop().flatten(),
                &mut total,
            );
            vec![total]
        } else {
            let targets = self.buffers.targets(bounds, n, (&mut force, &mut torque));
            let stats: Vec<ContactStats> = targets
                .into_par_iter()
                .zip(spring_parts.into_par_iter())
                .zip(records.into_par_iter())
                .enumerate()
                .map(|(k, ((mut target, part), record))| {
                    zero_buffer(&mut target);
                    let mut s = ContactStats::default();
                    pair_range(
                        pairs,
                        state,
                        part,
                        (bounds[k]..bounds[k + 1], target),
                        record,
                        &mut s,
                    );
                    s
                })
                .collect();
            self.buffers.reduce_into(bounds, &mut force, &mut torque);
            stats
        };
        p.force = force;
        p.torque = torque;
        let mut total = ContactStats::default();
        for s in &stats {
            total.merge(s);
        }
        total
    }
}

/// Adds the loads of the pairs whose first particle lies in `rows` into the target's
/// force and torque arrays, which hold particles from its offset on. With `record`, only
/// the known loads are added and each pair's lubrication resistance is recorded.
fn pair_range(
    pairs: &PairContext,
    p: &Particles,
    springs: &mut [Vec3],
    (rows, (force, torque, offset)): (std::ops::Range<usize>, RangeTarget<'_>),
    mut record: Option<&mut Vec<ResistancePair>>,
    stats: &mut ContactStats,
) {
    let PairContext {
        field,
        list,
        pbox,
        spring_dt: dt,
        ..
    } = *pairs;
    let frictional = !springs.is_empty();
    let first_pair = list.start[rows.start];
    // Filled as a local vector, put back at the end: the records' headers lie side by
    // side, and writing one's length at every push while another task does the same
    // would bounce their shared cache line between cores.
    let mut recorded = record.as_deref_mut().map(std::mem::take);
    for i in rows {
        for q in list.start[i]..list.start[i + 1] {
            let j = list.neighbours[q] as usize;
            let spring = if frictional {
                Some(&mut springs[q - first_pair])
            } else {
                None
            };
            let outcome = match recorded.as_mut() {
                None => field.pair(p, pbox, i, j, spring, dt),
                Some(rec) => field.pair_contact(p, pbox, i, j, spring, dt).inspect(|o| {
                    if let Some(resistance) = o.resistance {
                        rec.push(ResistancePair {
                            i: i as u32,
                            j: j as u32,
                            n: o.n,
                            resistance,
                        });
                    }
                }),
            };
            if let Some(out) = outcome {
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
    if let (Some(record), Some(recorded)) = (record, recorded) {
        *record = recorded;
    }
}
