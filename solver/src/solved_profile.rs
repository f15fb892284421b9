//! A solved profile as files, by one writer for the command line and Python alike:
//! `profile.csv` (the dataset's columns that the solve determines, one row per bin, with the
//! training-domain check of each bin and, when the models carry their calibration, the
//! bands; no standard errors, Theta empty unless the closure solved for it),
//! `summary.json` ([`SolveSummary`], read back by that type) and the scene it solved
//! (`scene.toml`).
use crate::bands::{ProfileBands, BANDED};
use crate::closure_kind::ClosureKind;
use crate::error::{Result, SolverError};
use crate::problem::ProfileProblem;
use crate::solution::ProfileSolution;
use crate::theta_balance::ThetaBalanceFit;
use schema::columns as col;
use serde::{Deserialize, Serialize};
use sim::input::scene::Scene;
use std::path::Path;
use surrogate::DomainCheck;

/// The solved profile's table.
pub const PROFILE: &str = "profile.csv";
/// Its summary.
pub const SUMMARY: &str = "summary.json";

/// A solution of a scene's problem with the training-domain check of its bins and its bands.
pub struct SolvedProfile<'a> {
    pub scene: &'a Scene,
    pub problem: &'a ProfileProblem,
    pub solution: &'a ProfileSolution,
    pub checks: &'a [DomainCheck],
    /// The bands, when the models were saved with their calibration.
    pub bands: Option<&'a ProfileBands>,
}

/// How a solve went (`summary.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolveSummary {
    pub scene: String,
    pub closure: String,
    /// The Theta balance the nonlocal closure solves (fitted whatever the closure).
    pub theta_balance: ThetaBalanceFit,
    pub bins: usize,
    pub iterations: usize,
    /// Whether Newton's method stalled from u = u_inf and the solve followed the
    /// continuation from the local law.
    pub continued: bool,
    /// Largest balance residual, in units of the forcing's drag density.
    pub residual: f64,
    pub pressure: f64,
    /// Bins outside the closure's training domain (columns `in_domain`, `domain_distance`
    /// of profile.csv): their closure values are extrapolations.
    pub bins_outside_domain: usize,
    /// Largest `domain_distance` over the bins (<= 1 is near enough the training rows).
    pub largest_domain_distance: f64,
    /// The bands of profile.csv, when the models carry their calibration.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bands: Option<BandSummary>,
    pub wall_ms: f64,
    pub code_version: String,
}

/// The bands of a solve: their level, margins and how they did on held-out families.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BandSummary {
    pub level: f64,
    /// Per observable (`u`, `phi_loc`, `mu`): the margin multiplying each bin's scale.
    pub margins: [f64; 3],
    /// Per observable: the mean band width relative to the mean |value| of the profile.
    pub relative_widths: [f64; 3],
    /// Per observable: the fraction of the calibration bins the 90 % band covered when their
    /// family was held out.
    pub held_out_coverage: [f64; 3],
}

