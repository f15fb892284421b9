//! The `ext` mapping's nonlocal input: each bin's distance to the nearest velocity extremum
//! of its profile (docs/physics.md section 8).
//!
//! On `n` periodic bins of width `w`, bin `k` centred at `y_k = (k + 1/2) w`, the face shear
//! rates are `g_k = (u_{k+1} - u_k) / w` at `y = (k + 1) w`. A velocity extremum lies where
//! they change sign: between faces `k` and `k + 1` at `(k + 1) w + w g_k / (g_k - g_{k+1})`
//! (linear interpolation; at face `k` itself when `g_k = 0`). A point's distance is the
//! periodic distance to the nearest such zero; a profile without one (uniform `u`) puts every
//! point `L / 2` away. The same rule serves the datasets' rows (the bin velocities `u`) and
//! the profile solver's unknowns, so the solver evaluates the feature as it was trained.
//!
//! Why this input: beside a velocity extremum the shear stress passes through zero while the
//! bands beside it keep the bin sheared, so bins of one J and phi_loc differ 2x in mu by
//! where they sit (plugs_003: mu 0.41 at y = 7, 0.84 at y = 13). The bin velocities'
//! differences place the extremum; the spectral `gdot` of the tables rings near sharp bands
//! and places it worse (leave-one-family-out, docs/physics.md section 8).

use std::borrow::Cow;
use std::collections::HashMap;

use crate::data::dataset::{Dataset, GROUP_COLUMN};
use crate::error::{Result, SurrogateError};
use schema::columns as col;

/// Positions (units a, in `[0, n w)`) of the zeros of the face shear rates of the bin
/// velocities `u` on periodic bins of width `width`, in increasing order of the face before
/// them.
pub fn shear_zeros(u: &[f64], width: f64) -> Vec<f64> {
    shear_zero_faces(u, width)
        .into_iter()
        .map(|z| z.position)
        .collect()
}

/// A zero of the face shear rates: where it lies, and the face `k` after which it does
/// (between faces `k` and `k + 1`, or on face `k`), whose rate is `g_k` and the next's
/// `g_{k+1}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearZero {
    pub position: f64,
    pub face: usize,
    pub rates: (f64, f64),
}

impl ShearZero {
    /// `d position / d (u_k, u_{k+1}, u_{k+2})` on bins of width `width`: the zero
    /// `(k + 1) w + w a / (a - b)` with `a = g_k = (u_{k+1} - u_k) / w` and
    /// `b = g_{k+1} = (u_{k+2} - u_{k+1}) / w` moves by `dz/da = -w b / (a - b)^2` and
    /// `dz/db = w a / (a - b)^2`.
    pub fn gradient(&self, width: f64) -> [f64; 3] {
        let (a, b) = self.rates;
        let d = (a - b) * (a - b);
        let (dz_da, dz_db) = (-width * b / d, width * a / d);
        // da/du = (-1, 1, 0) / w, db/du = (0, -1, 1) / w.
        [-dz_da / width, (dz_da - dz_db) / width, dz_db / width]
    }
}

/// The zeros of [`shear_zeros`], with their faces and rates.
pub fn shear_zero_faces(u: &[f64], width: f64) -> Vec<ShearZero> {
    let n = u.len();
    let length = n as f64 * width;
    let g: Vec<f64> = (0..n).map(|k| (u[(k + 1) % n] - u[k]) / width).collect();
    let mut zeros = Vec::new();
    for k in 0..n {
        let (a, b) = (g[k], g[(k + 1) % n]);
        let face = (k + 1) as f64 * width;
        if (a == 0.0 && b != 0.0) || a * b < 0.0 {
            zeros.push(ShearZero {
                position: (face + width * a / (a - b)) % length,
                face: k,
                rates: (a, b),
            });
        }
    }
    zeros
}

/// The periodic distance (period `length`) from `y` to the nearest of `zeros`; `length / 2`
/// without zeros.
pub fn distance_to_nearest(y: f64, zeros: &[f64], length: f64) -> f64 {
    zeros
        .iter()
        .map(|&z| {
            let d = (y - z).rem_euclid(length);
            d.min(length - d)
        })
        .fold(0.5 * length, f64::min)
}

