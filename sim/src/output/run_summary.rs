//! What a finished run hands over: its profile, its snapshot sums, and the summary
//! written to `summary.json` (docs/physics.md section 7).
use crate::input::composition::Composition;
use crate::input::thermal_scales::ThermalScales;
use crate::integrate::stage_timers::StageTimers;
use crate::integrate::timestep::TimeStep;
use crate::json_numbers::null_as_nan;
use crate::sampling::bin_averages::BinAverages;
use crate::sampling::block_sums::{BlockSums, Estimate};
use crate::sampling::conventions::Conventions;
use crate::sampling::shear_rheology::ShearRheology;
use crate::sampling::species_temperatures::SpeciesTemperature;
use crate::sampling::steady_state::Drift;
use crate::sampling::stress_checks::StressChecks;
use crate::sampling::stress_parts::StressParts;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a finished run reports besides its profile (written to summary.json, and read back
/// from it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    pub name: String,
    pub n_particles: usize,
    pub phi: f64,
    pub phi_actual: f64,
    pub stokes: f64,
    /// Brownian scales (kT, tau_B, tau_I, Peclet number) of a scene with `kT > 0`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thermal: Option<ThermalScales>,
    /// Composition and Peclet numbers `Pe_c`, `Pe_cg` of a colloid-grain mixture;
    /// absent in the summaries of other scenes and of runs made before it was added.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub composition: Option<Composition>,
    pub dt: f64,
    pub dt_limit: String,
    pub timestep: TimeStep,
    pub steps: u64,
    pub strain_total: f64,
    /// NaN when the run never reached steady state (written `null`).
    #[serde(deserialize_with = "null_as_nan")]
    pub strain_to_steady: f64,
    pub steady_drift: Vec<Drift>,
    pub snapshots: usize,
    pub wall_s: f64,
    pub particle_steps_per_s: f64,
    pub momentum_residual: Option<f64>,
    /// The independent checks of the bin-averaged stress.
    pub stress_checks: StressChecks,
    /// Box totals of the stress parts (contact, lubrication, drag, structural Brownian;
    /// docs/physics.md section 11), by the names of `stress.csv`'s columns; empty in the
    /// summaries of runs made before it was added.
    #[serde(default)]
    pub stress_parts: BTreeMap<String, Estimate>,
    /// Kinetic temperatures of each species over kT, translation and rotation, relative to
    /// the streaming flow (Brownian scenes; docs/physics.md section 11); absent otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub temperatures: Vec<SpeciesTemperature>,
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
    pub stress_convention: String,
    /// The definitions of the observables in the profile.
    pub observables: Conventions,
    pub code_version: String,
}

impl RunSummary {
    /// Reads the summary a finished run wrote at `path` (see
    /// [`write_results`](crate::output::result_files::write_results)).
    pub fn read(path: &std::path::Path) -> Result<RunSummary, crate::error::SimError> {
        let err = |message: String| crate::error::SimError::Output {
            path: path.display().to_string(),
            message,
        };
        let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
        serde_json::from_slice(&bytes).map_err(|e| err(format!("not a run summary: {e}")))
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::integrator::Integrator;
    use crate::integrate::timestep::DtLimit;

    fn estimate(mean: f64) -> Estimate {
        Estimate { mean, se: 0.1 }
    }

    /// A summary with every optional part present, and the limits that are infinite when
    /// their term is off (JSON `null`).
    fn summary() -> RunSummary {
        RunSummary {
            name: "tiny".into(),
            n_particles: 50,
            phi: 0.45,
            phi_actual: 0.4493,
            stokes: 0.01,
            thermal: Some(ThermalScales {
                kt: 0.5,
                tau_b: 2.0,
                tau_i: 0.01,
                inertia_diffusion: 0.005,
                peclet: None,
            }),
            composition: Some(Composition {
                alpha: 0.7,
                alpha_actual: 0.69,
                a_c: 1.0,
                a_g: 5.0,
                a_cg: 3.8,
                peclet_c: Some(1.0),
                peclet_cg: Some(54.872),
            }),
            dt: 1e-3,
            dt_limit: "contact".into(),
            timestep: TimeStep {
                dt: 1e-3,
                limit: DtLimit::Contact,
                contact_critical: 0.02,
                drag_critical: f64::INFINITY,
                lubrication_critical: f64::INFINITY,
                accuracy_limit: f64::INFINITY,
                friction_critical: f64::INFINITY,
                diffusion_limit: 2e-3,
                relaxation_limit: f64::INFINITY,
                cutoff_limit: f64::INFINITY,
                integrator: Integrator::Explicit,
            },
            steps: 1234,
            strain_total: 5.0,
            strain_to_steady: 1.2,
            steady_drift: vec![Drift {
                strain: 1.2,
                chi2_u: 0.9,
                chi2_sigma_xy: 1.1,
                chi2_phi_loc: 1.0,
                chi2_structure: 0.0,
            }],
            snapshots: 40,
            wall_s: 2.5,
            particle_steps_per_s: 24680.0,
            momentum_residual: Some(0.03),
            stress_checks: StressChecks {
                sigma_yy_chi2: 1.3,
                sigma_yy_max_z: 2.1,
                balance_residual: None,
            },
            stress_parts: BTreeMap::from([("sigma_xy_contact".to_string(), estimate(-0.2))]),
            temperatures: vec![SpeciesTemperature {
                radius: 1.0,
                translation: estimate(1.0),
                rotation: estimate(0.99),
            }],
            shear: Some(ShearRheology {
                shear_rate: 0.1,
                sigma_xy: estimate(-0.2),
                p: estimate(0.5),
                eta_r: estimate(2.0),
                mu: estimate(0.4),
                j: estimate(0.2),
            }),
            mean_overlap: 0.001,
            max_overlap: 0.01,
            list_builds: 17,
            solver_iterations_mean: None,
            timers: StageTimers {
                neighbours_s: 0.1,
                forces_s: 1.5,
                integration_s: 0.5,
                sampling_s: 0.4,
            },
            threads: 2,
            undefined_bins: vec![3],
            warnings: vec!["a warning".into()],
            stress_convention: "sigma = ...".into(),
            observables: Conventions::default(),
            code_version: "0.1.0".into(),
        }
    }

    #[test]
    fn a_written_summary_reads_back_equal() {
        let written = summary();
        let text = serde_json::to_string_pretty(&written).unwrap();
        assert!(text.contains("\"accuracy_limit\": null"));
        let read: RunSummary = serde_json::from_str(&text).unwrap();
        assert_eq!(read, written);

        // Without the optional parts, and a run that never reached steady state.
        let written = RunSummary {
            thermal: None,
            composition: None,
            shear: None,
            strain_to_steady: f64::NAN,
            ..summary()
        };
        let text = serde_json::to_string(&written).unwrap();
        for part in ["shear", "thermal", "composition"] {
            assert!(!text.contains(&format!("\"{part}\"")), "{text}");
        }
        let read: RunSummary = serde_json::from_str(&text).unwrap();
        assert!(read.strain_to_steady.is_nan());
        assert_eq!(
            RunSummary {
                strain_to_steady: 0.0,
                ..read
            },
            RunSummary {
                strain_to_steady: 0.0,
                ..written
            }
        );
    }
}
