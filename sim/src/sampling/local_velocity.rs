//! The local velocity fluctuation of Theta (thesis eq 6.1 and section 6.3, docs/physics.md
//! section 6): per snapshot, `du_i = |v_x,i - u*_i|` with `u*_i` the mean x-velocity of the
//! particles whose centres lie within `+-h` of `y_i` along the periodic y axis (particle i
//! included). Particles are sorted by y once per snapshot and the window slides over the
//! sorted list with prefix sums: `O(N log N)`, no allocation once the buffers have grown.
use crate::state::Vec3;

/// Scratch buffers kept between snapshots.
#[derive(Clone, Debug, Default)]
pub struct LocalVelocity {
    order: Vec<usize>,
    /// Sorted wrapped heights.
    y: Vec<f64>,
    /// Prefix sums of the sorted x-velocities over three periods (`3N + 1` values).
    prefix: Vec<f64>,
    /// `|v_x,i - u*_i|`, in particle order.
    deviation: Vec<f64>,
}

impl LocalVelocity {
    /// `|v_x,i - u*_i|` for every particle, with the window half-width `h` (`< l_y / 2`) on
    /// the period `l_y`.
    pub fn deviations(&mut self, pos: &[Vec3], vel: &[Vec3], l_y: f64, h: f64) -> &[f64] {
        debug_assert!(2.0 * h < l_y, "window wider than the period");
        let n = pos.len();
        let wrapped = |i: usize| pos[i].y.rem_euclid(l_y);
        self.order.clear();
        self.order.extend(0..n);
        self.order
            .sort_unstable_by(|&i, &j| wrapped(i).total_cmp(&wrapped(j)).then(i.cmp(&j)));
        self.y.clear();
        self.y.extend(self.order.iter().map(|&i| wrapped(i)));
        // prefix[m] = sum of the sorted velocities of virtual indices -n .. m - n - 1, where
        // virtual index j is sorted particle j mod n shifted by floor(j / n) periods.
        self.prefix.clear();
        self.prefix.push(0.0);
        for m in 0..3 * n {
            let v = vel[self.order[m % n]].x;
            self.prefix.push(self.prefix[m] + v);
        }
        let virtual_y = |j: i64| {
            let k = j.rem_euclid(n as i64) as usize;
            self.y[k] + l_y * j.div_euclid(n as i64) as f64
        };
        self.deviation.clear();
        self.deviation.resize(n, 0.0);
        let (mut lo, mut hi) = (-(n as i64), -(n as i64));
        for k in 0..n {
            let centre = self.y[k];
            while virtual_y(lo) < centre - h {
                lo += 1;
            }
            while hi < 2 * n as i64 && virtual_y(hi) <= centre + h {
                hi += 1;
            }
            // Window = virtual indices lo .. hi - 1.
            let at = |j: i64| self.prefix[(j + n as i64) as usize];
            let mean = (at(hi) - at(lo)) / (hi - lo) as f64;
            let i = self.order[k];
            self.deviation[i] = (vel[i].x - mean).abs();
        }
        &self.deviation
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `|v_i - mean of v_j over |y_j - y_i|_periodic <= h|`, the definition by brute force.
    fn brute_force(pos: &[Vec3], vel: &[Vec3], l_y: f64, h: f64) -> Vec<f64> {
        (0..pos.len())
            .map(|i| {
                let near: Vec<f64> = (0..pos.len())
                    .filter(|&j| {
                        let d = (pos[j].y - pos[i].y).rem_euclid(l_y);
                        d.min(l_y - d) <= h
                    })
                    .map(|j| vel[j].x)
                    .collect();
                (vel[i].x - near.iter().sum::<f64>() / near.len() as f64).abs()
            })
            .collect()
    }

    #[test]
    fn sliding_window_matches_the_definition_across_the_periodic_faces() {
        let l_y = 10.0;
        // Deterministic scatter, some heights outside [0, L_y) and near both faces.
        let n = 200;
        let pos: Vec<Vec3> = (0..n)
            .map(|i| {
                let y =
                    ((i * 7919) % 1013) as f64 / 1013.0 * l_y - if i % 9 == 0 { l_y } else { 0.0 };
                Vec3::new(0.0, y, 0.0)
            })
            .collect();
        let vel: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new((((i * 31) % 17) as f64 - 8.0) / 10.0, 0.0, 0.0))
            .collect();
        let mut local = LocalVelocity::default();
        for h in [0.01, 0.12, 0.7] {
            let fast = local.deviations(&pos, &vel, l_y, h).to_vec();
            let slow = brute_force(&pos, &vel, l_y, h);
            for i in 0..n {
                assert!(
                    (fast[i] - slow[i]).abs() < 1e-12,
                    "h = {h}, particle {i}: {} vs {}",
                    fast[i],
                    slow[i]
                );
            }
        }
        // A uniformly moving layer has no fluctuation.
        let still: Vec<Vec3> = vel.iter().map(|_| Vec3::new(0.3, 0.0, 0.0)).collect();
        assert!(local
            .deviations(&pos, &still, l_y, 0.12)
            .iter()
            .all(|d| d.abs() < 1e-12));
    }
}