/// Each bin centre's distance (units a) to the nearest velocity extremum of the bin
/// velocities `u` on periodic bins of width `width`.
pub fn extremum_distances(u: &[f64], width: f64) -> Vec<f64> {
    let zeros = shear_zeros(u, width);
    let length = u.len() as f64 * width;
    (0..u.len())
        .map(|k| distance_to_nearest((k as f64 + 0.5) * width, &zeros, length))
        .collect()
}

/// [`col::EXTREMUM_DISTANCE`] for every row of `dataset`, from the `u` and `y` of the rows of
/// its profile: the rows of one run ([`GROUP_COLUMN`] and, in a per-run table, `seed`),
/// ordered by `y`, which must be the centres of equal periodic bins filling `L_y`. A row whose
/// `u` is empty has none (NaN), and neither do the rows of its profile.
pub fn extremum_distance_column(dataset: &Dataset) -> Result<Vec<f64>> {
    let ids = dataset.group_keys()?;
    let seeds = dataset
        .column_names()
        .iter()
        .any(|c| c == col::SEED)
        .then(|| dataset.text(col::SEED))
        .transpose()?;
    let (y, u, l_y) = (
        dataset.column(col::Y)?,
        dataset.column(col::U)?,
        dataset.column(col::L_Y)?,
    );
    let mut profiles: HashMap<(&str, &str), Vec<usize>> = HashMap::new();
    for row in 0..dataset.n_rows() {
        let seed = seeds.map_or("", |s| s[row].as_str());
        profiles
            .entry((ids[row].as_str(), seed))
            .or_default()
            .push(row);
    }
    let mut distances = vec![f64::NAN; dataset.n_rows()];
    for mut rows in profiles.into_values() {
        rows.sort_by(|&a, &b| y[a].total_cmp(&y[b]));
        let length = l_y[rows[0]];
        let width = length / rows.len() as f64;
        let first = rows[0];
        let misplaced = rows
            .iter()
            .enumerate()
            .find(|&(k, &row)| ((k as f64 + 0.5) * width - y[row]).abs() > 1e-6 * width);
        if let Some((k, &row)) = misplaced {
            return Err(SurrogateError::InvalidArgument(format!(
                "{}: the {} rows of scene `{}` are not the centres of equal bins filling \
                 L_y = {length} (data row {} has y = {}, bin {k} is centred at {}): `{}` \
                 needs whole profiles",
                dataset.source_name(),
                rows.len(),
                ids[first],
                row + 1,
                y[row],
                (k as f64 + 0.5) * width,
                col::EXTREMUM_DISTANCE
            )));
        }
        let velocities: Vec<f64> = rows.iter().map(|&row| u[row]).collect();
        if velocities.iter().any(|v| !v.is_finite()) {
            continue;
        }
        for (row, d) in rows.iter().zip(extremum_distances(&velocities, width)) {
            distances[*row] = d;
        }
    }
    Ok(distances)
}

