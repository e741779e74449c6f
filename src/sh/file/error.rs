//! [`ShFileError`]: every way reading or writing an SH data-set file can fail, each naming
//! the file (and the part, attribute, channel or texel where there is one).
//!
//! Design rule: one variant per problem a reader can name; no partial data set accompanies
//! an error.

use super::FORMAT_VERSION;
use crate::sh::dataset::{ShDataError, MAX_BANDS};
use std::path::PathBuf;

/// What went wrong with an SH data-set file.
#[derive(Debug, thiserror::Error)]
pub enum ShFileError {
    /// Not a regular file (a device or FIFO is refused unopened), or over
    /// [`crate::image_io::MAX_EXR_FILE_BYTES`].
    #[error(transparent)]
    File(#[from] crate::error::FileError),
    #[error("{path}: I/O error: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: not a readable OpenEXR file: {message}")]
    Exr { path: PathBuf, message: String },
    #[error("{path}: no `{layer}` part")]
    MissingLayer { path: PathBuf, layer: &'static str },
    #[error("{path}: part `{layer}`: attribute `{name}` missing or of the wrong type")]
    MissingAttribute {
        path: PathBuf,
        layer: &'static str,
        name: &'static str,
    },
    #[error("{path}: part `{layer}`: attribute `{name}` has unsupported value `{value}`")]
    BadAttribute {
        path: PathBuf,
        layer: &'static str,
        name: &'static str,
        value: String,
    },
    #[error("{path}: unsupported format version {version} (this reader knows {FORMAT_VERSION})")]
    Version { path: PathBuf, version: i32 },
    #[error("{path}: part `{layer}`: band count {bands} out of range 1..={MAX_BANDS}")]
    Bands {
        path: PathBuf,
        layer: &'static str,
        bands: i32,
    },
    #[error("{path}: part `{layer}`: grid attributes {nu} x {nv} disagree with image size {width} x {height}")]
    GridMismatch {
        path: PathBuf,
        layer: &'static str,
        nu: i32,
        nv: i32,
        width: usize,
        height: usize,
    },
    #[error("{path}: part `{layer}`: missing channel `{channel}`")]
    MissingChannel {
        path: PathBuf,
        layer: &'static str,
        channel: String,
    },
    #[error("{path}: part `{layer}`: {count} channels, expected {expected}")]
    ChannelCount {
        path: PathBuf,
        layer: &'static str,
        count: usize,
        expected: usize,
    },
    #[error("{path}: part `{layer}`: channel `{channel}` is not 32-bit float")]
    ChannelType {
        path: PathBuf,
        layer: &'static str,
        channel: String,
    },
    #[error(
        "{path}: part `{layer}`: channel `{channel}` has a non-finite value at texel ({i}, {j})"
    )]
    NonFinite {
        path: PathBuf,
        layer: &'static str,
        channel: String,
        i: usize,
        j: usize,
    },
    /// A finite value over [`crate::brdf::MAX_BRDF_VALUE`] in magnitude (it would overflow
    /// to Inf in shading).
    #[error(
        "{path}: part `{layer}`: channel `{channel}` value {value:e} at texel ({i}, {j}) exceeds the limit +-{max:e}",
        max = crate::brdf::MAX_BRDF_VALUE
    )]
    TooLarge {
        path: PathBuf,
        layer: &'static str,
        channel: String,
        i: usize,
        j: usize,
        value: f32,
    },
    #[error("{path}: inconsistent data: {source}")]
    Data {
        path: PathBuf,
        #[source]
        source: ShDataError,
    },
}