impl SolvedProfile<'_> {
    /// The numeric columns per bin, in `profile.csv`'s order after `scene_id` and `profile`:
    /// `L_y, phi, y, u_inf, u, gdot, sigma_xy, P, phi_loc, J, mu, Theta` (NaN unless the
    /// closure solved for Theta), `Delta_v, f_x, d_ext`, then with bands `u_lower, u_upper,
    /// phi_loc_lower, phi_loc_upper, mu_lower, mu_upper`.
    pub fn columns(&self) -> Vec<(String, Vec<f64>)> {
        let (p, s) = (self.problem, self.solution);
        let n = p.n_bins();
        let f = &self.scene.file;
        let theta = if s.theta.is_empty() {
            vec![f64::NAN; n]
        } else {
            s.theta.clone()
        };
        let mut columns: Vec<(String, Vec<f64>)> = [
            (col::L_Y, vec![f.box_.l_y; n]),
            (col::PHI, vec![f.particles.phi; n]),
            (col::Y, p.bin_centres()),
            (col::U_INF, p.u_inf.clone()),
            (col::U, s.u.clone()),
            (col::GDOT, s.gdot.clone()),
            (col::SIGMA_XY, s.sigma_xy.clone()),
            (col::P, vec![s.pressure; n]),
            (col::PHI_LOC, s.phi_loc.clone()),
            (col::J, s.j.clone()),
            (col::MU, s.mu.clone()),
            (col::THETA, theta),
            (col::DELTA_V, s.delta_v.clone()),
            (col::F_X, s.f_x.clone()),
            (col::EXTREMUM_DISTANCE, s.d_ext.clone()),
        ]
        .into_iter()
        .map(|(name, values)| (name.to_owned(), values))
        .collect();
        if let Some(bands) = self.bands {
            for (i, o) in BANDED.iter().enumerate() {
                columns.push((
                    format!("{}{}", o.name(), col::LOWER_SUFFIX),
                    bands.lower[i].clone(),
                ));
                columns.push((
                    format!("{}{}", o.name(), col::UPPER_SUFFIX),
                    bands.upper[i].clone(),
                ));
            }
        }
        columns
    }

    /// The summary of this solution by `closure`, which took `wall_ms` (the solve and its
    /// bands), stamped with `code_version`; `bands` the account of [`SolvedProfile::bands`].
    pub fn summary(
        &self,
        closure: ClosureKind,
        theta_balance: ThetaBalanceFit,
        bands: Option<BandSummary>,
        wall_ms: f64,
        code_version: &str,
    ) -> SolveSummary {
        let s = self.solution;
        SolveSummary {
            scene: self.scene.file.name.clone(),
            closure: closure.name().into(),
            theta_balance,
            bins: self.problem.n_bins(),
            iterations: s.iterations,
            continued: s.continued,
            residual: s.residual,
            pressure: s.pressure,
            bins_outside_domain: self.checks.iter().filter(|c| !c.inside()).count(),
            largest_domain_distance: self.checks.iter().map(|c| c.distance).fold(0.0, f64::max),
            bands,
            wall_ms,
            code_version: code_version.into(),
        }
    }

    /// `profile.csv` as bytes: `scene_id, profile`, the [`SolvedProfile::columns`] (`{:e}`,
    /// empty where NaN: Theta where not solved for), then `in_domain, domain_distance` as
    /// `predict` writes them.
    pub fn table(&self) -> Result<Vec<u8>> {
        let err = |e: String| SolverError::File {
            path: PROFILE.into(),
            message: e,
        };
        let mut w = csv::Writer::from_writer(Vec::new());
        let columns = self.columns();
        let header = [col::SCENE_ID, col::PROFILE]
            .into_iter()
            .chain(columns.iter().map(|(name, _)| name.as_str()))
            .chain([col::IN_DOMAIN, col::DOMAIN_DISTANCE]);
        w.write_record(header).map_err(|e| err(e.to_string()))?;
        let f = &self.scene.file;
        for (k, check) in self.checks.iter().enumerate() {
            let mut record = vec![f.name.clone(), f.fluid.profile.clone()];
            record.extend(columns.iter().map(|(_, values)| {
                if values[k].is_nan() {
                    String::new()
                } else {
                    format!("{:e}", values[k])
                }
            }));
            record.extend([check.inside().to_string(), format!("{:e}", check.distance)]);
            w.write_record(&record).map_err(|e| err(e.to_string()))?;
        }
        w.into_inner().map_err(|e| err(e.to_string()))
    }

    /// Writes `profile.csv`, `summary.json` (of `summary`) and `scene.toml` into `dir`,
    /// each whole.
    pub fn write(&self, dir: &Path, summary: &SolveSummary) -> Result<()> {
        let io = |path: &Path, e: String| SolverError::File {
            path: path.display().to_string(),
            message: e,
        };
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e.to_string()))?;
        let json = serde_json::to_string_pretty(summary).expect("a summary serialises");
        sim::RunFolder::new(dir)
            .record_scene(&self.scene.file)
            .map_err(|e| io(dir, e.to_string()))?;
        // The profile last: it is what marks a finished solve (an earlier solution that a
        // re-run refuses to replace), so a write that fails leaves none.
        for (name, bytes) in [(SUMMARY, json.into_bytes()), (PROFILE, self.table()?)] {
            let path = dir.join(name);
            schema::write_atomic(&path, &bytes).map_err(|e| io(&path, e.to_string()))?;
        }
        Ok(())
    }
}

impl SolveSummary {
    /// The summary in `dir`.
    pub fn read(dir: &Path) -> Result<SolveSummary> {
        let path = dir.join(SUMMARY);
        let err = |message: String| SolverError::File {
            path: path.display().to_string(),
            message,
        };
        let text = std::fs::read_to_string(&path).map_err(|e| err(e.to_string()))?;
        serde_json::from_str(&text).map_err(|e| err(format!("not a solve's summary: {e}")))
    }
}
