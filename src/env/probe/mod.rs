//! Light probes: equirectangular HDR images loaded into the one convention of
//! [`crate::conventions`] (thesis 3.2.1).
//!
//! Design rule: a [`Probe`] is always clean. Every texel is finite and every channel is
//! `>= 0` once a probe exists; the loader decides (and reports) what happened to the
//! dirty texels of real files, so no sampler ever sees a negative weight or a NaN.
//!
//! * Negative channels (left by lossy DWAB compression around bright texels) keep the
//!   probe's local signed integral: their mass is moved into nearby positive texels
//!   (`clean.rs`), the texels counted in [`LoadReport::negative_texels`] and the power moved
//!   in [`LoadReport::negative_power_moved`], so the caller can warn
//!   ([`LoadReport::negative_warning`]). This is the one loader: the converged reference,
//!   every light set and every transfer table see the same cleaned probe.
//! * Non-finite channels (NaN, +-Inf) are an error naming the file and the count, unless
//!   [`LoadOptions::zero_non_finite`] is set, in which case the whole texel becomes black
//!   and is counted in [`LoadReport::non_finite_zeroed`].
//! * Any aspect ratio is accepted. A 0-sized image is an error. A 1-texel-high image is
//!   accepted: its single row spans the whole polar range [0, pi], so each texel is a lune
//!   of solid angle `4 pi / width` whose value sits at its centre on the equator (y = 0).
//! * Sizes are bounded before decoding ([`LoadOptions::max_texels`], default 2^26 texels,
//!   768 MiB of f32 RGB); larger images are rejected, never allocated.

use crate::conventions::{
    probe_direction, probe_texel, probe_texel_solid_angle, probe_uv, rotate_about_up,
    texel_center_f64,
};
use glam::DVec3;
use std::path::{Path, PathBuf};

/// Largest probe file read (bytes), to decode or to hash for a cache key.
pub const MAX_PROBE_FILE_BYTES: u64 = 1 << 30;

/// Why loading or building a probe failed. Every message names the file (or the name
/// given to [`Probe::from_texels`]) and the problem.
#[derive(Debug, thiserror::Error)]
pub enum ProbeError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read light probe: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Not a regular file, or over [`MAX_PROBE_FILE_BYTES`].
    #[error(transparent)]
    File(#[from] crate::error::FileError),
    /// The extension is neither `.exr` nor `.hdr`.
    #[error("{path}: unsupported light probe format (expected .exr or .hdr)")]
    UnsupportedFormat { path: PathBuf },
    /// The decoder rejected the file (corrupt data, missing R, G or B channel, ...).
    #[error("{path}: cannot decode light probe: {message}")]
    Decode { path: PathBuf, message: String },
    /// Width or height is zero.
    #[error("{path}: light probe is empty ({width}x{height} texels)")]
    Empty {
        path: PathBuf,
        width: usize,
        height: usize,
    },
    /// The image is larger than [`LoadOptions::max_texels`].
    #[error("{path}: light probe is {width}x{height} texels, more than the limit of {max_texels}")]
    TooLarge {
        path: PathBuf,
        width: usize,
        height: usize,
        max_texels: usize,
    },
    /// Texels with a NaN or infinite channel, and the option to zero them was off.
    #[error("{path}: light probe has {count} non-finite texel(s) (NaN or Inf); set zero_non_finite to load it with those texels black")]
    NonFinite { path: PathBuf, count: usize },
    /// `texels.len() != width * height` in [`Probe::from_texels`].
    #[error("{path}: light probe data has {got} texels, expected {expected} ({width}x{height})")]
    SizeMismatch {
        path: PathBuf,
        width: usize,
        height: usize,
        expected: usize,
        got: usize,
    },
}

/// Options for [`Probe::load`] and [`Probe::from_texels`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// Rotation of the environment about +y in radians, right-handed (see
    /// [`crate::conventions::rotate_about_up`]). Applied to every direction the probe
    /// reports and undone by every direction-to-texel lookup.
    pub rotation: f64,
    /// Zero texels with a NaN or infinite channel instead of failing.
    pub zero_non_finite: bool,
    /// Largest accepted `width * height`; bigger files are rejected before decoding.
    pub max_texels: usize,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            rotation: 0.0,
            zero_non_finite: false,
            max_texels: 1 << 26,
        }
    }
}

