//! Periodic orthorhombic box: wrapping and the minimum-image convention, optionally with
//! Lees-Edwards (sliding) images across the y faces for homogeneous simple shear
//! (docs/physics.md section 10).
//!
//! Under a shear rate `gdot` the copy of the box above (`y + L_y`) slides along x with the
//! velocity `gdot L_y` relative to the box, so at time t it sits shifted by the offset
//! `gdot L_y t` (taken modulo `L_x`). A particle image `n` boxes up (n = -1, 0, 1 for the
//! nearest image) is at `x + n (offset, L_y, 0)` and moves at `v + n (gdot L_y, 0, 0)`.
use crate::state::Vec3;

/// Box lengths (units a), their halves, and the Lees-Edwards state of a sheared box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicBox {
    pub len: Vec3,
    half: Vec3,
    /// x velocity of the image above relative to the box, `gdot L_y` (a / time); 0 in an
    /// unsheared box.
    shear_velocity: f64,
    /// x shift of the image above, `gdot L_y t` reduced to `[0, L_x)` (units a).
    shear_offset: f64,
}

impl PeriodicBox {
    /// A fully periodic box without shear.
    pub fn new(len: [f64; 3]) -> Self {
        let len = Vec3::from(len);
        Self {
            len,
            half: len * 0.5,
            shear_velocity: 0.0,
            shear_offset: 0.0,
        }
    }

    /// A Lees-Edwards box sheared at `gdot` (1/time, flow along x, gradient along y), at
    /// time 0 (no offset).
    pub fn sheared(len: [f64; 3], gdot: f64) -> Self {
        let mut pbox = Self::new(len);
        pbox.shear_velocity = gdot * pbox.len.y;
        pbox
    }

    /// Slides the images to time `t`: offset `gdot L_y t` modulo `L_x`. A function of the
    /// time alone, so a run continued from a checkpoint has the same offset bit for bit.
    pub fn set_time(&mut self, t: f64) {
        self.shear_offset = (self.shear_velocity * t).rem_euclid(self.len.x);
    }

    /// This box with its images slid by `offset` (units a, in `[0, L_x)`): the box a
    /// checkpointed neighbour list was built in.
    pub fn with_offset(mut self, offset: f64) -> Self {
        self.shear_offset = offset;
        self
    }

    /// Current x shift of the image above (units a, in `[0, L_x)`).
    pub fn shear_offset(&self) -> f64 {
        self.shear_offset
    }

    /// Whether the images slide (a sheared box).
    pub fn is_sheared(&self) -> bool {
        self.shear_velocity != 0.0
    }

    /// Minimum-image separation `x_j - x_i` for positions inside the box, and the index
    /// n (-1, 0 or 1) of the y image of j it points to.
    #[inline]
    pub fn image(&self, x_i: &Vec3, x_j: &Vec3) -> (Vec3, i32) {
        let mut d = x_j - x_i;
        let mut n = 0;
        if d.y > self.half.y {
            n = -1;
        } else if d.y < -self.half.y {
            n = 1;
        }
        let mut axes = [0, 2].as_slice();
        if n != 0 {
            let s = n as f64;
            d.y += s * self.len.y;
            d.x += s * self.shear_offset;
            // The offset may carry d.x beyond one box length.
            d.x -= self.len.x * (d.x / self.len.x).round();
            axes = &[2];
        }
        for &k in axes {
            if d[k] > self.half[k] {
                d[k] -= self.len[k];
            } else if d[k] < -self.half[k] {
                d[k] += self.len[k];
            }
        }
        (d, n)
    }

    /// Minimum-image separation `x_j - x_i` (through the sliding images of a sheared box).
    #[inline]
    pub fn separation(&self, x_i: &Vec3, x_j: &Vec3) -> Vec3 {
        self.image(x_i, x_j).0
    }

    /// Velocity of y image `n` relative to the original particle: `(n gdot L_y, 0, 0)`;
    /// the pair loads add it to `v_j - v_i`.
    #[inline]
    pub fn image_velocity(&self, n: i32) -> Vec3 {
        Vec3::new(n as f64 * self.shear_velocity, 0.0, 0.0)
    }

    /// Maps a position back into `[0, L)` along every axis. Leaving through a y face of a
    /// sheared box moves the particle to the sliding image it became: x shifted by the
    /// offset and `v_x` changed by the image velocity (the Lees-Edwards remap).
    #[inline]
    pub fn wrap(&self, x: &mut Vec3, v: &mut Vec3) {
        let ly = self.len.y;
        if x.y >= ly || x.y < 0.0 {
            let n = -(x.y / ly).floor();
            x.y += n * ly;
            if x.y >= ly {
                x.y -= ly;
            }
            x.x += n * self.shear_offset;
            v.x += n * self.shear_velocity;
        }
        for k in [0, 2] {
            let l = self.len[k];
            if x[k] >= l || x[k] < 0.0 {
                x[k] -= l * (x[k] / l).floor();
                if x[k] >= l {
                    x[k] -= l;
                }
            }
        }
    }
}
