//! The brdfkit SH data-set file: one multichannel, multi-part OpenEXR file that a GPU build
//! can upload as 3D textures (thesis 3.1.4-3.1.5: one texture layer per SH term).
//!
//! Design rule: the file is self-describing. Every convention a reader needs (grid,
//! parameterization, SH normalisation, phase, ordering, cosine flag) is written as a header
//! attribute, and the reader refuses any file whose attributes are missing, unknown or
//! inconsistent rather than guessing.
//!
//! # Format, version 1
//! * OpenEXR, 32-bit float channels. Encoding: RLE compression, 64x64 tiles (lossless;
//!   the `exr` crate's `Encoding::FAST_LOSSLESS`, in both parts;
//!   `tests/integration/file_formats.rs` reads it back from a written file's headers).
//! * Part (layer) `sh-coefficients`, required: image **width = nu** (azimuth texels),
//!   **height = nv** (polar texels). Pixel `(x, y) = (i, j)` holds view texel `(i, j)`;
//!   row `y = 0` (the top of the image in EXR viewers) is the polar texel next to the
//!   normal. One channel per `(l, m)` and colour, named `c.l{l}.m{m}.{R|G|B}`, e.g.
//!   `c.l3.m-2.R`; `3 bands^2` channels in all (EXR stores them sorted by name; readers
//!   find them by name). A GPU build packs channel `c.l{l}.m{m}.X` into depth layer
//!   `k = l*l + l + m` of the colour-X 3D texture and samples it at depth `(k + 1/2)/T`.
//! * Part `sh-basis`, optional: the basis table `Y_lm(light texel)` on its own
//!   `nu_b x nv_b` grid, channels `Y.l{l}.m{m}`, for GPU builds whose shaders cannot
//!   evaluate the basis (thesis 3.1.4). A stored table must equal the analytic basis of
//!   [`crate::sh::basis`] at its texel centres (within
//!   [`BASIS_TABLE_TOLERANCE`](crate::sh::dataset::BASIS_TABLE_TOLERANCE); the reader
//!   refuses any other table with [`ShFileError::Data`]), and it is never used for
//!   rendering: the data set is its coefficients with the analytic basis
//!   ([`crate::sh::dataset`], "Which basis defines a data set").
//! * Attributes of every part (EXR attribute `name: type = value`):
//!   - `brdfkit.format: string = "brdfkit-sh"`, `brdfkit.version: int = 1`,
//!   - `brdfkit.content: string = "coefficients" | "basis"`,
//!   - `brdfkit.bands: int` (L, all l < L; 1..=[`MAX_BANDS`](crate::sh::dataset::MAX_BANDS)),
//!   - `brdfkit.nu: int`, `brdfkit.nv: int` (must equal the image size),
//!   - `brdfkit.param: string` = [`PARAMETERIZATION`],
//!   - `brdfkit.sh: string` = [`SH_CONVENTION`],
//!   - `brdfkit.cosine: int` (1 if the values include `cos(polar_i)`, else 0; coefficient
//!     part only),
//!   - `brdfkit.provenance: string` (UTF-8 bytes, free text; coefficient part only),
//!   - `brdfkit.band_threshold: float` (optional, coefficient part only; default
//!     [`DEFAULT_BAND_THRESHOLD`](crate::sh::dataset::DEFAULT_BAND_THRESHOLD) = 0 when
//!     absent): the largest fraction of the coefficient energy `sum c_lm^2` (over texels,
//!     colours, l, m) that a renderer may drop by shading only the first bands
//!     ([`ShDataset::effective_bands`](crate::sh::ShDataset::effective_bands)); must satisfy
//!     `0 <= value < 1`. Written only when non-zero, so files without it stay byte-identical.
//!   - `brdfkit.lookup: string = "nearest" | "bilinear"` (optional, coefficient part only;
//!     nearest when absent, the meaning of every file written before it existed): the filter
//!     of the coefficient table (view direction; thesis 3.1.4, `GL_NEAREST` / `GL_LINEAR`,
//!     [`Lookup`](crate::sh::dataset::Lookup)) that reproduces the source best, the one a
//!     renderer uses unless told otherwise (`brdfkit render --lookup`, a scene's
//!     `material.lookup`). `brdfkit acquire` writes `"bilinear"`. Written only when not
//!     nearest, so files of nearest data sets stay byte-identical; any other value is
//!     refused ([`ShFileError::BadAttribute`]).
//!   - `brdfkit.isotropic: int = 1` (optional, coefficient part only; 0 when absent): the
//!     data describe an isotropic BRDF, so a renderer may shade them in the view-aligned
//!     frame and read only azimuth texel 0 ([`ShDataset::isotropic`](crate::sh::ShDataset::isotropic);
//!     [`crate::conventions`], "Frame of isotropic tabulated materials"). `brdfkit acquire`
//!     writes it for an isotropic source. Written only when set; any value but 0 or 1 is
//!     refused.
//!
//! Reading fails with [`ShFileError`] naming the file and the problem; no partial data set
//! is ever returned. Writing goes to a temporary file in the same directory, then renames
//! it over the target, so a reader never sees a half-written file.
//!
//! # Layout
//! - this file: the format's constants and channel names;
//! - [`error`] -- [`ShFileError`], what went wrong, naming the file;
//! - [`mod@write`] -- [`write_sh_dataset`];
//! - [`read`] -- [`read_sh_dataset`], through the crate's one guarded EXR reader
//!   ([`crate::image_io::exr_guard`]: regular file, size limit, declared pixels checked
//!   against the file's length before decoding) and its attribute accessors.

