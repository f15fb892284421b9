//! Fully periodic orthorhombic box: wrapping and the minimum-image convention.
use crate::Vec3;

/// Box lengths (units a) and their halves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicBox {
    pub len: Vec3,
    half: Vec3,
}

impl PeriodicBox {
    pub fn new(len: [f64; 3]) -> Self {
        let len = Vec3::from(len);
        Self {
            len,
            half: len * 0.5,
        }
    }

    /// Minimum-image separation `x_j - x_i` for positions already inside the box.
    #[inline]
    pub fn separation(&self, x_i: &Vec3, x_j: &Vec3) -> Vec3 {
        let mut d = x_j - x_i;
        for k in 0..3 {
            if d[k] > self.half[k] {
                d[k] -= self.len[k];
            } else if d[k] < -self.half[k] {
                d[k] += self.len[k];
            }
        }
        d
    }

    /// Maps a position back into `[0, L)` along every axis.
    #[inline]
    pub fn wrap(&self, x: &mut Vec3) {
        for k in 0..3 {
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