/// What the loader changed to make the probe clean.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LoadReport {
    /// Texels with at least one negative channel (those channels were set to 0 and their
    /// mass moved into nearby positive texels, `clean.rs`).
    pub negative_texels: usize,
    /// Per RGB channel, the power of the negative texels moved into nearby positive ones:
    /// `sum |v| x solid angle` over negative channels (W/m^2 for a probe in W/(m^2 sr)).
    #[serde(default)]
    pub negative_power_moved: [f64; 3],
    /// Per RGB channel, negative power that could not be placed because the whole probe's
    /// signed integral of that channel is negative (those channels end all black).
    #[serde(default)]
    pub negative_power_unplaced: [f64; 3],
    /// Per RGB channel, the probe's signed integral `sum v x solid angle` before cleaning
    /// (W/m^2), which cleaning keeps.
    #[serde(default)]
    pub signed_power: [f64; 3],
    /// Texels with a non-finite channel that were set to black (only with
    /// [`LoadOptions::zero_non_finite`]).
    pub non_finite_zeroed: usize,
    /// The probe's size in texels, `(width, height)`; an equirectangular probe is 2:1.
    pub size: (usize, usize),
}

impl LoadReport {
    /// The power the cleaning moved and the probe's signed power, both luminance-weighted
    /// with [`crate::env::LUMINANCE_WEIGHTS`] (W/m^2 for a probe in W/(m^2 sr)):
    /// `(moved, signed)`.
    pub fn luminance_power_moved(&self) -> (f64, f64) {
        (
            luminance_of(self.negative_power_moved),
            luminance_of(self.signed_power),
        )
    }

    /// The one-line warning for a probe whose negative texels were cleaned, `None` when
    /// there were none: the texel count and the power moved, absolute (luminance-weighted,
    /// [`LoadReport::luminance_power_moved`]) and as a percentage of the probe's signed
    /// luminance power. `probe` names the file as the user gave it (callers pass the path
    /// as typed, not a resolved or canonical one).
    pub fn negative_warning(&self, probe: &str) -> Option<String> {
        if self.negative_texels == 0 {
            return None;
        }
        let (moved, total) = self.luminance_power_moved();
        let mut msg = format!(
            "{probe}: {} texels with negative values (lossy compression): their power, {:.4e} W/m^2 \
             ({:.3}% of the probe's {:.4e} W/m^2, luminance), was moved into nearby positive \
             texels, keeping the signed integral",
            self.negative_texels,
            moved,
            100.0 * moved / total.abs().max(f64::MIN_POSITIVE),
            total
        );
        let unplaced = luminance_of(self.negative_power_unplaced);
        if unplaced > 0.0 {
            msg += &format!(
                "; {unplaced:.4e} W/m^2 could not be placed (a channel's signed integral is negative) and was dropped"
            );
        }
        Some(msg)
    }
}

/// Luminance of per-channel powers ([`crate::env::LUMINANCE_WEIGHTS`], no clamping: a
/// signed power stays signed).
fn luminance_of(p: [f64; 3]) -> f64 {
    (0..3)
        .map(|c| crate::env::LUMINANCE_WEIGHTS[c] * p[c])
        .sum()
}

/// An equirectangular light probe: linear RGB radiance (units of the file, typically
/// W/(m^2 sr)), row-major, row 0 the +y pole row, texel `(row, col)` centred at
/// `u = (col + 1/2)/width`, `v = (row + 1/2)/height` (see [`crate::conventions`]).
/// Every channel is finite and `>= 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct Probe {
    width: usize,
    height: usize,
    texels: Vec<[f32; 3]>,
    rotation: f64,
    name: String,
}

