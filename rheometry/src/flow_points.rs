//! The points of the flow curves of a grid of homogeneous-shear scenes (docs/physics.md
//! sections 10 and 11) that a batch ran into its folders: per finished run the box totals
//! of its summary as a [`StatePoint`] of `surrogate::rheology::flow_curves`, with the
//! Green-Kubo viscosity at its volume fraction when given, and its line of
//! `flow_curves.csv` ([`FlowCurveRow`], written and read back by that type).
use crate::error::{Result, RheometryError};
use crate::green_kubo::GreenKuboResult;
use serde::{Deserialize, Serialize};
use sim::input::grid::{Grid, GridRun};
use sim::output::result_files::RESULTS;
use sim::output::run_summary::RunSummary;
use sim::run::run_folder::{Recorded, RunFolder, RunStatus};
use sim::sampling::block_sums::Estimate;
use sim::sampling::shear_rheology::ShearRheology;
use std::path::{Path, PathBuf};
use surrogate::{
    bin_viscosity, green_kubo_at, part_viscosity, Dataset, State, StatePoint, StepSetting,
};

/// The parts of `eta_r` the table and figures show: name in `flow_curves.csv`, legend, and
/// the stress part (`schema::columns::STRESS_PARTS`) it is `-sigma_xy / (eta gdot)` of.
/// `contact + lubrication` is the box's `eta_r`; the drag stresslet (the isolated spheres'
/// `2.5 phi`) and the structural Brownian stress are reported beside them.
pub const PARTS: [(&str, &str, &str); 4] = [
    ("eta_r_contact", "contact", "sigma_xy_contact"),
    (
        "eta_r_hydrodynamic",
        "hydrodynamic (lubrication)",
        "sigma_xy_lubrication",
    ),
    ("eta_r_drag", "one-body drag", "sigma_xy_drag"),
    ("eta_r_brownian", "structural Brownian", "sigma_xy_brownian"),
];

/// One finished run: its point on the flow curves and what the table shows beside it.
#[derive(Clone, Debug)]
pub struct FlowPoint {
    pub id: String,
    pub summary: Box<RunSummary>,
    pub rheology: ShearRheology,
    /// Thermal energy (0 without Brownian forces).
    pub kt: f64,
    /// `tau_I / tau_B = rho kT / (eta^2 a)` of a Brownian scene.
    pub inertia_diffusion: Option<f64>,
    /// The contact stiffness and the lubrication's inner gap of its scene ([`contacts_of`]).
    pub contacts: (f64, f64),
    pub point: StatePoint,
}

/// The finished runs of a grid, and the labels of those not finished.
pub struct FlowRuns {
    pub points: Vec<FlowPoint>,
    pub missing: Vec<String>,
}

