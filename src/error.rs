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

/// Why an input file was refused before (or while) reading it
/// ([`crate::image_io::read_regular_file`], [`crate::image_io::check_regular_file`]).
/// Shared by every reader, whatever its own error type: each wraps it unchanged, so the
/// message is the same one line naming the file wherever it comes from.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file could not be examined or read.
    #[error("{path}: cannot read {what}: {source}")]
    Io {
        path: PathBuf,
        what: &'static str,
        #[source]
        source: std::io::Error,
    },
    /// A directory, device (`/dev/zero`), FIFO or socket: it has no length to check and
    /// reading it may never end, so it is refused without being opened.
    #[error("{path}: {what} is not a regular file (a directory, device or FIFO)")]
    NotRegular { path: PathBuf, what: &'static str },
    /// Longer than the reader's stated limit.
    #[error("{path}: {what} is {len} bytes, over the {limit} byte limit")]
    TooLarge {
        path: PathBuf,
        what: &'static str,
        len: u64,
        limit: u64,
    },
}

impl From<FileError> for Error {
    fn from(e: FileError) -> Self {
        Error::Message(e.to_string())
    }
}

/// A TOML parse error as one line, `line N: message` (the line of the error's span in
/// `text`, 1-based), for every TOML file brdfkit reads (scenes, the golden manifest).
pub fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message().trim().replace('\n', " ");
    match e.span() {
        Some(span) => {
            let line = text[..span.start].matches('\n').count() + 1;
            format!("line {line}: {msg}")
        }
        None => msg,
    }
}
