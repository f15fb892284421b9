//! Synthetic datasets with the schema of docs/physics.md section 8 and known smooth relations, so that a
//! working pipeline must reach small errors and a broken one cannot.
#![allow(dead_code)] // each test file uses a different part

use std::path::PathBuf;

use surrogate::Dataset;

/// The relations the synthetic data follow, for features `J`, `Theta` and global `phi`:
/// `phi_loc = phi + 0.04 (1 + log10 Theta)`, `mu = 0.3 + 0.5 J^0.4 + 0.3 (phi_loc - 0.5) + 0.1 phi`,
/// `Delta_v = 0.05 + 0.3 Theta`.
pub fn phi_loc_of(theta: f64, phi: f64) -> f64 {
    phi + 0.04 * (1.0 + theta.log10())
}

pub fn mu_of(j: f64, phi_loc: f64, phi: f64) -> f64 {
    0.3 + 0.5 * j.powf(0.4) + 0.3 * (phi_loc - 0.5) + 0.1 * phi
}

pub fn delta_v_of(theta: f64) -> f64 {
    0.05 + 0.3 * theta
}

/// A small deterministic generator (64-bit LCG, Knuth's constants) giving uniforms in [0, 1).
pub struct Lcg(u64);

impl Lcg {
    pub fn new(seed: u64) -> Self {
        Lcg(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1)
    }

    pub fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

const COLUMNS: &[&str] = &[
    "scene_id",
    "profile",
    "L_y",
    "phi",
    "seed",
    "y",
    "u_inf",
    "u",
    "gdot",
    "sigma_xy",
    "P",
    "phi_loc",
    "J",
    "mu",
    "Theta",
    "Delta_v",
    "u_se",
    "gdot_se",
    "sigma_xy_se",
    "P_se",
    "phi_loc_se",
    "J_se",
    "mu_se",
    "Theta_se",
    "Delta_v_se",
];

/// CSV text of `n_scenes` fake simulations with `rows_per_scene` bins each, cycling through
/// phi in {0.50, 0.52, 0.54, 0.56} and L_y in {50, 100} like the seeds' training grid. `J` is
/// log-uniform in [1e-3, 1e-1] and `Theta` log-uniform in [1e-2, 1].
pub fn synthetic_csv(n_scenes: usize, rows_per_scene: usize, seed: u64) -> String {
    let mut rng = Lcg::new(seed);
    let mut csv = COLUMNS.join(",") + "\n";
    for scene in 0..n_scenes {
        let phi = [0.50, 0.52, 0.54, 0.56][scene % 4];
        let l_y = [50.0, 100.0][(scene / 4) % 2];
        for bin in 0..rows_per_scene {
            let y = (bin as f64 + 0.5) * l_y / rows_per_scene as f64;
            let u_inf = 0.1 * (2.0 * std::f64::consts::PI * y / l_y).sin();
            let j = 10f64.powf(-3.0 + 2.0 * rng.uniform());
            let theta = 10f64.powf(-2.0 + 2.0 * rng.uniform());
            let phi_loc = phi_loc_of(theta, phi);
            let mu = mu_of(j, phi_loc, phi);
            let delta_v = delta_v_of(theta);
            let pressure = 1.0 + rng.uniform();
            let u = u_inf * (1.0 - delta_v);
            let values = [
                l_y,
                phi,
                seed as f64,
                y,
                u_inf,
                u,
                j * pressure,
                mu * pressure,
                pressure,
                phi_loc,
                j,
                mu,
                theta,
                delta_v,
            ];
            let numbers: Vec<String> = values.iter().map(f64::to_string).collect();
            let errors = ["0.001"; 9];
            csv += &format!(
                "s{scene},0.1*sin(2*pi*y/L),{},{}\n",
                numbers.join(","),
                errors.join(",")
            );
        }
    }
    csv
}

/// [`synthetic_csv`] read as a dataset.
pub fn synthetic_dataset(n_scenes: usize, rows_per_scene: usize, seed: u64) -> Dataset {
    Dataset::from_csv_bytes(
        synthetic_csv(n_scenes, rows_per_scene, seed).as_bytes(),
        "synthetic",
    )
    .unwrap()
}

/// A fresh, empty directory for one test's files.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// [`synthetic_csv`] with the scenes spread over `families` profile families: scene `s`
/// gets the profile `0.<f+1>*sin(2*pi*y/L)` with `f = s % families` (the other cells are
/// unchanged).
pub fn synthetic_csv_with_families(
    n_scenes: usize,
    rows_per_scene: usize,
    seed: u64,
    families: usize,
) -> String {
    let csv = synthetic_csv(n_scenes, rows_per_scene, seed);
    let mut lines = csv.lines();
    let mut out = lines.next().unwrap().to_owned() + "\n";
    for line in lines {
        let (scene, rest) = line.split_once(',').unwrap();
        let s: usize = scene[1..].parse().unwrap();
        let profile = format!("0.{}*sin(2*pi*y/L)", s % families + 1);
        out += &format!(
            "{scene},{}\n",
            rest.replacen("0.1*sin(2*pi*y/L)", &profile, 1)
        );
    }
    out
}
