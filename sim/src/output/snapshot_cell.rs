//! The periodic cell a snapshot frame records: the box's edges `a = (L_x, 0, 0)`,
//! `b = (t, L_y, 0)`, `c = (0, 0, L_z)` (units a). In a Lees-Edwards box the image above sits
//! shifted along x by the current offset (docs/physics.md section 10), so the box tiles space
//! as this sheared cell with the tilt `t` = offset, reduced to `[-L_x/2, L_x/2)` (an equivalent
//! edge, `b - a`, once the offset passes half the box); `t = 0` without shear.
use crate::state::periodic_box::PeriodicBox;

/// Edge lengths and the xy tilt of a frame's cell (units a).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnapshotCell {
    pub len: [f64; 3],
    /// x component of the y edge, `b_x` (units a).
    pub tilt_xy: f64,
    /// Whether the box is a Lees-Edwards one (its tilt changes from frame to frame, and is 0
    /// at some).
    pub sheared: bool,
}

impl SnapshotCell {
    /// The cell `pbox` tiles space with at its current time.
    pub fn of(pbox: &PeriodicBox) -> Self {
        let l = pbox.len;
        let offset = pbox.shear_offset();
        let tilt_xy = if offset >= 0.5 * l.x {
            offset - l.x
        } else {
            offset
        };
        Self {
            len: [l.x, l.y, l.z],
            tilt_xy,
            sheared: pbox.is_sheared(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilt_is_the_offset_reduced_to_half_a_box() {
        let unsheared = SnapshotCell::of(&PeriodicBox::new([10.0, 12.0, 9.0]));
        assert_eq!(unsheared.tilt_xy, 0.0);
        assert!(!unsheared.sheared);
        // gdot L_y t = 0.05 * 12 * t: offsets 3 (kept) and 9 (= -1 after one box length).
        let mut pbox = PeriodicBox::sheared([10.0, 12.0, 9.0], 0.05);
        pbox.set_time(5.0);
        assert!((SnapshotCell::of(&pbox).tilt_xy - 3.0).abs() < 1e-12);
        pbox.set_time(15.0);
        assert!((SnapshotCell::of(&pbox).tilt_xy + 1.0).abs() < 1e-12);
        assert_eq!(SnapshotCell::of(&pbox).len, [10.0, 12.0, 9.0]);
        assert!(SnapshotCell::of(&pbox).sheared);
    }
}