/// `dataset` with the derived column [`col::EXTREMUM_DISTANCE`] added when `features` name
/// it and the table lacks it (a table may carry its own); otherwise `dataset` itself.
pub fn with_derived_features<'a, S: AsRef<str>>(
    dataset: &'a Dataset,
    features: &[S],
) -> Result<Cow<'a, Dataset>> {
    let name = col::EXTREMUM_DISTANCE;
    let needed = features.iter().any(|f| f.as_ref() == name);
    if !needed || dataset.column_names().iter().any(|c| c == name) {
        return Ok(Cow::Borrowed(dataset));
    }
    let values = extremum_distance_column(dataset).map_err(|e| {
        SurrogateError::InvalidArgument(format!(
            "the input `{name}` (distance to the nearest velocity extremum) is derived from \
             each profile's `{}`, `{}`, `{}` and `{}` columns, or read from a `{name}` \
             column: {e}",
            GROUP_COLUMN,
            col::Y,
            col::U,
            col::L_Y
        ))
    })?;
    Ok(Cow::Owned(dataset.with_column(name, &values)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// u = sin(2 pi y / L) on 20 bins of width 2: the extrema at L/4 = 10 and 3L/4 = 30.
    #[test]
    fn a_sine_has_its_extrema_at_the_quarter_periods() {
        let (n, w) = (20, 2.0);
        let l = n as f64 * w;
        let u: Vec<f64> = (0..n)
            .map(|k| (2.0 * PI * (k as f64 + 0.5) * w / l).sin())
            .collect();
        let zeros = shear_zeros(&u, w);
        assert_eq!(zeros.len(), 2, "{zeros:?}");
        // The bin velocities' differences are symmetric about the extrema, so the linear
        // interpolation puts the zeros on them exactly.
        assert!((zeros[0] - 10.0).abs() < 1e-9 && (zeros[1] - 30.0).abs() < 1e-9);
        let d = extremum_distances(&u, w);
        // Bin 4 is centred at y = 9, bin 0 at y = 1 (9 from the extremum at 10, 11 from the
        // one at 30 across the period).
        assert!(
            (d[4] - 1.0).abs() < 1e-9 && (d[0] - 9.0).abs() < 1e-9,
            "{d:?}"
        );
        assert!(d.iter().all(|&x| (0.0..=10.0).contains(&x)));
    }

    #[test]
    fn a_zero_moves_with_the_velocities_as_its_gradient_says() {
        let u = [0.0, 1.0, 1.5, 0.7, -0.2];
        let (w, h) = (2.0, 1e-7);
        let zeros = shear_zero_faces(&u, w);
        for z in &zeros {
            let gradient = z.gradient(w);
            for (i, g) in gradient.iter().enumerate() {
                let bin = (z.face + i) % u.len();
                let mut moved = u;
                moved[bin] += h;
                let after = shear_zero_faces(&moved, w)
                    .into_iter()
                    .find(|m| m.face == z.face)
                    .unwrap();
                let numeric = (after.position - z.position) / h;
                assert!((numeric - g).abs() < 1e-5, "bin {bin}: {numeric} vs {g}");
            }
        }
    }

    #[test]
    fn a_zero_at_the_period_edge_is_seen_from_both_sides_and_uniform_flow_has_none() {
        // Differences +, +, -, - , ...: u rises then falls; the wrap from the last face to
        // the first also changes sign.
        let u = [0.0, 1.0, 2.0, 1.0];
        let zeros = shear_zeros(&u, 1.0);
        assert_eq!(zeros.len(), 2, "{zeros:?}");
        for &z in &zeros {
            assert!((0.0..4.0).contains(&z));
        }
        assert!((distance_to_nearest(3.9, &[0.1], 4.0) - 0.2).abs() < 1e-12);
        assert_eq!(extremum_distances(&[1.0; 4], 1.0), vec![2.0; 4]);
    }

    #[test]
    fn a_table_gets_one_profile_per_run_in_any_row_order() {
        let csv = "scene_id,seed,L_y,y,u\n\
                   a,1,4,3,1\na,1,4,1,1\na,1,4,2,2\na,1,4,0.5,0\n";
        // Rows out of order, and y not bin centres: refused with the row named.
        let data = Dataset::from_csv_bytes(csv.as_bytes(), "t").unwrap();
        let message = extremum_distance_column(&data).unwrap_err().to_string();
        assert!(message.contains("scene `a`"), "{message}");
        let csv = "scene_id,seed,L_y,y,u\n\
                   a,1,4,3.5,1\na,1,4,0.5,0\na,2,4,0.5,0\na,1,4,1.5,1\na,1,4,2.5,2\n\
                   a,2,4,1.5,0\na,2,4,2.5,0\na,2,4,3.5,0\n";
        let data = Dataset::from_csv_bytes(csv.as_bytes(), "t").unwrap();
        let d = extremum_distance_column(&data).unwrap();
        let run1 = extremum_distances(&[0.0, 1.0, 2.0, 1.0], 1.0);
        assert_eq!(
            [d[1], d[3], d[4], d[0]],
            [run1[0], run1[1], run1[2], run1[3]]
        );
        // Seed 2 is uniform: every bin half the period away.
        assert_eq!([d[2], d[5], d[6], d[7]], [2.0; 4]);
    }
}
