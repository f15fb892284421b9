//! The local-rheology closure fitted on a dataset.

use sim::output::dataset_columns as col;
use surrogate::{Dataset, LocalRheology};

use crate::error::Result;

/// `mu = A J^b` and eq 6.7 fitted on every row of `data` that has J, phi_loc and mu.
pub fn fit_local_rheology(data: &Dataset) -> Result<LocalRheology> {
    let rows = data.complete_rows(&[col::J, col::PHI_LOC, col::MU])?;
    let column = |name: &str| -> Result<Vec<f64>> {
        let c = data.column(name)?;
        Ok(rows.iter().map(|&r| c[r]).collect())
    };
    Ok(LocalRheology::fit(
        &column(col::J)?,
        &column(col::PHI_LOC)?,
        &column(col::MU)?,
    )?)
}
