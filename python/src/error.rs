//! The package's exceptions, raised with the crates' messages: `suspflow.SuspflowError` and,
//! under it, one class per kind of failure a caller may want to handle on its own.
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::PyErr;
use std::path::Path;

pyo3::create_exception!(
    suspflow,
    SuspflowError,
    PyException,
    "An error of the simulator, the surrogate models or the profile solver (bad input names the field)."
);
pyo3::create_exception!(
    suspflow,
    FileError,
    SuspflowError,
    "A file that is missing, unreadable, locked by another run, or could not be written."
);
pyo3::create_exception!(
    suspflow,
    SceneError,
    SuspflowError,
    "A scene that is not valid: the field and the allowed range are named."
);
pyo3::create_exception!(
    suspflow,
    ModelError,
    SuspflowError,
    "A trained model that cannot be loaded or does not fit the data (unknown mapping, missing feature, inconsistent files)."
);
pyo3::create_exception!(
    suspflow,
    DataError,
    SuspflowError,
    "A table whose contents are not what the command reads (missing column, a cell that is not a number or not physical)."
);
pyo3::create_exception!(
    suspflow,
    RunInterrupted,
    SuspflowError,
    "A run stopped before its end by a signal (its checkpoint holds its state; resume=True continues)."
);

/// Which class of [`SuspflowError`] an error raises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    General,
    File,
    Scene,
    Model,
    Data,
    Interrupted,
}

/// Any of the crates' errors, with the context that says what was being done.
#[derive(Debug)]
pub struct Error {
    pub kind: Kind,
    pub message: String,
}

impl Error {
    /// An error of `kind`.
    pub fn new(kind: Kind, message: impl Into<String>) -> Self {
        Error {
            kind,
            message: message.into(),
        }
    }

    /// `e` prefixed with what was being done, its kind kept.
    pub fn context(what: impl std::fmt::Display, e: impl Into<Error>) -> Self {
        let e = e.into();
        Error::new(e.kind, format!("{what}: {}", e.message))
    }

    /// The classes of this module, for `suspflow._native`.
    pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
        let py = m.py();
        m.add("SuspflowError", py.get_type::<SuspflowError>())?;
        m.add("FileError", py.get_type::<FileError>())?;
        m.add("SceneError", py.get_type::<SceneError>())?;
        m.add("ModelError", py.get_type::<ModelError>())?;
        m.add("DataError", py.get_type::<DataError>())?;
        m.add("RunInterrupted", py.get_type::<RunInterrupted>())?;
        Ok(())
    }
}

impl From<String> for Error {
    fn from(message: String) -> Self {
        Error::new(Kind::General, message)
    }
}

impl From<sim::SimError> for Error {
    fn from(e: sim::SimError) -> Self {
        use sim::SimError as E;
        let kind = match &e {
            // A scene given as a mapping is named `<mapping>`; a path that does not exist
            // is a missing file, not a bad scene.
            E::SceneFile { path, .. } if !path.starts_with('<') && !Path::new(path).exists() => {
                Kind::File
            }
            E::Field { .. } | E::Profile { .. } | E::SceneFile { .. } | E::Packing(_) => {
                Kind::Scene
            }
            E::Checkpoint { .. }
            | E::CheckpointUnusable { .. }
            | E::Locked { .. }
            | E::Output { .. } => Kind::File,
            E::Table(schema::SchemaError::Read { .. } | schema::SchemaError::Write { .. }) => {
                Kind::File
            }
            E::Table(_) => Kind::Data,
            E::Interrupted { .. } | E::InterruptedPacking => Kind::Interrupted,
            _ => Kind::General,
        };
        Error::new(kind, e.to_string())
    }
}

impl From<surrogate::SurrogateError> for Error {
    fn from(e: surrogate::SurrogateError) -> Self {
        use surrogate::SurrogateError as E;
        let kind = match &e {
            E::Io { .. } | E::UnreadableFile { .. } => Kind::File,
            E::InconsistentModel { .. }
            | E::ModelFormat(_)
            | E::UnknownMapping { .. }
            | E::Xgboost(_)
            | E::FeatureMismatch { .. }
            | E::NotTrainingData { .. }
            | E::Json { .. } => Kind::Model,
            E::MissingColumn { .. }
            | E::NotANumber { .. }
            | E::EmptyCell { .. }
            | E::NonFinite { .. }
            | E::BeyondF32 { .. }
            | E::Unphysical { .. }
            | E::NonPositive { .. }
            | E::EmptyDataset { .. }
            | E::RaggedRow { .. }
            | E::Csv { .. } => Kind::Data,
            _ => Kind::General,
        };
        Error::new(kind, e.to_string())
    }
}

impl From<solver::SolverError> for Error {
    fn from(e: solver::SolverError) -> Self {
        match e {
            solver::SolverError::Surrogate(e) => e.into(),
            solver::SolverError::During { doing, source } => Error::context(doing, *source),
            solver::SolverError::File { .. } => Error::new(Kind::File, e.to_string()),
            solver::SolverError::Interrupted { .. } => Error::new(Kind::Interrupted, e.to_string()),
            solver::SolverError::WouldReplace { .. } => Error::new(
                Kind::File,
                format!("{e}; force=True replaces it, or choose another out"),
            ),
            e => Error::new(Kind::General, e.to_string()),
        }
    }
}

impl From<rheometry::RheometryError> for Error {
    fn from(e: rheometry::RheometryError) -> Self {
        use rheometry::RheometryError as E;
        match e {
            E::Sim(e) => e.into(),
            E::Surrogate(e) => e.into(),
            E::Schema(schema::SchemaError::Read { .. } | schema::SchemaError::Write { .. })
            | E::File { .. } => Error::new(Kind::File, e.to_string()),
            E::Schema(_) => Error::new(Kind::Data, e.to_string()),
        }
    }
}

impl From<Error> for PyErr {
    fn from(e: Error) -> Self {
        match e.kind {
            Kind::General => SuspflowError::new_err(e.message),
            Kind::File => FileError::new_err(e.message),
            Kind::Scene => SceneError::new_err(e.message),
            Kind::Model => ModelError::new_err(e.message),
            Kind::Data => DataError::new_err(e.message),
            Kind::Interrupted => RunInterrupted::new_err(e.message),
        }
    }
}
