//! The simulator's error type.
use thiserror::Error;

/// Every failure the simulator reports: bad input names the field, runtime failures name the step and particle.
#[derive(Debug, Error)]
pub enum SimError {
    /// A scene field has an invalid value.
    #[error("scene field `{field}`: {message}")]
    Field { field: String, message: String },
    /// The flow profile expression does not parse, is not finite, or is not periodic.
    #[error("flow profile `{expr}`: {message}")]
    Profile { expr: String, message: String },
    /// The initial configuration could not be built.
    #[error("initial packing: {0}")]
    Packing(String),
}