impl FlowRuns {
    /// The runs of `grid` in the batch folders `runs` (where `generate` ran it: one folder,
    /// or one per shard of a split grid), each with the Green-Kubo viscosity of
    /// `green_kubo` at its volume fraction (the mean over the results there). Refuses a grid
    /// without homogeneous shear, folders made for other scenes, a folder that is not there,
    /// a run finished in two of the folders (which one to take is not ours to guess), and
    /// folders where no run of the grid has finished (flow curves of nothing).
    pub fn read(grid: &Grid, runs: &[PathBuf], green_kubo: &[GreenKuboResult]) -> Result<FlowRuns> {
        if let Some(absent) = runs.iter().find(|r| !r.is_dir()) {
            return Err(RheometryError::File {
                path: absent.display().to_string(),
                message: "is not a folder of runs (the folder in which the grid was run)".into(),
            });
        }
        let replicas = replicas(green_kubo);
        let mut found = FlowRuns {
            points: Vec::new(),
            missing: Vec::new(),
        };
        for gs in &grid.runs {
            let Some(gdot) = gs.scene.shear_rate() else {
                return Err(RheometryError::File {
                    path: grid.name.clone(),
                    message: format!(
                        "scene {} has no fluid.shear_rate; flow curves need homogeneous shear",
                        gs.id
                    ),
                });
            };
            let mut done = runs
                .iter()
                .map(|r| RunFolder::in_batch(r, &gs.label()))
                .filter(|w| w.status(&RESULTS) == RunStatus::Done);
            let Some(work) = done.next() else {
                found.missing.push(gs.label());
                continue;
            };
            if let Some(again) = done.next() {
                return Err(RheometryError::File {
                    path: again.dir.display().to_string(),
                    message: format!(
                        "run {} finished here and in {} too: give each run's folder once",
                        gs.label(),
                        work.dir.display()
                    ),
                });
            }
            if work.recorded_scene(&gs.scene.file)? != Recorded::Same {
                return Err(RheometryError::File {
                    path: work.dir.display().to_string(),
                    message: format!(
                        "the run there was not made for scene {} of grid `{}` (another shear \
                         rate, volume fraction or setting, or no scene.toml): the runs must be \
                         the folder in which the grid was run",
                        gs.id, grid.name
                    ),
                });
            }
            let summary = Box::new(work.summary()?);
            let rheology = summary.shear.ok_or_else(|| RheometryError::File {
                path: work.summary_json().display().to_string(),
                message: "no `shear` box totals".into(),
            })?;
            let eta_gdot = gs.scene.file.fluid.eta * gdot;
            let eta_r_bins = bin_viscosity(&Dataset::read_csv(work.profile_csv())?, eta_gdot)?;
            let parts = PARTS.map(|(_, _, part)| {
                summary
                    .stress_parts
                    .get(part)
                    .map_or((f64::NAN, f64::NAN), |e| {
                        part_viscosity(e.mean, e.se, eta_gdot)
                    })
            });
            let estimate = |e: Estimate| (e.mean, e.se);
            found.points.push(FlowPoint {
                id: gs.id.clone(),
                point: StatePoint {
                    state: state_of(gs),
                    phi: gs.scene.file.particles.phi,
                    seed: gs.scene.file.seed,
                    phi_actual: summary.phi_actual,
                    eta_r: estimate(rheology.eta_r),
                    eta_r_bins,
                    parts,
                    mu: estimate(rheology.mu),
                    j: estimate(rheology.j),
                    green_kubo: green_kubo_at(&replicas, summary.phi_actual),
                },
                summary,
                rheology,
                kt: gs.scene.file.fluid.kt,
                inertia_diffusion: gs.scene.thermal.map(|t| t.inertia_diffusion),
                contacts: contacts_of(gs),
            });
        }
        if found.points.is_empty() {
            return Err(RheometryError::File {
                path: runs
                    .iter()
                    .map(|r| r.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                message: format!(
                    "holds no finished run of grid `{}` (none of its {} runs: the grid not run \
                     there yet, or the folder of another grid)",
                    grid.name,
                    grid.runs.len()
                ),
            });
        }
        Ok(found)
    }
}

/// The state `(mu_p, Pe, alpha, rho, time step)` of the grid's scene `gs`: what names its
/// curve.
pub(crate) fn state_of(gs: &GridRun) -> State {
    State {
        mu_p: gs.scene.file.forces.mu_p,
        peclet: gs
            .scene
            .thermal
            .and_then(|t| t.peclet)
            .unwrap_or(f64::INFINITY),
        alpha: gs.scene.file.particles.mixture.as_ref().map(|m| m.alpha),
        rho: gs.scene.rho,
        step: StepSetting {
            dt: gs.scene.file.run.dt,
            dt_factor: gs.scene.file.run.dt_factor,
        },
    }
}

/// `(k_n, xi_min)` of the grid's scene `gs`: the normal contact stiffness and the
/// lubrication's inner regularisation of the gap (`[forces]`), what tells apart runs of one
/// state made with other contacts (a check of the step at a softer contact, say).
pub(crate) fn contacts_of(gs: &GridRun) -> (f64, f64) {
    let forces = &gs.scene.file.forces;
    (forces.k_n, forces.xi_min)
}

/// The Green-Kubo results as `(phi_actual, eta_B / eta, its standard error)`, the
/// extrapolated viscosity of each: what `surrogate::green_kubo_at` averages at a point.
pub(crate) fn replicas(green_kubo: &[GreenKuboResult]) -> Vec<(f64, f64, f64)> {
    green_kubo
        .iter()
        .map(|g| {
            (
                g.phi_actual,
                g.extrapolated_eta_brownian_over_eta,
                g.extrapolated_eta_brownian_over_eta_se,
            )
        })
        .collect()
}

/// One run's line of `flow_curves.csv`: the run, its box totals (mean and standard error),
/// `eta_r` of its bins and of each of [`PARTS`], and a mixture's composition (empty for
/// other scenes).
///
/// Tables written before a column existed still read back: the columns added since the first
/// tables (the state, the parts, the composition, the density, the step, the code version,
/// the contacts) are NaN, or none, where they are missing, and the state of a redrawn point
/// comes from its grid ([`FlowCurveRow::point`]), as do its contacts when the table is read
/// with its grid ([`FlowCurveRow::of_grid`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlowCurveRow {
    pub scene_id: String,
    #[serde(default = "not_recorded")]
    pub phi: f64,
    /// Infinite without Brownian forces.
    #[serde(default = "not_recorded")]
    pub peclet: f64,
    #[serde(default = "not_recorded")]
    pub mu_p: f64,
    pub seed: u64,
    pub n_particles: usize,
    pub phi_actual: f64,
    pub strain_to_steady: f64,
    pub mean_overlap: f64,
    pub shear_rate: f64,
    #[serde(rename = "kT", default = "not_recorded")]
    pub kt: f64,
    pub sigma_xy: f64,
    pub sigma_xy_se: f64,
    #[serde(rename = "P")]
    pub p: f64,
    #[serde(rename = "P_se")]
    pub p_se: f64,
    pub eta_r: f64,
    pub eta_r_se: f64,
    pub mu: f64,
    pub mu_se: f64,
    #[serde(rename = "J")]
    pub j: f64,
    #[serde(rename = "J_se")]
    pub j_se: f64,
    pub eta_r_bins: f64,
    pub eta_r_bins_se: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_contact: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_contact_se: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_hydrodynamic: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_hydrodynamic_se: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_drag: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_drag_se: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_brownian: f64,
    #[serde(default = "not_recorded")]
    pub eta_r_brownian_se: f64,
    #[serde(default)]
    pub alpha: Option<f64>,
    #[serde(default)]
    pub alpha_actual: Option<f64>,
    #[serde(default)]
    pub peclet_c: Option<f64>,
    #[serde(default)]
    pub peclet_cg: Option<f64>,
    #[serde(default = "not_recorded")]
    pub rho: f64,
    #[serde(default)]
    pub tau_i_over_tau_b: Option<f64>,
    /// The time step the run took (its `summary.json`).
    #[serde(default = "not_recorded")]
    pub dt: f64,
    /// The version of the code that made the run (its `summary.json`).
    #[serde(default)]
    pub code_version: Option<String>,
    /// Normal contact stiffness of the run's scene (`forces.k_n`, units of force per length).
    #[serde(default = "not_recorded")]
    pub k_n: f64,
    /// The lubrication's inner regularisation of the dimensionless gap (`forces.xi_min`).
    #[serde(default = "not_recorded")]
    pub xi_min: f64,
}

