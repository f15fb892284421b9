//! Stability on stiff and extreme cases: one parameter at a time away
//! from a base scene (k_n, xi_min, phi, amplitude, size ratio), each at several multiples of
//! the automatic time step. Each case is a short run through the ordinary [`crate::run`], so
//! the blow-up checks under test are the real ones.
use crate::input::integrator::Integrator;
use crate::input::scene::{Scene, SceneFile};
use crate::run::RunOptions;
use crate::SimError;
use rayon::prelude::*;

/// How long each case runs, and how big the base box is.
#[derive(Clone, Copy)]
pub struct SweepSize {
    /// Strain of each of the 4 steady-state windows.
    pub window_strain: f64,
    /// Snapshots averaged after them (0.01 strain apart).
    pub snapshots: usize,
    /// Base box edge (x and z; y is 1.5x), units a.
    pub box_edge: f64,
}

/// One case of the sweep.
pub struct Case {
    pub parameter: &'static str,
    pub value: f64,
    pub dt_factor: f64,
}

/// How a case ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stability {
    /// Finished with a momentum residual at most [`INACCURATE_RESIDUAL`].
    Stable,
    /// Finished, momentum residual above [`INACCURATE_RESIDUAL`].
    Inaccurate,
    BlowUp,
    NotSteady,
    /// Invalid scene or packing.
    Refused,
}

impl Stability {
    /// Whether the run reached the end of its averaging.
    pub fn finished(self) -> bool {
        matches!(self, Stability::Stable | Stability::Inaccurate)
    }
}

impl std::fmt::Display for Stability {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Stability::Stable => "stable",
            Stability::Inaccurate => "inaccurate",
            Stability::BlowUp => "blow-up",
            Stability::NotSteady => "not steady",
            Stability::Refused => "refused",
        })
    }
}

/// What a case did.
pub struct CaseResult {
    pub case: Case,
    pub status: Stability,
    pub dt: f64,
    /// What limits dt, and the gain over the explicit scheme's automatic step on the same
    /// scene, e.g. `accuracy, 30x explicit`.
    pub dt_limit: String,
    pub max_overlap: f64,
    pub momentum_residual: f64,
    /// The error message, if any.
    pub message: String,
    /// For a failure: whether the message names step, particle and likely cause.
    pub cause_named: bool,
}

/// Parameter values swept (docs/physics.md section 1 defaults in the middle), and the dt multiples.
pub const PARAMETERS: [(&str, &[f64]); 5] = [
    ("k_n", &[1e3, 1e4, 1e5, 1e6]),
    ("xi_min", &[1e-2, 1e-3, 1e-4, 1e-5]),
    ("phi", &[0.40, 0.50, 0.56, 0.60, 0.62]),
    ("amplitude", &[0.01, 0.1, 0.3, 1.0]),
    ("size_ratio", &[1.0, 1.4, 2.0, 4.0]),
];
/// Multiples 0.5-4 of the automatic step, plus 8 and 16 to show that instability, once it comes, is caught.
pub const DT_FACTORS: [f64; 6] = [0.5, 1.0, 2.0, 4.0, 8.0, 16.0];

/// A finished run whose momentum residual exceeds this is reported as inaccurate: short
/// stable runs at the automatic dt stay below 0.1 (the base case at 0.015).
pub const INACCURATE_RESIDUAL: f64 = 0.1;

/// Every (parameter value, dt factor) pair, for the parameters named in `only` (all when empty).
pub fn cases(only: &[String]) -> Vec<Case> {
    PARAMETERS
        .iter()
        .filter(|(p, _)| only.is_empty() || only.iter().any(|o| o == p))
        .flat_map(|&(parameter, values)| {
            values.iter().flat_map(move |&value| {
                DT_FACTORS.iter().map(move |&dt_factor| Case {
                    parameter,
                    value,
                    dt_factor,
                })
            })
        })
        .collect()
}

