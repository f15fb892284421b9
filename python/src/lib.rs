//! The native half of the Python package `suspflow` (module `suspflow._native`): thin
//! bindings of the `sim`, `surrogate`, `solver` and `rheometry` crates. Tables cross the boundary as
//! columns (lists of floats or strings) or CSV bytes; `suspflow/__init__.py` turns them into
//! NumPy arrays and pandas DataFrames. The physics, units and equations are the crates'
//! (docs/physics.md); the docstrings of `suspflow/__init__.py` restate the units.
use pyo3::prelude::*;

mod cross_validate;
mod dataset;
mod error;
mod flow_curves;
mod generate;
mod green_kubo;
mod models;
mod scene;
mod simulate;
mod solve;
mod train;
mod worker;

/// Version of the code that produced a result: package version and commit (the
/// workspace's stamp, `build/stamp.rs`), as the command line writes it.
pub const CODE_VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("SUSPFLOW_COMMIT"));

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    error::Error::register(m)?;
    m.add("CODE_VERSION", CODE_VERSION)?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<models::Predictions>()?;
    m.add_class::<solve::Solution>()?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(models::predict, m)?)?;
    m.add_function(wrap_pyfunction!(models::validate, m)?)?;
    m.add_function(wrap_pyfunction!(cross_validate::cross_validate, m)?)?;
    m.add_function(wrap_pyfunction!(flow_curves::flow_curves, m)?)?;
    m.add_function(wrap_pyfunction!(generate::generate, m)?)?;
    m.add_function(wrap_pyfunction!(green_kubo::green_kubo, m)?)?;
    m.add_function(wrap_pyfunction!(dataset::read_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(solve::solve, m)?)?;
    m.add_function(wrap_pyfunction!(train::train, m)?)?;
    Ok(())
}