impl Probe {
    /// Loads an OpenEXR (`.exr`, first layer with R, G and B channels, any sample type,
    /// alpha ignored) or Radiance (`.hdr`) file. The extension picks the decoder.
    ///
    /// Fails with [`ProbeError`]: unreadable file, not a regular file (a device or FIFO
    /// is refused unopened) or over [`MAX_PROBE_FILE_BYTES`], unknown extension, decoder error (also a
    /// header declaring more texels than the file's length can hold, see
    /// [`HDR_TEXELS_PER_BYTE`] and [`crate::image_io::check_exr_declared_size`]), empty or oversized image, non-finite texels (unless zeroed
    /// by option).
    pub fn load(path: &Path, opts: &LoadOptions) -> Result<(Probe, LoadReport), ProbeError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        if matches!(ext.as_deref(), Some("exr" | "hdr")) {
            crate::image_io::check_regular_file(path, MAX_PROBE_FILE_BYTES, "light probe")?;
        }
        let (w, h, texels) = match ext.as_deref() {
            Some("exr") => read_exr(path, opts)?,
            Some("hdr") => read_hdr(path, opts)?,
            _ => {
                return Err(ProbeError::UnsupportedFormat {
                    path: path.to_path_buf(),
                })
            }
        };
        Probe::from_texels(&path.display().to_string(), w, h, texels, opts)
    }

    /// Builds a probe from raw linear RGB texels (row-major, row 0 at +y), applying the
    /// same cleaning as [`Probe::load`]. `name` is used in error messages and as the
    /// probe's name (for light-set headers).
    ///
    /// Fails on an empty or oversized image, a length mismatch, or non-finite texels
    /// (unless `opts.zero_non_finite`).
    pub fn from_texels(
        name: &str,
        width: usize,
        height: usize,
        mut texels: Vec<[f32; 3]>,
        opts: &LoadOptions,
    ) -> Result<(Probe, LoadReport), ProbeError> {
        let path = PathBuf::from(name);
        check_size(&path, width, height, opts)?;
        if texels.len() != width * height {
            return Err(ProbeError::SizeMismatch {
                path,
                width,
                height,
                expected: width * height,
                got: texels.len(),
            });
        }
        let mut report = LoadReport {
            size: (width, height),
            ..LoadReport::default()
        };
        let mut non_finite = 0usize;
        for t in texels.iter_mut() {
            if t.iter().any(|c| !c.is_finite()) {
                non_finite += 1;
                *t = [0.0; 3];
                continue;
            }
            // -0.0 is not negative mass; normalise it so hashes see one zero.
            for c in t.iter_mut() {
                if *c == 0.0 {
                    *c = 0.0;
                }
            }
        }
        if non_finite > 0 {
            if !opts.zero_non_finite {
                return Err(ProbeError::NonFinite {
                    path,
                    count: non_finite,
                });
            }
            report.non_finite_zeroed = non_finite;
        }
        clean::move_negative_mass(&mut texels, width, height, &mut report);
        Ok((
            Probe {
                width,
                height,
                texels,
                rotation: opts.rotation,
                name: name.to_string(),
            },
            report,
        ))
    }

    /// Width in texels (azimuth samples).
    pub fn width(&self) -> usize {
        self.width
    }
    /// Height in texels (polar samples).
    pub fn height(&self) -> usize {
        self.height
    }
    /// The clean texels, row-major.
    pub fn texels(&self) -> &[[f32; 3]] {
        &self.texels
    }
    /// Radiance of texel `(row, col)`. Panics if out of range.
    pub fn texel(&self, row: usize, col: usize) -> [f32; 3] {
        self.texels[row * self.width + col]
    }
    /// Rotation about +y in radians.
    pub fn rotation(&self) -> f64 {
        self.rotation
    }
    /// Name given at load (the file path) or to [`Probe::from_texels`].
    pub fn name(&self) -> &str {
        &self.name
    }
    /// A copy with another rotation about +y (radians).
    pub fn with_rotation(mut self, rotation: f64) -> Probe {
        self.rotation = rotation;
        self
    }

    /// Unit world direction of the centre of texel `(row, col)`, rotation applied.
    pub fn direction(&self, row: usize, col: usize) -> DVec3 {
        let d = probe_direction(
            texel_center_f64(col, self.width),
            texel_center_f64(row, self.height),
        );
        rotate_about_up(d, self.rotation)
    }

    /// Image coordinates `(u, v)` of a world direction, rotation undone.
    pub fn uv_of(&self, d: DVec3) -> (f64, f64) {
        probe_uv(rotate_about_up(d, -self.rotation))
    }

    /// The texel `(row, col)` a world direction falls in (inverse of [`Probe::direction`]).
    pub fn texel_of(&self, d: DVec3) -> (usize, usize) {
        let (u, v) = self.uv_of(d);
        probe_texel(u, v, self.width, self.height)
    }

    /// Exact solid angle in sr of a texel in row `row`.
    pub fn solid_angle(&self, row: usize) -> f64 {
        probe_texel_solid_angle(row, self.width, self.height)
    }

    /// The probe's integral over the sphere, `sum RGB x solid angle` in f64: the total
    /// "power" every light set must carry (W/m^2 for radiance in W/(m^2 sr)).
    pub fn total_power(&self) -> DVec3 {
        let mut total = DVec3::ZERO;
        for row in 0..self.height {
            let mut r = DVec3::ZERO;
            for t in &self.texels[row * self.width..(row + 1) * self.width] {
                r += DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64);
            }
            total += r * self.solid_angle(row);
        }
        total
    }
}

/// [`Probe::load`] with the crate's [`crate::error::Error`] (for tools and the methods'
/// preparations).
pub fn load_probe(path: &Path, opts: &LoadOptions) -> crate::error::Result<(Probe, LoadReport)> {
    Probe::load(path, opts).map_err(|e| crate::error::Error::Message(e.to_string()))
}

mod clean;
mod read;
pub mod resample;
mod tables;
use read::{check_size, read_exr, read_hdr};
pub use read::{HDR_TEXELS_PER_BYTE, HDR_TEXEL_SLACK};
pub use tables::ProbeTables;

#[cfg(test)]
mod tests;
