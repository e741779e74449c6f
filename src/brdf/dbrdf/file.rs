//! The brdfkit D-BRDF file: the half-vector table `p(h)` of a [`DBrdf`] as a single-channel
//! OpenEXR image, with `c` and `R_s` in the header (thesis 2.3.6).
//!
//! Design rule: self-describing, like the SH file (`sh::file`): the reader checks
//! every attribute and refuses a file that is missing one rather than guessing.
//!
//! # Format, version 1
//! * OpenEXR, one part named `dbrdf-p`, one 32-bit float channel named `p`. Encoding: RLE
//!   compression, 64x64 tiles (lossless; the `exr` crate's `Encoding::FAST_LOSSLESS`;
//!   `tests/integration/file_formats.rs` reads it back from a written file's headers). Image
//!   **width = nu** (half-vector azimuth texels), **height = nv** (polar texels); pixel
//!   `(x, y) = (i, j)` holds `p` at texel `(i, j)`, so row 0 (the top in EXR viewers) is
//!   next to the normal. Values are finite and `>= 0`, normalised to unit
//!   projected area (`sum p cos(polar) dω = 1`).
//! * Attributes: `brdfkit.format: string = "brdfkit-dbrdf"`, `brdfkit.version: int = 1`,
//!   `brdfkit.param: string` = [`PARAMETERIZATION`] (the hemispherical texel convention of
//!   [`crate::conventions`], applied to the local half vector), `brdfkit.c: float` (the
//!   constant `c`, finite, > 0), `brdfkit.rs: v3f` (`R_s`, RGB, each in [0, 1]),
//!   `brdfkit.provenance: string` (free text).
//!
//! Reading fails with a [`DbrdfFileError`] naming the file and the problem; writing goes to
//! a temporary file in the same directory that is renamed over the target.

use super::DBrdf;
use crate::image_io::exr_guard::{self, text, Attributes, ExrGuardError};
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, Layer, LayerAttributes,
    WritableImage,
};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Value of `brdfkit.format`.
pub const FORMAT_NAME: &str = "brdfkit-dbrdf";
/// Value of `brdfkit.version` written and read.
pub const FORMAT_VERSION: i32 = 1;
/// Value of `brdfkit.param`.
pub const PARAMETERIZATION: &str = "half-vector hemisphere; s=azimuth_h/(2pi), t=polar_h/(pi/2); \
texel (i,j) centre ((i+0.5)/nu, (j+0.5)/nv); GL_LINEAR, azimuth GL_REPEAT, polar GL_CLAMP_TO_EDGE; \
local frame: +z normal, azimuth 0 = world +y projected onto the tangent plane; \
f = c p(h) F(k.h) / (k1.n + k2.n - (k1.n)(k2.n)), F Schlick with R_s";
const LAYER: &str = "dbrdf-p";

/// What went wrong with a D-BRDF file.
#[derive(Debug, thiserror::Error)]
pub enum DbrdfFileError {
    #[error("{path}: I/O error: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: not a readable OpenEXR file: {message}")]
    Exr { path: PathBuf, message: String },
    #[error(
        "{path}: not a brdfkit D-BRDF file (brdfkit.format is {}; expected '{FORMAT_NAME}' from `brdfkit fit-dbrdf`)",
        .found.as_deref().map_or("missing".to_string(), |f| format!("'{f}'"))
    )]
    NotDbrdf {
        path: PathBuf,
        found: Option<String>,
    },
    #[error("{path}: attribute `{name}` missing or of the wrong type")]
    MissingAttribute { path: PathBuf, name: &'static str },
    #[error("{path}: attribute `{name}` has unsupported value {value}")]
    BadAttribute {
        path: PathBuf,
        name: &'static str,
        value: String,
    },
    #[error("{path}: no 32-bit float channel `p`")]
    Channel { path: PathBuf },
    #[error("{path}: channel `p` is negative or non-finite at texel ({i}, {j})")]
    Value { path: PathBuf, i: usize, j: usize },
    /// `c p` over [`crate::brdf::MAX_BRDF_VALUE`] at a texel (a finite value that would
    /// overflow in shading).
    #[error(
        "{path}: channel `p` at texel ({i}, {j}): c * p = {c:e} * {p:e} exceeds the limit {max:e} 1/sr",
        max = crate::brdf::MAX_BRDF_VALUE
    )]
    TooLarge {
        path: PathBuf,
        i: usize,
        j: usize,
        c: f32,
        p: f32,
    },
    /// Not a regular file, or over [`crate::image_io::MAX_EXR_FILE_BYTES`].
    #[error(transparent)]
    File(#[from] crate::error::FileError),
}

