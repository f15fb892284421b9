//! The neighbour search for colloid-grain mixtures (thesis chapter 5: radii 1 : 1.4 and
//! 5 : 7 together): the Verlet list built from one cell list for the largest pair's reach,
//! or from one cell list per size class, holds exactly the pairs a brute-force search over
//! all pairs finds, each pair with its own reach, in a plain and in a sheared
//! (Lees-Edwards) periodic box.
use rand::{Rng, SeedableRng};
use sim::neighbours::cell_list::CellList;
use sim::neighbours::size_classes::{classify, CandidateCells};
use sim::neighbours::verlet_list::VerletList;
use sim::state::periodic_box::PeriodicBox;
use sim::Vec3;

const RADII: [f64; 4] = [1.0, 1.4, 5.0, 7.0];
/// Lubrication cut-off of the dimensionless gap: a pair reaches `(a_i + a_j)(1 + XI_MAX / 2)`.
const XI_MAX: f64 = 0.05;
const SKIN: f64 = 0.2;

fn reach(a_i: f64, a_j: f64) -> f64 {
    (a_i + a_j) * (1.0 + XI_MAX / 2.0)
}

/// Every pair i < j closer than its reach plus the skin, by looking at all pairs.
fn brute_force(positions: &[Vec3], radii: &[f64], pbox: &PeriodicBox) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    for i in 0..positions.len() {
        for j in i + 1..positions.len() {
            let d = pbox.separation(&positions[i], &positions[j]).norm();
            if d < reach(radii[i], radii[j]) + SKIN {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

fn listed(list: &VerletList) -> Vec<(usize, usize)> {
    (0..list.start.len() - 1)
        .flat_map(|i| {
            list.neighbours[list.start[i]..list.start[i + 1]]
                .iter()
                .map(move |&j| (i, j as usize))
        })
        .collect()
}

#[test]
fn cell_and_verlet_lists_hold_every_pair_of_a_colloid_grain_mixture() {
    // 800 centres, uniform in a box 36 x 40 x 36 (2.6-2.9 grain diameters of radius 7),
    // a quarter of each species; overlaps do not matter to the search.
    let len = [36.0, 40.0, 36.0];
    let mut rng = rand::rngs::StdRng::seed_from_u64(29);
    let n = 800;
    let radii: Vec<f64> = (0..n).map(|k| RADII[k % 4]).collect();
    let positions: Vec<Vec3> = (0..n)
        .map(|_| {
            Vec3::new(
                rng.gen_range(0.0..len[0]),
                rng.gen_range(0.0..len[1]),
                rng.gen_range(0.0..len[2]),
            )
        })
        .collect();
    let largest = reach(7.0, 7.0);
    for pbox in [
        PeriodicBox::new(len),
        PeriodicBox::sheared(len, 0.01).with_offset(13.7),
    ] {
        let expected = brute_force(&positions, &radii, &pbox);
        // The test means something only if every kind of pair occurs.
        let kinds = |a: f64, b: f64| {
            expected
                .iter()
                .filter(|&&(i, j)| (radii[i], radii[j]) == (a, b) || (radii[i], radii[j]) == (b, a))
                .count()
        };
        assert!(kinds(1.0, 1.4) > 0 && kinds(1.0, 7.0) > 0 && kinds(7.0, 7.0) > 0);
        // One cell list for the largest pair, and the two size classes (radii 1 and 1.4
        // small, 5 and 7 large).
        let single = CandidateCells::Single(CellList::build(&positions, &pbox, largest + SKIN));
        let is_large: Vec<bool> = radii.iter().map(|&a| a > 2.0).collect();
        let reaches = [
            reach(1.4, 1.4) + SKIN,
            reach(1.4, 7.0) + SKIN,
            largest + SKIN,
        ];
        let classes = CandidateCells::build(&positions, &pbox, is_large, reaches);
        assert!(matches!(classes, CandidateCells::Classes(_)));
        for cells in [single, classes] {
            let list = VerletList::build(&positions, &pbox, &cells, SKIN, |i, j| {
                reach(radii[i], radii[j])
            });
            assert_eq!(listed(&list), expected, "sheared: {}", pbox.is_sheared());
        }
    }
}

#[test]
fn colloids_and_grains_fall_into_two_size_classes_and_bidisperse_colloids_into_one() {
    let by_radius = |radii: &[f64]| {
        classify(radii.len(), SKIN, |s, t| {
            reach(radii[s as usize], radii[t as usize])
        })
    };
    let (large, reaches) = by_radius(&RADII);
    assert_eq!(large, vec![false, false, true, true]);
    let expected = [reach(1.4, 1.4), reach(1.4, 7.0), reach(7.0, 7.0)].map(|r| r + SKIN);
    for (got, want) in reaches.iter().zip(expected) {
        assert!((got - want).abs() < 1e-12, "{reaches:?}");
    }
    // Radii 1 : 1.4 (and 1 : 1.9): one class, so one cell list as before.
    assert_eq!(by_radius(&[1.0, 1.4]).0, vec![false, false]);
    assert_eq!(by_radius(&[1.0, 1.9]).0, vec![false, false]);
}