/// The scene of `case`: phi 0.5, `0.15 sin(2 pi y/L)`, radii 1 : 1.4, defaults otherwise,
/// with the one parameter changed; the box grows when large spheres need it.
fn scene_file(case: &Case, size: SweepSize) -> SceneFile {
    let (mut phi, mut amplitude, mut ratio, mut k_n, mut xi_min) = (0.5, 0.15, 1.4, 1e4, 1e-3);
    match case.parameter {
        "k_n" => k_n = case.value,
        "xi_min" => xi_min = case.value,
        "phi" => phi = case.value,
        "amplitude" => amplitude = case.value,
        _ => ratio = case.value,
    }
    // Twice the interaction range plus skin, with room to spare, rounded up to whole bins.
    let edge = size
        .box_edge
        .max((2.2 * (2.0 * ratio * 1.025 + 0.1) / 2.0).ceil() * 2.0);
    let mut f = SceneFile::with_defaults(
        &format!("{}_{}_dt{}", case.parameter, case.value, case.dt_factor),
        [edge, box_height(edge), edge],
        phi,
        &format!("{amplitude}*sin(2*pi*y/L)"),
    );
    f.seed = 7;
    f.particles.radii = vec![1.0, ratio];
    f.forces.k_n = k_n;
    f.forces.xi_min = xi_min;
    let run = &mut f.run;
    run.dt_factor = case.dt_factor;
    run.sample_strain = 0.01;
    run.window_strain = size.window_strain;
    run.max_strain = 5.0 * size.window_strain;
    run.steady_chi2 = 1e9;
    run.snapshots = size.snapshots;
    run.blocks = 4;
    f
}

/// Height `L_y` of a sweep box `edge` wide (units a): 1.5 edges, rounded up to whole 2a bins.
pub fn box_height(edge: f64) -> f64 {
    (edge * 0.75).ceil() * 2.0
}

/// Runs one case to the end of its short averaging, or to its failure.
fn run_case(case: Case, size: SweepSize) -> CaseResult {
    let mut result = CaseResult {
        case,
        status: Stability::Refused,
        dt: f64::NAN,
        dt_limit: String::new(),
        max_overlap: f64::NAN,
        momentum_residual: f64::NAN,
        message: String::new(),
        cause_named: false,
    };
    let scene = match Scene::from_file(scene_file(&result.case, size), false) {
        Ok(s) => s,
        Err(e) => {
            result.message = e.to_string();
            return result;
        }
    };
    let t = scene.timestep;
    let mut explicit = scene.file.clone();
    explicit.run.integrator = Integrator::Explicit;
    explicit.run.dt_factor = 1.0;
    let gain = Scene::from_file(explicit, false)
        .map_or(f64::NAN, |e| t.dt / result.case.dt_factor / e.timestep.dt);
    (result.dt, result.dt_limit) = (t.dt, format!("{}, {gain:.0}x explicit", t.limit));
    match crate::run::run(&scene, &RunOptions::default(), &mut |_, _| {}) {
        Ok(out) => {
            result.max_overlap = out.summary.max_overlap;
            result.momentum_residual = out.summary.momentum_residual.unwrap_or(f64::NAN);
            result.status = if result.momentum_residual <= INACCURATE_RESIDUAL {
                Stability::Stable
            } else {
                Stability::Inaccurate
            };
        }
        Err(e) => {
            result.status = match e {
                SimError::BlowUp { .. } => Stability::BlowUp,
                SimError::NotSteady { .. } => Stability::NotSteady,
                _ => Stability::Refused,
            };
            result.cause_named = matches!(&e, SimError::BlowUp { cause, what, .. } if !cause.is_empty() && !what.is_empty());
            result.message = e.to_string();
        }
    }
    result
}

/// Runs `cases`, in parallel over cases (each case on one thread), in case order, calling
/// `done` after each.
pub fn sweep(cases: Vec<Case>, size: SweepSize, done: &(dyn Fn() + Sync)) -> Vec<CaseResult> {
    cases
        .into_par_iter()
        .with_max_len(1)
        .map(|c| {
            let r = run_case(c, size);
            done();
            r
        })
        .collect()
}
