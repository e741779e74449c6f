//! MERL measured BRDFs (Matusik et al., "A data-driven reflectance model", SIGGRAPH 2003),
//! in the `.binary` format of the MERL BRDF database and its reference reader `BRDFRead.cpp`.
//!
//! Design rule: this module reproduces the reference reader's indexing exactly (bins,
//! scales, reciprocity fold), so that a table read here evaluates like the original code;
//! and its writer tabulates any [`Brdf`] with the same indexing, so tests can make MERL files
//! from analytic models.
//!
//! # Format
//! Three little-endian `i32` dimensions `(90, 90, 180)` = (theta_h, theta_d, phi_d) bins,
//! then three planar blocks (R, G, B) of `90*90*180` little-endian `f64`. Sample index
//! `theta_h_idx * 90 * 180 + theta_d_idx * 180 + phi_d_idx`. Stored values are multiplied by
//! the per-channel scales `1/1500`, `1.15/1500`, `1.66/1500` on reading; negative samples
//! mean "below the horizon" and evaluate to zero. The file is exactly
//! `12 + 8 * 3 * 90 * 90 * 180 = 34_992_012` bytes.
//!
//! # Coordinates (Rusinkiewicz, "A new change of variables for efficient BRDF
//! representation", 1998)
//! `h = normalize(wi + wo)`, `theta_h = acos(h.z)`, `phi_h = atan2(h.y, h.x)`; the
//! difference vector is `wi` rotated by `-phi_h` about z and then `-theta_h` about y:
//! `theta_d = acos(d.z)`, `phi_d = atan2(d.y, d.x)`, folded into [0, pi) by adding pi when
//! negative (reciprocity). Bins: `theta_h_idx = floor(sqrt(theta_h / (pi/2)) * 90)`,
//! `theta_d_idx = floor(theta_d / (pi/2) * 90)`, `phi_d_idx = floor(phi_d / pi * 180)`,
//! each clamped to its range (no interpolation, as in the reference reader). The local
//! frame is that of [`crate::conventions`]; MERL data are isotropic, so `phi_h` is unused.
//! Degenerate cases are guarded so no NaN can arise: `h` near the normal
//! (`theta_h ~ 0`, `phi_h` undefined) and `d` near `h` (`theta_d ~ 0`, `phi_d` undefined)
//! both fall in bins 0 through the clamped `acos`/`atan2`, and `wi = -wo` gives zero.

use super::Brdf;
use glam::{DVec3, Vec3};
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};

/// Bins along theta_h, theta_d, phi_d.
pub const MERL_DIMS: [usize; 3] = [90, 90, 180];
/// Samples per colour channel.
pub const MERL_SAMPLES: usize = 90 * 90 * 180;
/// Exact file size in bytes.
pub const MERL_FILE_SIZE: usize = 12 + 8 * 3 * MERL_SAMPLES;
/// Per-channel scales applied to stored values (R, G, B).
pub const MERL_SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];

/// Errors reading or writing MERL files; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum MerlError {
    /// Not a regular file ([`crate::image_io::check_regular_file`]).
    #[error(transparent)]
    File(#[from] crate::error::FileError),
    #[error("{path}: I/O error: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: file is {got} bytes, shorter than the 12-byte MERL header")]
    NoHeader { path: PathBuf, got: usize },
    #[error("{path}: dimensions {dims:?}, expected [90, 90, 180]")]
    Dims { path: PathBuf, dims: [i32; 3] },
    #[error(
        "{path}: file is {got} bytes, expected {expected} (12-byte header + 3 x 90*90*180 f64)"
    )]
    Size {
        path: PathBuf,
        got: usize,
        expected: usize,
    },
    #[error("{path}: channel {channel} sample {index} is {value}: samples must be finite and scale to at most {max} 1/sr", max = crate::brdf::MAX_BRDF_VALUE)]
    NonFinite {
        path: PathBuf,
        channel: char,
        index: usize,
        value: f64,
    },
}

/// A tabulated MERL BRDF (stored values as in the file, unscaled, planar R, G, B).
#[derive(Clone, Debug)]
pub struct MerlBrdf {
    data: Vec<f64>,
    name: String,
}

/// `(theta_h, theta_d, phi_d)` of a pair of local unit directions (module doc); `phi_d` in
/// [0, pi). Returns `None` if `wi + wo` is (nearly) zero.
pub fn half_diff_angles(wi: DVec3, wo: DVec3) -> Option<(f64, f64, f64)> {
    let h = (wi + wo).try_normalize()?;
    let theta_h = h.z.clamp(-1.0, 1.0).acos();
    let phi_h = h.y.atan2(h.x);
    // rotate wi by -phi_h about z, then by -theta_h about y
    let (s, c) = (-phi_h).sin_cos();
    let t = DVec3::new(c * wi.x - s * wi.y, s * wi.x + c * wi.y, wi.z);
    let (s, c) = (-theta_h).sin_cos();
    let d = DVec3::new(c * t.x + s * t.z, t.y, -s * t.x + c * t.z);
    let theta_d = d.z.clamp(-1.0, 1.0).acos();
    let mut phi_d = d.y.atan2(d.x);
    if phi_d < 0.0 {
        phi_d += PI;
    }
    if phi_d >= PI {
        phi_d -= PI;
    }
    Some((theta_h, theta_d, phi_d))
}