fn exr_err(path: &Path, e: exr::error::Error) -> DbrdfFileError {
    match e {
        exr::error::Error::Io(source) if source.kind() != std::io::ErrorKind::UnexpectedEof => {
            DbrdfFileError::Io {
                path: path.to_owned(),
                source,
            }
        }
        other => DbrdfFileError::Exr {
            path: path.to_owned(),
            message: other.to_string(),
        },
    }
}

/// Writes `d` to `path` (module doc), through a unique temporary file beside it, synced,
/// and a rename ([`crate::image_io::replace_via_temp`]). Fails with
/// [`DbrdfFileError::Io`] or [`DbrdfFileError::Exr`]; the temporary file is removed.
pub fn write_dbrdf(path: &Path, d: &DBrdf, provenance: &str) -> Result<(), DbrdfFileError> {
    let (nu, nv) = d.grid();
    let mut a = LayerAttributes::named(text(LAYER));
    let o = &mut a.other;
    o.insert(
        text("brdfkit.format"),
        AttributeValue::Text(text(FORMAT_NAME)),
    );
    o.insert(text("brdfkit.version"), AttributeValue::I32(FORMAT_VERSION));
    o.insert(
        text("brdfkit.param"),
        AttributeValue::Text(text(PARAMETERIZATION)),
    );
    o.insert(text("brdfkit.c"), AttributeValue::F32(d.c));
    o.insert(
        text("brdfkit.rs"),
        AttributeValue::FloatVec3((d.rs.x, d.rs.y, d.rs.z)),
    );
    o.insert(
        text("brdfkit.provenance"),
        AttributeValue::Text(text(provenance)),
    );
    let chans = vec![AnyChannel::new(
        text("p"),
        FlatSamples::F32(d.table().to_vec()),
    )];
    let layer = Layer::new(
        (nu, nv),
        a,
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(chans.into()),
    );
    let image = Image::from_layer(layer);
    crate::image_io::replace_via_temp(
        path,
        |tmp| image.write().to_file(tmp).map_err(|e| exr_err(path, e)),
        |source| DbrdfFileError::Io {
            path: path.to_owned(),
            source,
        },
    )
}

