//! The crate's error type. Every message names the file or field at fault and the problem,
//! in one line, so the command line can print it as it is.

use std::path::PathBuf;

/// Everything that can go wrong between reading input and writing output.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {what}: {source}")]
    Io {
        path: PathBuf,
        what: &'static str,
        source: std::io::Error,
    },
    /// A file was read but its content is not valid.
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    /// A complete one-line message from a module with its own error type (it already
    /// names its file).
    #[error("{0}")]
    Message(String),
    /// A field (scene key or command-line option) has a value outside its domain.
    #[error("{field}: {message}")]
    Field { field: String, message: String },
}

impl Error {
    pub fn io(path: impl Into<PathBuf>, what: &'static str, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            what,
            source,
        }
    }
    pub fn format(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::Format {
            path: path.into(),
            message: message.into(),
        }
    }
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Field {
            field: field.into(),
            message: message.into(),
        }
    }
}

pub type Result<T> = std::result::Result<T, Error>;