/// Flat sample index of `(theta_h, theta_d, phi_d)` with the reference reader's bins.
pub fn merl_index(theta_h: f64, theta_d: f64, phi_d: f64) -> usize {
    let th = if theta_h <= 0.0 {
        0
    } else {
        ((theta_h / FRAC_PI_2).sqrt() * 90.0) as usize
    }
    .min(89);
    let td = ((theta_d.max(0.0) / FRAC_PI_2 * 90.0) as usize).min(89);
    let pd = ((phi_d.max(0.0) / PI * 180.0) as usize).min(179);
    th * 90 * 180 + td * 180 + pd
}

/// Centre angles `(theta_h, theta_d, phi_d)` of bin `(ih, id, ip)` (theta_h centre in the
/// square-root parameterization: `((ih + 1/2)/90)^2 pi/2`).
pub fn merl_bin_center(ih: usize, id: usize, ip: usize) -> (f64, f64, f64) {
    let u = (ih as f64 + 0.5) / 90.0;
    (
        u * u * FRAC_PI_2,
        (id as f64 + 0.5) / 90.0 * FRAC_PI_2,
        (ip as f64 + 0.5) / 180.0 * PI,
    )
}

/// Local `(wi, wo)` of half/difference angles with `phi_h = 0` (inverse of
/// [`half_diff_angles`]).
pub fn directions_from_half_diff(theta_h: f64, theta_d: f64, phi_d: f64) -> (DVec3, DVec3) {
    let d = DVec3::new(
        theta_d.sin() * phi_d.cos(),
        theta_d.sin() * phi_d.sin(),
        theta_d.cos(),
    );
    // rotate d by +theta_h about y
    let (s, c) = theta_h.sin_cos();
    let wi = DVec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
    let h = DVec3::new(s, 0.0, c);
    let wo = 2.0 * wi.dot(h) * h - wi;
    (wi, wo)
}

