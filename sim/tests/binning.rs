//! Exact slab volumes and the method-of-planes shares (docs/physics.md section 6).
use sim::sampling::binning::Bins;
use std::f64::consts::PI;

#[test]
fn sphere_volume_is_split_exactly_across_slabs_and_the_periodic_boundary() {
    let bins = Bins::new(2.0, 10);
    for (y, a) in [
        (0.3, 1.4),
        (19.9, 1.0),
        (5.0, 1.0),
        (7.77, 1.4),
        (10.0, 4.0),
    ] {
        let mut v = vec![0.0; 10];
        bins.add_sphere_volume(y, a, &mut v);
        let total = 4.0 / 3.0 * PI * a * a * a;
        assert!(
            (v.iter().sum::<f64>() - total).abs() < 1e-12 * total,
            "y {y} a {a}"
        );
        assert!(v.iter().all(|&x| x >= 0.0));
    }
    // A sphere centred on a face puts half its volume on each side.
    let mut v = vec![0.0; 10];
    bins.add_sphere_volume(4.0, 1.0, &mut v);
    assert!((v[1] - v[2]).abs() < 1e-14 && (v[1] - 2.0 / 3.0 * PI).abs() < 1e-12);
    // Centred at y = 0: half in the last bin (wrapped), half in the first.
    let mut v = vec![0.0; 10];
    bins.add_sphere_volume(0.0, 1.0, &mut v);
    assert!((v[0] - v[9]).abs() < 1e-14 && v[0] > 0.0);
}

#[test]
fn segment_shares_follow_the_length_inside_each_bin() {
    let bins = Bins::new(2.0, 10);
    let mut shares = [0.0; 10];
    // From y = 1.5 up by 2.5: 0.5 in bin 0, 2.0 in bin 1 -> 0.2, 0.8.
    bins.share_segment(1.5, 2.5, |k, f| shares[k] += f);
    assert!((shares[0] - 0.2).abs() < 1e-12 && (shares[1] - 0.8).abs() < 1e-12);
    // Downwards across the periodic boundary: from 0.5 down by 1.5 -> 0.5 in bin 0, 1.0 in bin 9.
    let mut shares = [0.0; 10];
    bins.share_segment(0.5, -1.5, |k, f| shares[k] += f);
    assert!((shares[0] - 1.0 / 3.0).abs() < 1e-12 && (shares[9] - 2.0 / 3.0).abs() < 1e-12);
    // Horizontal pair: all to the bin of the first particle.
    let mut shares = [0.0; 10];
    bins.share_segment(7.0, 0.0, |k, f| shares[k] += f);
    assert_eq!(shares[3], 1.0);
    // Faces crossed: from 1.5 to 4.5 crosses y = 2 (bin 1) and y = 4 (bin 2).
    let mut faces = Vec::new();
    bins.for_each_face(1.5, 4.5, |k| faces.push(k));
    assert_eq!(faces, vec![1, 2]);
    let mut faces = Vec::new();
    bins.for_each_face(-0.5, 0.5, |k| faces.push(k));
    assert_eq!(faces, vec![0]);
}
