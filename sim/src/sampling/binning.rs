//! Slabs of width w along y (docs/physics.md section 6): which slabs an interval crosses, the exact
//! volume of a sphere inside a slab, and the method-of-planes share of a pair segment.
use std::f64::consts::PI;

/// Periodic bins `[k w, (k+1) w)`, `k = 0..n`, covering `[0, L_y)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bins {
    pub width: f64,
    pub count: usize,
}

impl Bins {
    pub fn new(width: f64, count: usize) -> Self {
        Self { width, count }
    }

    /// Bin holding the coordinate y (any real y, wrapped periodically).
    #[inline]
    pub fn index(&self, y: f64) -> usize {
        ((y / self.width).floor() as i64).rem_euclid(self.count as i64) as usize
    }

    /// Centre of bin k.
    pub fn centre(&self, k: usize) -> f64 {
        (k as f64 + 0.5) * self.width
    }

    /// Calls `visit(bin, lo, hi)` for every bin the interval `[lo, hi]` (unwrapped, `lo <=
    /// hi`) crosses, with `[lo, hi]` clipped to that bin in the same unwrapped coordinates.
    #[inline]
    pub fn for_each_overlap(&self, lo: f64, hi: f64, mut visit: impl FnMut(usize, f64, f64)) {
        let mut k = (lo / self.width).floor() as i64;
        loop {
            let (b_lo, b_hi) = (k as f64 * self.width, (k + 1) as f64 * self.width);
            let (s, e) = (lo.max(b_lo), hi.min(b_hi));
            if e > s {
                visit(k.rem_euclid(self.count as i64) as usize, s, e);
            }
            if b_hi >= hi {
                break;
            }
            k += 1;
        }
    }

    /// Adds to `volume[bin]` the exact volume of the sphere (centre y, radius a) inside
    /// each slab: `pi * [a^2 t - t^3/3]` between the slab faces, `t = y' - y` clipped to
    /// `[-a, a]` (spherical caps). The additions sum to `4/3 pi a^3` up to round-off.
    pub fn add_sphere_volume(&self, y: f64, a: f64, volume: &mut [f64]) {
        let g = |t: f64| PI * (a * a * t - t * t * t / 3.0);
        self.for_each_overlap(y - a, y + a, |k, s, e| volume[k] += g(e - y) - g(s - y));
    }

    /// Method of planes: calls `share(bin, fraction)` for every bin crossed by the
    /// centre-to-centre segment from `y_i` to `y_i + r_y`, with the fraction of the
    /// segment's y-extent inside it (fractions sum to 1). A segment with no y-extent goes
    /// whole to the bin of `y_i`.
    #[inline]
    pub fn share_segment(&self, y_i: f64, r_y: f64, mut share: impl FnMut(usize, f64)) {
        let len = r_y.abs();
        if len < 1e-12 * self.width {
            share(self.index(y_i), 1.0);
            return;
        }
        let (lo, hi) = if r_y > 0.0 {
            (y_i, y_i + r_y)
        } else {
            (y_i + r_y, y_i)
        };
        self.for_each_overlap(lo, hi, |k, s, e| share(k, (e - s) / len));
    }

    /// Calls `cross(k)` for every bin whose lower face `y = k w` (periodically) lies
    /// strictly inside the unwrapped interval `(lo, hi)`.
    #[inline]
    pub fn for_each_face(&self, lo: f64, hi: f64, mut cross: impl FnMut(usize)) {
        let mut k = (lo / self.width).floor() as i64 + 1;
        while (k as f64) * self.width < hi {
            cross(k.rem_euclid(self.count as i64) as usize);
            k += 1;
        }
    }
}
