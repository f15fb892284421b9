//! The dataset's column names, defined once (docs/physics.md section 8): every table of
//! binned results (`simulate`'s `profile.csv`, `generate`'s datasets, `solve`'s profiles) and
//! every reader of them (`merge`, `compare`, `plot`, the surrogate's mappings) take the names
//! from here. A row is one bin of one scene: the scene and bin columns, then each observable
//! followed by its standard error.

/// Scene id (also the grouping key of cross-validation).
pub const SCENE_ID: &str = "scene_id";
/// The streaming flow u_inf(y) as written in the scene file.
pub const PROFILE: &str = "profile";
pub const L_Y: &str = "L_y";
/// Global volume fraction.
pub const PHI: &str = "phi";
pub const SEED: &str = "seed";
/// Strain at which the run was steady.
pub const STEADY_STRAIN: &str = "steady_strain";
pub const MOMENTUM_RESIDUAL: &str = "momentum_residual";
pub const CODE_VERSION: &str = "code_version";
/// Bin centre.
pub const Y: &str = "y";
/// Streaming velocity at the bin centre.
pub const U_INF: &str = "u_inf";

pub const U: &str = "u";
pub const GDOT: &str = "gdot";
pub const SIGMA_XY: &str = "sigma_xy";
pub const P: &str = "P";
pub const PHI_LOC: &str = "phi_loc";
pub const J: &str = "J";
pub const MU: &str = "mu";
pub const THETA: &str = "Theta";
pub const DELTA_V: &str = "Delta_v";
pub const F_X: &str = "f_x";
pub const COUNT: &str = "count";

/// The columns before the observables, in table order.
pub const SCENE_AND_BIN: [&str; 10] = [
    SCENE_ID,
    PROFILE,
    L_Y,
    PHI,
    SEED,
    STEADY_STRAIN,
    MOMENTUM_RESIDUAL,
    CODE_VERSION,
    Y,
    U_INF,
];

/// The columns that hold text rather than numbers.
pub const TEXT: [&str; 3] = [SCENE_ID, PROFILE, CODE_VERSION];

/// The observables, in table order; each is followed by its standard error.
pub const OBSERVABLES: [&str; 11] = [
    U, GDOT, SIGMA_XY, P, PHI_LOC, J, MU, THETA, DELTA_V, F_X, COUNT,
];

/// The name of the standard-error column of `observable`.
pub fn standard_error(observable: &str) -> String {
    format!("{observable}_se")
}

/// Whether column `name` is a standard error.
pub fn is_standard_error(name: &str) -> bool {
    name.ends_with("_se")
}

/// The header line of a dataset (without the line break).
pub fn header() -> String {
    let mut names: Vec<String> = SCENE_AND_BIN.iter().map(|s| s.to_string()).collect();
    for o in OBSERVABLES {
        names.push(o.to_string());
        names.push(standard_error(o));
    }
    names.join(",")
}