pub mod error;
pub mod read;
#[cfg(test)]
mod tests;
pub mod write;

pub use error::ShFileError;
pub use read::read_sh_dataset;
pub use write::write_sh_dataset;

use super::basis::sh_lm;
use std::path::Path;

/// Value of `brdfkit.format`.
pub const FORMAT_NAME: &str = "brdfkit-sh";
/// Value of `brdfkit.version` written by this code; the only version it reads.
pub const FORMAT_VERSION: i32 = 1;
/// Value of `brdfkit.param`: the hemispherical grid parameterization (see
/// [`crate::conventions`]).
pub const PARAMETERIZATION: &str = "hemisphere; s=azimuth/(2pi), t=polar/(pi/2); \
texel (i,j) centre ((i+0.5)/nu, (j+0.5)/nv); azimuth GL_REPEAT, polar GL_CLAMP_TO_EDGE; \
local frame: +z normal, azimuth 0 = world +y projected onto the tangent plane, \
azimuth = atan2(y, x) in [0, 2pi)";
/// Value of `brdfkit.sh`: the SH convention of [`crate::sh::basis`].
pub const SH_CONVENTION: &str = "real; orthonormal over the full sphere; \
no Condon-Shortley phase; m>0 sqrt2 K P cos(m az), m<0 sqrt2 K P sin(|m| az); \
index k = l*l + l + m; polar angle from local +z";

/// Name of the optional isotropy attribute (see the module doc).
pub const ISOTROPIC_ATTRIBUTE: &str = "brdfkit.isotropic";

/// Name of the optional coefficient-lookup attribute (see the module doc).
pub const LOOKUP_ATTRIBUTE: &str = "brdfkit.lookup";

/// Value of [`LOOKUP_ATTRIBUTE`] for a lookup.
pub fn lookup_value(l: crate::sh::dataset::Lookup) -> &'static str {
    match l {
        crate::sh::dataset::Lookup::Nearest => "nearest",
        crate::sh::dataset::Lookup::Bilinear => "bilinear",
    }
}

const COEFF_LAYER: &str = "sh-coefficients";
const BASIS_LAYER: &str = "sh-basis";
const COLOURS: [&str; 3] = ["R", "G", "B"];

/// Channel name of coefficient `k` (flat SH index) and colour `c` (0 R, 1 G, 2 B).
pub fn coeff_channel_name(k: usize, c: usize) -> String {
    let (l, m) = sh_lm(k);
    format!("c.l{l}.m{m}.{}", COLOURS[c])
}

/// Channel name of basis term `k`.
pub fn basis_channel_name(k: usize) -> String {
    let (l, m) = sh_lm(k);
    format!("Y.l{l}.m{m}")
}

fn exr_err(path: &Path, e: exr::error::Error) -> ShFileError {
    match e {
        exr::error::Error::Io(source) if source.kind() != std::io::ErrorKind::UnexpectedEof => {
            ShFileError::Io {
                path: path.to_owned(),
                source,
            }
        }
        other => ShFileError::Exr {
            path: path.to_owned(),
            message: other.to_string(),
        },
    }
}
