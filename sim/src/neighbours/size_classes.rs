//! Candidate pairs of a mixture of very different sizes (colloids and grains, thesis
//! chapter 5) from two cell lists, one per size class, so that a colloid does not scan
//! cells as wide as the grains' reach.
//!
//! One cell list sized for the largest pair (14.6 a for radii 7 and 7) makes every colloid
//! look through 27 cells of that width, some 2700 candidates at phi 0.64, for about 15
//! neighbours. Here the small particles sit in cells sized for the small pairs and the
//! large in cells sized for the largest pair. A small particle finds the small ones in the
//! adjacent small cells and the large ones in the adjacent large cells; a large particle
//! finds the large ones in the adjacent large cells and the small ones within enough rings
//! of small cells to cover the small-large reach. Every pair within its reach is found from
//! both of its particles, as with one cell list.
use crate::neighbours::cell_list::{CellList, MAX_RINGS};
use crate::state::periodic_box::PeriodicBox;
use crate::state::Vec3;

/// Smallest ratio of the largest pair reach to the largest small-pair reach for which two
/// classes are used: below it one cell list costs little more.
pub const SPLIT_RATIO: f64 = 2.0;

/// The size classes of `n_species` species whose pairs reach `cutoff(s, t)`: a species is
/// large when its own pairs reach at least [`SPLIT_RATIO`] times as far as the shortest
/// species' own pairs. Returns the class of each species and the largest reaches (cut-off
/// plus `skin`) of small-small, small-large and any pairs, as [`CandidateCells::build`]
/// takes them.
pub fn classify(
    n_species: usize,
    skin: f64,
    cutoff: impl Fn(u16, u16) -> f64,
) -> (Vec<bool>, [f64; 3]) {
    let species = 0..n_species as u16;
    let own = |s: u16| cutoff(s, s);
    let shortest = species.clone().map(own).fold(f64::INFINITY, f64::min);
    let large: Vec<bool> = species
        .clone()
        .map(|s| own(s) >= SPLIT_RATIO * shortest)
        .collect();
    let mut reaches = [0.0f64; 3];
    for s in species.clone() {
        for t in species.clone() {
            let class = match (large[s as usize], large[t as usize]) {
                (false, false) => 0,
                (true, true) => 2,
                _ => 1,
            };
            reaches[class] = reaches[class].max(cutoff(s, t) + skin);
        }
    }
    let max = reaches.iter().cloned().fold(0.0, f64::max);
    (large, [reaches[0], reaches[1], max])
}

/// Where the candidates of a particle are looked up.
pub enum CandidateCells {
    /// Every particle in one cell list sized for the largest pair.
    Single(CellList),
    /// Two size classes.
    Classes(SizeClasses),
}

/// The two cell lists of a mixture and the class of every particle.
pub struct SizeClasses {
    small: CellList,
    large: CellList,
    is_large: Vec<bool>,
    /// Rings of small cells a large particle searches for small neighbours.
    rings: usize,
}

impl CandidateCells {
    /// The cells for `positions` where particle `i` is of the large class when
    /// `is_large[i]`: `reach_small` is the largest reach (cut-off plus skin) of a pair of
    /// small particles, `reach_mixed` of a small and a large one, `reach_max` of any pair.
    /// Two classes when the large reach is at least [`SPLIT_RATIO`] times the small one,
    /// both classes are present and the small cells allow the rings a large particle needs
    /// (in a sheared box, `2 rings + 1` rows along y); one cell list otherwise.
    pub fn build(
        positions: &[Vec3],
        pbox: &PeriodicBox,
        is_large: Vec<bool>,
        [reach_small, reach_mixed, reach_max]: [f64; 3],
    ) -> Self {
        let single = || CandidateCells::Single(CellList::build(positions, pbox, reach_max));
        let large: Vec<u32> = (0..positions.len() as u32)
            .filter(|&i| is_large[i as usize])
            .collect();
        if reach_max < SPLIT_RATIO * reach_small
            || large.is_empty()
            || large.len() == positions.len()
        {
            return single();
        }
        let small: Vec<u32> = (0..positions.len() as u32)
            .filter(|&i| !is_large[i as usize])
            .collect();
        let small = CellList::build_of(positions, pbox, reach_small, &small);
        let rings = (reach_mixed / small.min_cell_size()).ceil() as usize;
        let rows_needed = if pbox.is_sheared() { 2 * rings + 1 } else { 0 };
        if rings > MAX_RINGS || small.dims()[1] < rows_needed {
            return single();
        }
        CandidateCells::Classes(SizeClasses {
            small,
            large: CellList::build_of(positions, pbox, reach_max, &large),
            is_large,
            rings,
        })
    }

    /// Calls `visit(j)` for every candidate neighbour `j` of particle `i` at `x` (`i`
    /// itself included; each candidate once).
    pub fn for_each_candidate(&self, i: usize, x: &Vec3, mut visit: impl FnMut(u32)) {
        match self {
            CandidateCells::Single(cells) => cells.for_each_near(x, visit),
            CandidateCells::Classes(c) => {
                c.large.for_each_near(x, &mut visit);
                let rings = if c.is_large[i] { c.rings } else { 1 };
                c.small.for_each_within(x, rings, visit);
            }
        }
    }
}
