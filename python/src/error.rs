//! The package's exception, `suspflow.SuspflowError`, raised with the crates' messages.
use pyo3::exceptions::PyException;
use pyo3::PyErr;

pyo3::create_exception!(
    _native,
    SuspflowError,
    PyException,
    "An error of the simulator, the surrogate models or the profile solver (bad input names the field)."
);

/// Any of the crates' errors, with the context that says what was being done.
#[derive(Debug)]
pub struct Error(pub String);

impl Error {
    /// `e` prefixed with what was being done.
    pub fn context(what: impl std::fmt::Display, e: impl std::fmt::Display) -> Self {
        Error(format!("{what}: {e}"))
    }
}

impl From<sim::SimError> for Error {
    fn from(e: sim::SimError) -> Self {
        Error(e.to_string())
    }
}

impl From<surrogate::SurrogateError> for Error {
    fn from(e: surrogate::SurrogateError) -> Self {
        Error(e.to_string())
    }
}

impl From<solver::SolverError> for Error {
    fn from(e: solver::SolverError) -> Self {
        Error(e.to_string())
    }
}

impl From<Error> for PyErr {
    fn from(e: Error) -> Self {
        SuspflowError::new_err(e.0)
    }
}
