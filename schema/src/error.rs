//! The schema's one error type.

/// What reading a table, or writing a file, can fail on.
#[derive(Debug, thiserror::Error)]
pub enum SchemaError {
    /// The file could not be read.
    #[error("reading {path}")]
    Read {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// A file could not be written.
    #[error("writing {path}: {source}")]
    Write {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// The text breaks the table's format; the message names the line and column.
    #[error("{0}")]
    Format(String),
    /// A format error in the named file.
    #[error("in {path}")]
    InFile {
        path: String,
        #[source]
        source: Box<SchemaError>,
    },
}

/// Result with [`SchemaError`].
pub type Result<T> = std::result::Result<T, SchemaError>;
