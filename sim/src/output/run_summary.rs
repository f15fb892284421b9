//! What a finished run hands over: its profile, its snapshot sums, and the summary
//! written to `summary.json` (docs/physics.md section 7).
use crate::input::thermal_scales::ThermalScales;
use crate::integrate::stage_timers::StageTimers;
use crate::integrate::timestep::TimeStep;
use crate::sampling::bin_averages::BinAverages;
use crate::sampling::block_sums::{BlockSums, Estimate};
use crate::sampling::conventions::Conventions;
use crate::sampling::shear_rheology::ShearRheology;
use crate::sampling::steady_state::Drift;
use crate::sampling::stress_checks::StressChecks;
use crate::sampling::stress_parts::StressParts;
use serde::Serialize;
use std::collections::BTreeMap;

/// What a finished run reports besides its profile (written to summary.json).
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    pub name: String,
    pub n_particles: usize,
    pub phi: f64,
    pub phi_actual: f64,
    pub stokes: f64,
    /// Brownian scales (kT, tau_B, tau_I, Peclet number) of a scene with `kT > 0`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thermal: Option<ThermalScales>,
    pub dt: f64,
    pub dt_limit: String,
    pub timestep: TimeStep,
    pub steps: u64,
    pub strain_total: f64,
    pub strain_to_steady: f64,
    pub steady_drift: Vec<Drift>,
    pub snapshots: usize,
    pub wall_s: f64,
    pub particle_steps_per_s: f64,
    pub momentum_residual: Option<f64>,
    /// The independent checks of the bin-averaged stress.
    pub stress_checks: StressChecks,
    /// Box totals of the stress parts (contact, lubrication, drag, structural Brownian;
    /// docs/physics.md section 11), by the names of `stress.csv`'s columns.
    pub stress_parts: BTreeMap<String, Estimate>,
    /// Box totals of a homogeneous-shear scene (docs/physics.md section 10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear: Option<ShearRheology>,
    /// Mean overlap over contacts, averaged over the steady snapshots (units a).
    pub mean_overlap: f64,
    /// Largest overlap ratio seen at a steady snapshot (overlap / smaller radius).
    pub max_overlap: f64,
    pub list_builds: u64,
    /// Mean conjugate-gradient iterations per implicit step (absent for the explicit
    /// scheme); counted since the last start or restart.
    pub solver_iterations_mean: Option<f64>,
    pub timers: StageTimers,
    pub threads: usize,
    pub undefined_bins: Vec<usize>,
    pub warnings: Vec<String>,
    pub stress_convention: &'static str,
    /// The definitions of the observables in the profile.
    pub observables: Conventions,
    pub code_version: &'static str,
}

/// Result of a completed run.
pub struct RunOutcome {
    pub profile: BinAverages,
    pub summary: RunSummary,
    /// The parts of the stress, per bin and over the box.
    pub stress: StressParts,
    /// The averaged snapshot sums, from which the profile under any convention follows.
    pub sums: BlockSums,
}
