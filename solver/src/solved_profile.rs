//! A solve's result as `suspflow solve` writes it and the Python package returns it: the
//! profile per bin under the datasets' column names, its training-domain check and bands
//! (`profile.csv`), and the summary of the solve (`summary.json`). One writer for both.

use schema::columns as col;
use serde::Serialize;
use surrogate::DomainCheck;

use crate::bands::{ProfileBands, BANDED};
use crate::error::{Result, SolverError};
use crate::problem::ProfileProblem;
use crate::solution::ProfileSolution;
use crate::theta_balance::ThetaBalanceFit;

/// A solved profile with what is known about it.
pub struct SolvedProfile<'a> {
    /// The scene's name, forcing expression, box height and volume fraction.
    pub scene_id: &'a str,
    pub profile: &'a str,
    pub l_y: f64,
    pub phi: f64,
    pub problem: &'a ProfileProblem,
    pub solution: &'a ProfileSolution,
    /// Each bin's check against the closure's training domain.
    pub checks: &'a [DomainCheck],
    /// The bands, when the models were saved with their calibration.
    pub bands: Option<&'a ProfileBands>,
}

impl<'a> SolvedProfile<'a> {
    /// The solved profile of `scene`: its name, forcing, box height and volume fraction
    /// with the solve's problem, solution, domain checks and bands.
    pub fn of_scene(
        scene: &'a sim::Scene,
        problem: &'a ProfileProblem,
        solution: &'a ProfileSolution,
        checks: &'a [DomainCheck],
        bands: Option<&'a ProfileBands>,
    ) -> Self {
        let f = &scene.file;
        SolvedProfile {
            scene_id: &f.name,
            profile: &f.fluid.profile,
            l_y: f.box_.l_y,
            phi: f.particles.phi,
            problem,
            solution,
            checks,
            bands,
        }
    }

    /// The numeric columns per bin, in `profile.csv`'s order after `scene_id` and `profile`:
    /// `L_y, phi, y, u_inf, u, gdot, sigma_xy, P, phi_loc, J, mu, Theta` (NaN unless the
    /// closure solved for Theta), `Delta_v, f_x, d_ext`, then with bands `u_lower, u_upper,
    /// phi_loc_lower, phi_loc_upper, mu_lower, mu_upper`.
    pub fn numeric_columns(&self) -> Vec<(String, Vec<f64>)> {
        let (s, n) = (self.solution, self.problem.n_bins());
        let theta = if s.theta.is_empty() {
            vec![f64::NAN; n]
        } else {
            s.theta.clone()
        };
        let mut columns: Vec<(String, Vec<f64>)> = [
            (col::L_Y, vec![self.l_y; n]),
            (col::PHI, vec![self.phi; n]),
            (col::Y, self.problem.bin_centres()),
            (col::U_INF, self.problem.u_inf.clone()),
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

    /// `profile.csv`: `scene_id, profile`, the [`SolvedProfile::numeric_columns`] (`{:e}`,
    /// Theta empty where not solved for), then `in_domain, domain_distance` as `predict`
    /// writes them.
    pub fn to_csv(&self) -> Result<String> {
        let columns = self.numeric_columns();
        let csv_error = |e: csv::Error| SolverError::InvalidArgument(format!("profile.csv: {e}"));
        let mut w = csv::Writer::from_writer(Vec::new());
        let header = [col::SCENE_ID, col::PROFILE]
            .into_iter()
            .map(str::to_owned)
            .chain(columns.iter().map(|(name, _)| name.clone()))
            .chain([col::IN_DOMAIN.to_owned(), col::DOMAIN_DISTANCE.to_owned()]);
        w.write_record(header).map_err(csv_error)?;
        for (k, check) in self.checks.iter().enumerate() {
            let mut record = vec![self.scene_id.to_owned(), self.profile.to_owned()];
            record.extend(columns.iter().map(|(_, v)| {
                if v[k].is_nan() {
                    String::new()
                } else {
                    format!("{:e}", v[k])
                }
            }));
            record.extend([check.inside().to_string(), format!("{:e}", check.distance)]);
            w.write_record(&record).map_err(csv_error)?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| SolverError::InvalidArgument(format!("profile.csv: {e}")))?;
        String::from_utf8(bytes).map_err(|e| SolverError::InvalidArgument(e.to_string()))
    }
}

/// What `summary.json` holds.
#[derive(Debug, Clone, Serialize)]
pub struct SolveSummary {
    pub scene: String,
    pub closure: &'static str,
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
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bands: Option<BandSummary>,
    pub wall_ms: f64,
    pub code_version: String,
}

/// The bands of a solve: their level, margins and how they did on held-out families.
#[derive(Debug, Clone, Serialize)]
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