/// A value of a column that an older table lacks.
fn not_recorded() -> f64 {
    f64::NAN
}

impl FlowCurveRow {
    /// The line of `point`.
    pub fn of(point: &FlowPoint) -> Self {
        let (s, r, p) = (&point.summary, &point.rheology, &point.point);
        let c = s.composition;
        let [contact, hydrodynamic, drag, brownian] = p.parts;
        FlowCurveRow {
            scene_id: point.id.clone(),
            phi: p.phi,
            peclet: p.state.peclet,
            mu_p: p.state.mu_p,
            seed: p.seed,
            n_particles: s.n_particles,
            phi_actual: s.phi_actual,
            strain_to_steady: s.strain_to_steady,
            mean_overlap: s.mean_overlap,
            shear_rate: r.shear_rate,
            kt: point.kt,
            sigma_xy: r.sigma_xy.mean,
            sigma_xy_se: r.sigma_xy.se,
            p: r.p.mean,
            p_se: r.p.se,
            eta_r: r.eta_r.mean,
            eta_r_se: r.eta_r.se,
            mu: r.mu.mean,
            mu_se: r.mu.se,
            j: r.j.mean,
            j_se: r.j.se,
            eta_r_bins: p.eta_r_bins.0,
            eta_r_bins_se: p.eta_r_bins.1,
            eta_r_contact: contact.0,
            eta_r_contact_se: contact.1,
            eta_r_hydrodynamic: hydrodynamic.0,
            eta_r_hydrodynamic_se: hydrodynamic.1,
            eta_r_drag: drag.0,
            eta_r_drag_se: drag.1,
            eta_r_brownian: brownian.0,
            eta_r_brownian_se: brownian.1,
            alpha: c.map(|c| c.alpha),
            alpha_actual: c.map(|c| c.alpha_actual),
            peclet_c: c.and_then(|c| c.peclet_c),
            peclet_cg: c.and_then(|c| c.peclet_cg),
            rho: p.state.rho,
            tau_i_over_tau_b: point.inertia_diffusion,
            dt: s.dt,
            code_version: Some(s.code_version.clone()),
            k_n: point.contacts.0,
            xi_min: point.contacts.1,
        }
    }

    /// This line of a table written earlier, read with the grid's scene `gs` it was made of:
    /// the contacts an older table did not record taken from the scene. Refuses (with the
    /// reason) a line whose recorded state is not the scene's: a volume fraction, friction
    /// coefficient, Peclet number or contacts of another scene (a grid edited since the
    /// table was written, whose scene of this id is now another).
    pub fn of_grid(mut self, gs: &GridRun) -> std::result::Result<Self, String> {
        let (k_n, xi_min) = contacts_of(gs);
        let state = state_of(gs);
        let recorded = [
            ("phi", self.phi, gs.scene.file.particles.phi),
            ("mu_p", self.mu_p, state.mu_p),
            ("peclet", self.peclet, state.peclet),
            ("k_n", self.k_n, k_n),
            ("xi_min", self.xi_min, xi_min),
        ];
        if let Some((name, line, scene)) = recorded
            .into_iter()
            .find(|&(_, line, scene)| !line.is_nan() && line != scene)
        {
            return Err(format!(
                "its line of scene {} has {name} {line}, the grid's scene {scene}",
                self.scene_id
            ));
        }
        self.k_n = k_n;
        self.xi_min = xi_min;
        Ok(self)
    }

