//! The dataset's column names, defined once (docs/physics.md section 8): every table of
//! binned results (`simulate`'s `profile.csv`, `generate`'s datasets, `solve`'s profiles) and
//! every reader of them (`merge`, `compare`, `plot`, the surrogate's mappings) take the names
//! from here. A row is one bin of one run (one replica of a scene, told apart by `seed`): the
//! scene and bin columns, then each observable followed by its standard error.
//!
//! The ensemble table (`<dataset>.ensemble.csv`, written by `generate` and `merge` when a
//! scene has several replicas) has one row per bin per scene: [`ENSEMBLE_SCENE_AND_BIN`],
//! then each observable's mean over the replicas followed by its standard error, which is
//! the between-replica one (sample standard deviation over sqrt(n)) when n >= 2 and the one
//! run's batch-means error when n = 1, as [`SE_FROM`] says on every row.

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

/// Prediction tables (`predict`, `solve`): whether the row lies inside the model's training
/// domain (`true`/`false`).
pub const IN_DOMAIN: &str = "in_domain";
/// Prediction tables: the row's distance to the training rows in units of the domain's
/// threshold (<= 1 is near enough).
pub const DOMAIN_DISTANCE: &str = "domain_distance";
/// The suffix of a predicted output's column: `mu_pred` is the prediction of `mu`.
pub const PREDICTED_SUFFIX: &str = "_pred";
/// Prediction tables (`predict`, `solve`): the suffixes of an output's interval bounds,
/// `mu_lower` and `mu_upper` (at the level the command states, 90 % by default).
pub const LOWER_SUFFIX: &str = "_lower";
pub const UPPER_SUFFIX: &str = "_upper";
/// Derived by the surrogate, not written by the simulator: a bin's distance (units a) to the
/// nearest velocity extremum of its profile, where the bin velocities' differences change
/// sign (the `ext` mapping's nonlocal input, docs/physics.md section 8).
pub const EXTREMUM_DISTANCE: &str = "d_ext";

/// Ensemble table: number of replicas averaged in the row.
pub const REPLICAS: &str = "replicas";
/// Ensemble table: the replicas' seeds, separated by spaces.
pub const SEEDS: &str = "seeds";
/// The columns that hold whole numbers (a reader gives them as integers, not floats).
pub const INTEGER_COLUMNS: [&str; 2] = [SEED, REPLICAS];
/// Ensemble table: where the row's standard errors come from, [`SE_FROM_REPLICAS`] or
/// [`SE_FROM_BATCH_MEANS`].
pub const SE_FROM: &str = "se_from";
/// [`SE_FROM`] of a scene with n >= 2 replicas: sample standard deviation between the
/// replicas over sqrt(n).
pub const SE_FROM_REPLICAS: &str = "replicas";
/// [`SE_FROM`] of a scene with one replica: that run's batch-means standard error (a lower
/// bound on the scatter between realisations, see datasets/README.md).
pub const SE_FROM_BATCH_MEANS: &str = "batch_means";

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

/// The columns of the ensemble table before the observables, in table order.
pub const ENSEMBLE_SCENE_AND_BIN: [&str; 10] = [
    SCENE_ID,
    PROFILE,
    L_Y,
    PHI,
    REPLICAS,
    SEEDS,
    SE_FROM,
    CODE_VERSION,
    Y,
    U_INF,
];

/// The columns that hold text rather than numbers.
pub const TEXT: [&str; 5] = [SCENE_ID, PROFILE, CODE_VERSION, SEEDS, SE_FROM];

/// The observables, in table order; each is followed by its standard error.
pub const OBSERVABLES: [&str; 11] = [
    U, GDOT, SIGMA_XY, P, PHI_LOC, J, MU, THETA, DELTA_V, F_X, COUNT,
];

/// The parts of the stress, in table order (a run's `stress.csv`: `y`, then each part followed
/// by its standard error; its box totals in `summary.json`): the contact springs', the
/// lubrication's stresslets, which sum to the profile's `sigma_xy` and `P` under the default
/// `pairs` stress convention, the Stokes drag's (added under `pairs+drag`; it is traceless:
/// no `P`), and the structural Brownian stress (thesis eq 3.54), which is part of none.
pub const STRESS_PARTS: [&str; 7] = [
    "sigma_xy_contact",
    "P_contact",
    "sigma_xy_lubrication",
    "P_lubrication",
    "sigma_xy_drag",
    "sigma_xy_brownian",
    "P_brownian",
];

/// The header line of a run's stress-parts table (without the line break).
pub fn stress_parts_header() -> String {
    with_standard_errors(&[Y], &STRESS_PARTS).join(",")
}

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
    with_observables(&SCENE_AND_BIN).join(",")
}

/// The column names of the ensemble table, in order.
pub fn ensemble_header() -> Vec<String> {
    with_observables(&ENSEMBLE_SCENE_AND_BIN)
}

/// `first`, then every observable followed by its standard error.
fn with_observables(first: &[&str]) -> Vec<String> {
    with_standard_errors(first, &OBSERVABLES)
}

/// `first`, then each of `values` followed by its standard error.
fn with_standard_errors(first: &[&str], values: &[&str]) -> Vec<String> {
    let mut names: Vec<String> = first.iter().map(|s| s.to_string()).collect();
    for v in values {
        names.push(v.to_string());
        names.push(standard_error(v));
    }
    names
}