impl MerlBrdf {
    /// Parses the bytes of a `.binary` file; `path` only labels errors.
    ///
    /// Fails with [`MerlError::NoHeader`] (under 12 bytes), [`MerlError::Dims`] (header
    /// other than `(90, 90, 180)`), [`MerlError::Size`] (length other than
    /// [`MERL_FILE_SIZE`]) or [`MerlError::NonFinite`] (a NaN or infinite sample: the
    /// format's "no data" marker is a negative value, never NaN). Allocates only after the
    /// length is checked, and never more than the input's size.
    pub fn from_bytes(bytes: &[u8], path: &Path, name: &str) -> Result<Self, MerlError> {
        if bytes.len() < 12 {
            return Err(MerlError::NoHeader {
                path: path.to_owned(),
                got: bytes.len(),
            });
        }
        let dim = |k: usize| i32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().unwrap());
        let dims = [dim(0), dim(1), dim(2)];
        if dims != [90, 90, 180] {
            return Err(MerlError::Dims {
                path: path.to_owned(),
                dims,
            });
        }
        if bytes.len() != MERL_FILE_SIZE {
            return Err(MerlError::Size {
                path: path.to_owned(),
                got: bytes.len(),
                expected: MERL_FILE_SIZE,
            });
        }
        let data: Vec<f64> = bytes[12..]
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        // Scaled samples over MAX_BRDF_VALUE are refused as if infinite (see that constant).
        let max = crate::brdf::MAX_BRDF_VALUE as f64;
        let too_big = |k: usize, v: f64| {
            let s = (v * MERL_SCALE[k / MERL_SAMPLES]).abs();
            s.is_nan() || s > max
        };
        if let Some(k) = (0..data.len()).find(|&k| too_big(k, data[k])) {
            return Err(MerlError::NonFinite {
                path: path.to_owned(),
                channel: ['R', 'G', 'B'][k / MERL_SAMPLES],
                index: k % MERL_SAMPLES,
                value: data[k],
            });
        }
        Ok(MerlBrdf {
            data,
            name: name.to_owned(),
        })
    }

    /// Reads a `.binary` file (errors name the file and say what size was expected).
    ///
    /// Fails as [`MerlBrdf::from_bytes`], with [`MerlError::File`] for a directory, device or
    /// FIFO, or with [`MerlError::Io`]. A file whose length
    /// is not [`MERL_FILE_SIZE`] is not read beyond its 12-byte header.
    pub fn read(path: &Path) -> Result<Self, MerlError> {
        use std::io::Read;
        let io = |source| MerlError::Io {
            path: path.to_owned(),
            source,
        };
        // A device or FIFO is refused before it is opened (opening a FIFO blocks).
        crate::image_io::check_regular_file(path, u64::MAX, "MERL file")?;
        let mut file = std::fs::File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        let mut bytes = Vec::new();
        // Read at most one byte more than a MERL file has, so a wrong length is reported
        // without reading (or allocating for) a huge file.
        (&mut file)
            .take(if len == MERL_FILE_SIZE as u64 {
                MERL_FILE_SIZE as u64 + 1
            } else {
                12
            })
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if bytes.len() == 12 && len != MERL_FILE_SIZE as u64 {
            // Header complete: report wrong dimensions first, else the length.
            let dims = |k: usize| i32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().unwrap());
            let dims = [dims(0), dims(1), dims(2)];
            if dims != [90, 90, 180] {
                return Err(MerlError::Dims {
                    path: path.to_owned(),
                    dims,
                });
            }
            return Err(MerlError::Size {
                path: path.to_owned(),
                got: usize::try_from(len).unwrap_or(usize::MAX),
                expected: MERL_FILE_SIZE,
            });
        }
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "merl".into());
        Self::from_bytes(&bytes, path, &name)
    }

    /// Tabulates `src` at the bin centres (with `phi_h = 0`: MERL assumes isotropy, so an
    /// anisotropic source is sampled along its local x-z plane of half vectors). `f_r` is
    /// stored (a cosine-including source is divided by `wi.z`); bins whose centre lies
    /// below the horizon store -1.
    pub fn tabulate(src: &dyn Brdf) -> Self {
        let mut data = vec![0.0f64; 3 * MERL_SAMPLES];
        for ih in 0..90 {
            for id in 0..90 {
                for ip in 0..180 {
                    let (th, td, pd) = merl_bin_center(ih, id, ip);
                    let (wi, wo) = directions_from_half_diff(th, td, pd);
                    let k = ih * 90 * 180 + id * 180 + ip;
                    if wi.z <= 0.0 || wo.z <= 0.0 {
                        for c in 0..3 {
                            data[c * MERL_SAMPLES + k] = -1.0;
                        }
                        continue;
                    }
                    let mut f = src.eval(wi.as_vec3(), wo.as_vec3()).as_dvec3();
                    if src.includes_cosine() {
                        f /= wi.z;
                    }
                    for c in 0..3 {
                        data[c * MERL_SAMPLES + k] = f[c] / MERL_SCALE[c];
                    }
                }
            }
        }
        MerlBrdf {
            data,
            name: format!("merl({})", src.name()),
        }
    }

    /// The `.binary` bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(MERL_FILE_SIZE);
        for d in MERL_DIMS {
            out.extend_from_slice(&(d as i32).to_le_bytes());
        }
        for v in &self.data {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// Writes a `.binary` file via a unique temporary file in the same directory, synced,
    /// and a rename ([`crate::image_io::replace_via_temp`]).
    pub fn write(&self, path: &Path) -> Result<(), MerlError> {
        let io = |source| MerlError::Io {
            path: path.to_owned(),
            source,
        };
        crate::image_io::replace_via_temp(
            path,
            |tmp| std::fs::write(tmp, self.to_bytes()).map_err(io),
            io,
        )
    }

    /// Scaled RGB sample at flat index `k` (negative stored values give zero).
    pub fn sample(&self, k: usize) -> DVec3 {
        let mut v = DVec3::ZERO;
        for c in 0..3 {
            v[c] = (self.data[c * MERL_SAMPLES + k] * MERL_SCALE[c]).max(0.0);
        }
        v
    }

    /// f64 evaluation (nearest bin, as the reference reader).
    pub fn eval_f64(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return DVec3::ZERO;
        }
        match half_diff_angles(wi.normalize(), wo.normalize()) {
            Some((th, td, pd)) => self.sample(merl_index(th, td, pd)),
            None => DVec3::ZERO,
        }
    }
}

impl Brdf for MerlBrdf {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.eval_f64(wi.as_dvec3(), wo.as_dvec3()).as_vec3()
    }

    fn name(&self) -> &str {
        &self.name
    }

    /// MERL data are isotropic (module doc).
    fn is_isotropic(&self) -> bool {
        true
    }

    /// [`MerlBrdf::eval_f64`]: the angles and bins in f64 from the f64 directions (the
    /// table holds f64 samples). Not expected to agree with [`Brdf::eval`] to f32 rounding
    /// everywhere: the reference reader's lookup is nearest-bin, so directions within f32
    /// rounding of a bin edge may fall into neighbouring bins in f32 and f64.
    fn eval_f64(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        MerlBrdf::eval_f64(self, wi, wo)
    }
}

#[cfg(test)]
mod tests;