/// Reads a file written by [`write_dbrdf`]; returns the D-BRDF and its provenance. Fails
/// with a [`DbrdfFileError`] naming the file and the problem; never returns partial data.
///
/// Limits: a regular file of at most [`crate::image_io::MAX_EXR_FILE_BYTES`]; declared
/// pixels within [`crate::image_io::check_exr_declared_size`] of the file's length (checked
/// before any pixel is allocated, by the crate's one guarded reader
/// [`crate::image_io::exr_guard`]); every `c p` at most [`crate::brdf::MAX_BRDF_VALUE`].
pub fn read_dbrdf(path: &Path) -> Result<(DBrdf, String), DbrdfFileError> {
    // A device or FIFO is refused unopened; then the headers alone are read and the pixels
    // they declare checked against the file's length, before the decoder allocates them.
    let image =
        exr_guard::read_all_layers(path, crate::image_io::MAX_EXR_FILE_BYTES, "D-BRDF file")
            .map_err(|e| match e {
                ExrGuardError::File(e) => DbrdfFileError::File(e),
                ExrGuardError::Exr(e) => exr_err(path, e),
                ExrGuardError::DeclaredSize(message) => DbrdfFileError::Exr {
                    path: path.to_owned(),
                    message,
                },
            })?;
    let p = || path.to_owned();
    let layer = image.layer_data.first().ok_or(DbrdfFileError::NotDbrdf {
        path: p(),
        found: None,
    })?;
    let attrs = Attributes(&layer.attributes.other);
    let get_text = |name: &str| attrs.string(name);
    let format = get_text("brdfkit.format");
    if format.as_deref() != Some(FORMAT_NAME) {
        return Err(DbrdfFileError::NotDbrdf {
            path: p(),
            found: format,
        });
    }
    let missing = |name| DbrdfFileError::MissingAttribute { path: p(), name };
    let bad = |name, value: String| DbrdfFileError::BadAttribute {
        path: p(),
        name,
        value,
    };
    match attrs.i32("brdfkit.version") {
        Some(FORMAT_VERSION) => {}
        Some(v) => return Err(bad("brdfkit.version", v.to_string())),
        None => return Err(missing("brdfkit.version")),
    }
    let param = get_text("brdfkit.param").ok_or_else(|| missing("brdfkit.param"))?;
    if param != PARAMETERIZATION {
        return Err(bad("brdfkit.param", format!("{param:?}")));
    }
    let c = attrs.f32("brdfkit.c").ok_or_else(|| missing("brdfkit.c"))?;
    if !(c.is_finite() && c > 0.0) {
        return Err(bad("brdfkit.c", c.to_string()));
    }
    let rs = match attrs.v3f("brdfkit.rs") {
        Some((x, y, z)) => Vec3::new(x, y, z),
        None => return Err(missing("brdfkit.rs")),
    };
    if !rs.is_finite() || rs.min_element() < 0.0 || rs.max_element() > 1.0 {
        return Err(bad("brdfkit.rs", format!("{rs}")));
    }
    let provenance = get_text("brdfkit.provenance").ok_or_else(|| missing("brdfkit.provenance"))?;
    let (nu, nv) = (layer.size.0, layer.size.1);
    let chan = layer
        .channel_data
        .list
        .iter()
        .find(|ch| ch.name.eq("p"))
        .ok_or(DbrdfFileError::Channel { path: p() })?;
    let values = match &chan.sample_data {
        FlatSamples::F32(v) => v.clone(),
        _ => return Err(DbrdfFileError::Channel { path: p() }),
    };
    if let Some(k) = values.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(DbrdfFileError::Value {
            path: p(),
            i: k % nu,
            j: k / nu,
        });
    }
    if let Some(k) = values
        .iter()
        .position(|v| c * v > crate::brdf::MAX_BRDF_VALUE)
    {
        return Err(DbrdfFileError::TooLarge {
            path: p(),
            i: k % nu,
            j: k / nu,
            c,
            p: values[k],
        });
    }
    let mut d = DBrdf::new(nu, nv, values, rs);
    d.c = c;
    Ok((d, provenance))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_clear_errors() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let mut d = DBrdf::from_fn(8, 4, Vec3::new(0.1, 0.5, 0.9), |h| h.z.powi(8) + h.x.abs());
        d.c = 0.31;
        let path = dir.join("a.exr");
        write_dbrdf(&path, &d, "test").unwrap();
        let (back, prov) = read_dbrdf(&path).unwrap();
        assert_eq!(prov, "test");
        assert_eq!(back.table(), d.table());
        assert_eq!(back.grid(), d.grid());
        assert_eq!((back.c, back.rs), (d.c, d.rs));
        // An SH data set given to this reader: `sh::file`'s tests (brdf imports nothing
        // from sh).
        let e = read_dbrdf(&dir.join("missing.exr"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.exr"), "{e}");
    }
}