    /// The point of this line, a run of the grid's scene `gs`, with the Green-Kubo viscosity
    /// of `replicas` ([`replicas`]) at its volume fraction: the inverse of [`Self::of`] on
    /// what the flow curves fit and draw, the state taken from the grid.
    pub fn point(&self, gs: &GridRun, replicas: &[(f64, f64, f64)]) -> StatePoint {
        StatePoint {
            state: state_of(gs),
            phi: gs.scene.file.particles.phi,
            seed: gs.scene.file.seed,
            phi_actual: self.phi_actual,
            eta_r: (self.eta_r, self.eta_r_se),
            eta_r_bins: (self.eta_r_bins, self.eta_r_bins_se),
            parts: [
                (self.eta_r_contact, self.eta_r_contact_se),
                (self.eta_r_hydrodynamic, self.eta_r_hydrodynamic_se),
                (self.eta_r_drag, self.eta_r_drag_se),
                (self.eta_r_brownian, self.eta_r_brownian_se),
            ],
            mu: (self.mu, self.mu_se),
            j: (self.j, self.j_se),
            green_kubo: green_kubo_at(replicas, self.phi_actual),
        }
    }

    /// Writes `rows` to `path` (whole).
    pub fn write_all(path: &Path, rows: &[FlowCurveRow]) -> Result<()> {
        let bytes = Self::to_csv(rows).map_err(|message| RheometryError::File {
            path: path.display().to_string(),
            message,
        })?;
        Ok(schema::write_atomic(path, &bytes)?)
    }

    /// The table of `rows` as CSV text, or why it cannot be made.
    pub fn to_csv(rows: &[FlowCurveRow]) -> std::result::Result<Vec<u8>, String> {
        let mut table = csv::Writer::from_writer(Vec::new());
        for row in rows {
            table.serialize(row).map_err(|e| e.to_string())?;
        }
        table.into_inner().map_err(|e| e.to_string())
    }

    /// The lines of the table at `path`.
    pub fn read_all(path: &Path) -> Result<Vec<FlowCurveRow>> {
        let err = |e: csv::Error| RheometryError::File {
            path: path.display().to_string(),
            message: format!("not a flow-curve table: {e}"),
        };
        csv::Reader::from_path(path)
            .map_err(err)?
            .deserialize()
            .collect::<std::result::Result<_, _>>()
            .map_err(err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table written before the state, the parts and the composition were columns (the
    /// header of reports/brownian/nonbrownian_n1000/flow_curves.csv, one line of it) reads
    /// back with those NaN or none; a line missing a measured column does not.
    #[test]
    fn tables_of_older_versions_read_back_without_their_missing_columns() {
        let dir = std::env::temp_dir().join(format!("flow-rows-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let old = dir.join("old.csv");
        let header = "scene_id,seed,n_particles,phi_actual,strain_to_steady,mean_overlap,\
                      shear_rate,sigma_xy,sigma_xy_se,P,P_se,eta_r,eta_r_se,mu,mu_se,J,J_se,\
                      eta_r_bins,eta_r_bins_se";
        let line = "a_000,1,1000,0.55,1.0,0.001,0.01,-0.2,0.01,0.5,0.01,20,1,0.4,0.02,\
                    0.02,0.001,20,1";
        std::fs::write(&old, format!("{header}\n{line}\n")).unwrap();
        let rows = FlowCurveRow::read_all(&old).unwrap();
        assert_eq!(rows.len(), 1);
        let row = &rows[0];
        assert_eq!((row.eta_r, row.mu, row.j), (20.0, 0.4, 0.02));
        assert!(row.eta_r_contact.is_nan() && row.rho.is_nan() && row.peclet.is_nan());
        assert_eq!((row.alpha, row.tau_i_over_tau_b), (None, None));
        assert!(row.dt.is_nan() && row.code_version.is_none());
        let cut = header.replace(",eta_r_bins,eta_r_bins_se", "");
        let short: Vec<&str> = line.split(',').collect();
        std::fs::write(&old, format!("{cut}\n{}\n", short[..17].join(","))).unwrap();
        let refused = FlowCurveRow::read_all(&old).unwrap_err().to_string();
        assert!(refused.contains("eta_r_bins"), "{refused}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
