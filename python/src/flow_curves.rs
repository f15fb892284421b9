//! `flow_curves`: the flow curves of a grid of homogeneous-shear runs that `generate` ran,
//! as `suspflow flow-curves` computes them (`rheometry::FlowCurves`): the table of the
//! finished runs (`flow_curves.csv`'s text) and the jamming law fitted per state and stress
//! convention.
use crate::error::Error;
use pyo3::prelude::*;
use rheometry::{read_green_kubo_replicas, FlowCurveRow, FlowCurveSource, FlowCurves};
use sim::input::grid::Grid;
use std::path::PathBuf;
use surrogate::CONVENTIONS;

/// One fit of the jamming law `eta_r = (1 - phi/phi_J)^(-lambda)`: the state (mu_p, peclet,
/// alpha, rho, dt_factor and the fixed dt if any), the stress convention, phi_J and its
/// standard error, lambda and its standard error (`None` where the points could not be
/// fitted), and why not.
type FitRecord = (
    f64,
    f64,
    Option<f64>,
    f64,
    f64,
    Option<f64>,
    &'static str,
    Option<[f64; 4]>,
    Option<String>,
);

/// The flow curves of the grid file `grid` run into the batch folders `runs` (one, or one
/// per shard of the grid), with the Green-Kubo runs in the folders `green_kubo`:
/// `flow_curves.csv`'s text, the fits, and the labels of the runs not finished. With
/// `table` (a `flow_curves.csv` written earlier for the grid) the runs replace its lines of
/// the same scenes, or, with no runs, the table alone gives the curves.
#[pyfunction]
#[pyo3(signature = (grid, runs, green_kubo = Vec::new(), table = None))]
pub fn flow_curves(
    grid: PathBuf,
    runs: Vec<PathBuf>,
    green_kubo: Vec<PathBuf>,
    table: Option<PathBuf>,
) -> Result<(String, Vec<FitRecord>, Vec<String>), Error> {
    let grid = Grid::from_path(&grid, false)?;
    let green_kubo = read_green_kubo_replicas(&green_kubo)?;
    let source = FlowCurveSource::new(table.as_deref(), &runs);
    let curves = FlowCurves::read(&grid, source, &green_kubo)?;
    let table = FlowCurveRow::to_csv(&curves.rows).map_err(Error::from)?;
    let mut fits = Vec::new();
    for f in &curves.fits {
        let s = f.state;
        for ((convention, _), fit) in CONVENTIONS.iter().zip(&f.fits) {
            let (values, why) = match fit {
                Ok(j) => (
                    Some([j.all.phi_j, j.phi_j_se, j.all.lambda, j.lambda_se]),
                    None,
                ),
                Err(e) => (None, Some(e.to_string())),
            };
            fits.push((
                s.mu_p,
                s.peclet,
                s.alpha,
                s.rho,
                s.step.dt_factor,
                s.step.dt,
                *convention,
                values,
                why,
            ));
        }
    }
    let table = String::from_utf8(table).map_err(|e| Error::from(e.to_string()))?;
    Ok((table, fits, curves.missing))
}
