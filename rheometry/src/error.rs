//! The crate's one error type.

/// What measuring from runs can fail on.
#[derive(Debug, thiserror::Error)]
pub enum RheometryError {
    #[error(transparent)]
    Sim(#[from] sim::SimError),
    #[error(transparent)]
    Surrogate(#[from] surrogate::SurrogateError),
    #[error(transparent)]
    Schema(#[from] schema::SchemaError),
    /// A result file that cannot be read, or runs that are not those of the grid.
    #[error("{path}: {message}")]
    File { path: String, message: String },
}

/// Result with [`RheometryError`].
pub type Result<T> = std::result::Result<T, RheometryError>;
