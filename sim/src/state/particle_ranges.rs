//! Per-particle work split into the contiguous ranges of particles of the force
//! evaluation (`bounds[k]..bounds[k + 1]`), each range run as one task.
//!
//! The list of ranges is halved at each fork: the first half stays on the calling thread
//! and the second is taken by another, so with a fixed pool a range is (nearly always)
//! worked on by the same thread in every phase of a step: drift, force evaluation,
//! implicit solve, velocity update. Its particles' data then stay in that core's cache
//! instead of moving between cores at each phase. Results are merged in range order, so
//! the same bounds give the same bits.

/// Data held one entry per particle, from which the particles of a range can be split
/// off.
pub trait PerParticle: Send + Sized {
    /// The first `at` particles' part and the rest.
    fn split_at(self, at: usize) -> (Self, Self);
}

impl<T: Send> PerParticle for &mut [T] {
    fn split_at(self, at: usize) -> (Self, Self) {
        self.split_at_mut(at)
    }
}

impl<T: Sync> PerParticle for &[T] {
    fn split_at(self, at: usize) -> (Self, Self) {
        <[T]>::split_at(self, at)
    }
}

impl<A: PerParticle, B: PerParticle> PerParticle for (A, B) {
    fn split_at(self, at: usize) -> (Self, Self) {
        let (a0, a1) = self.0.split_at(at);
        let (b0, b1) = self.1.split_at(at);
        ((a0, b0), (a1, b1))
    }
}

/// Runs `f(k, first, part)` on every range `k` of `bounds` in parallel, `part` being the
/// range's share of `data` (which covers particles `bounds[0]..`) and `first` its first
/// particle, and merges the results with `merge`, in range order.
pub fn over_ranges<D: PerParticle, S: Send>(
    bounds: &[usize],
    data: D,
    f: &(impl Fn(usize, usize, D) -> S + Sync),
    merge: &(impl Fn(S, S) -> S + Sync),
) -> S {
    from_range(0, bounds, data, f, merge)
}

/// [`over_ranges`] for work that returns nothing.
pub fn each_range<D: PerParticle>(
    bounds: &[usize],
    data: D,
    f: &(impl Fn(usize, usize, D) + Sync),
) {
    over_ranges(bounds, data, f, &|(), ()| ())
}

/// [`over_ranges`] on the ranges numbered from `k0`.
fn from_range<D: PerParticle, S: Send>(
    k0: usize,
    bounds: &[usize],
    data: D,
    f: &(impl Fn(usize, usize, D) -> S + Sync),
    merge: &(impl Fn(S, S) -> S + Sync),
) -> S {
    if bounds.len() <= 2 {
        return f(k0, bounds[0], data);
    }
    let mid = bounds.len() / 2;
    let (a, b) = data.split_at(bounds[mid] - bounds[0]);
    let (a, b) = rayon::join(
        || from_range(k0, &bounds[..=mid], a, f, merge),
        || from_range(k0 + mid, &bounds[mid..], b, f, merge),
    );
    merge(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every particle is visited once, by the range that holds it, with the right range
    /// number and first index; results are merged in range order.
    #[test]
    fn ranges_cover_the_particles_once_in_order() {
        let bounds = [0, 3, 4, 9, 12, 20];
        let mut owner = [usize::MAX; 20];
        let mut index = [0usize; 20];
        let order = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap()
            .install(|| {
                over_ranges(
                    &bounds,
                    (&mut owner[..], &mut index[..]),
                    &|k, first, (owner, index): (&mut [usize], &mut [usize])| {
                        assert_eq!(owner.len(), bounds[k + 1] - bounds[k]);
                        for (m, (o, i)) in owner.iter_mut().zip(index.iter_mut()).enumerate() {
                            *o = k;
                            *i = first + m;
                        }
                        vec![k]
                    },
                    &|mut a, b| {
                        a.extend(b);
                        a
                    },
                )
            });
        assert_eq!(order, vec![0, 1, 2, 3, 4]);
        assert_eq!(index.to_vec(), (0..20).collect::<Vec<_>>());
        for (i, &k) in owner.iter().enumerate() {
            assert!((bounds[k]..bounds[k + 1]).contains(&i));
        }
    }
}
