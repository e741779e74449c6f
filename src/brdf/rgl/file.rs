//! Reading an RGL material from a tensor file ([`super::tensor`]): which fields are read,
//! the checks made on them, and the error naming the file and the field.
//!
//! # Fields read (all little-endian; shapes as the published readers require)
//! - `description` (`uint8`, rank 1): free text, kept as [`RglBrdf::description`];
//! - `jacobian` (`uint8`, shape `[1]`): nonzero when the `D / (4 sigma)` factor applies;
//! - `theta_i` (`float32`, `[n_theta]`), `phi_i` (`float32`, `[n_phi]`): the parameter
//!   axes of the viewer direction, radians, strictly increasing, `theta_i` in
//!   `[0, pi/2]`, `phi_i` in `[-pi, pi]`; `n_phi <= 2` means isotropic, otherwise the span
//!   of `phi_i` must be `2 pi / r` with `r` 1, 2 or 4;
//! - `ndf`, `sigma` (`float32`, rank 2, each side >= 2): finite, `ndf >= 0`, `sigma > 0`;
//! - `vndf` (`float32`, `[n_phi, n_theta, h, w]`, sides >= 2): finite, >= 0, each slice
//!   with a positive integral;
//! - `luminance` (`float32`, `[n_phi, n_theta, n, n]`): its shape is checked against the
//!   spectra (the published readers require it), its values are not read (they serve
//!   importance sampling, which brdfkit does not do);
//! - `spectra` (`float32`, `[n_phi, n_theta, n_wl, n, n]`) with `wavelengths`
//!   (`float32`, `[n_wl]`, nm, strictly increasing), or, without `wavelengths`, `rgb`
//!   (`float32`, `[n_phi, n_theta, 3, n, n]`): finite, magnitude at most
//!   [`crate::brdf::MAX_BRDF_VALUE`]; negative samples are clamped to 0.
//!
//! Other fields are ignored. Every size is checked against the file before anything sized
//! by it is allocated; a file is at most [`MAX_RGL_FILE_BYTES`].

use super::colour::srgb_weights;
use super::tensor::{self, Dtype, Field, TensorError};
use super::warp::Table;
use super::{RglBrdf, Tables};
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};

/// Largest RGL file read (the published spectral materials are tens of MB).
pub const MAX_RGL_FILE_BYTES: u64 = 1 << 30;

/// Errors reading an RGL file; each names the file and, for a malformed field, the field.
#[derive(Debug, thiserror::Error)]
pub enum RglError {
    /// Not a regular file, missing, or too large ([`crate::image_io::check_regular_file`]).
    #[error(transparent)]
    File(#[from] crate::error::FileError),
    #[error("{path}: {problem}")]
    Header { path: PathBuf, problem: String },
    #[error("{path}: field `{field}`: {problem}")]
    Field {
        path: PathBuf,
        field: String,
        problem: String,
    },
}

struct Ctx<'a> {
    path: &'a Path,
}

impl Ctx<'_> {
    fn field(&self, field: &str, problem: impl Into<String>) -> RglError {
        RglError::Field {
            path: self.path.to_owned(),
            field: field.to_string(),
            problem: problem.into(),
        }
    }
}

fn find<'a, 'b>(
    c: &Ctx,
    fields: &'b [Field<'a>],
    name: &str,
    dtype: Dtype,
    rank: usize,
) -> Result<&'b Field<'a>, RglError> {
    let f = fields
        .iter()
        .find(|f| f.name == name)
        .ok_or_else(|| c.field(name, "missing (an RGL material file has it)"))?;
    if f.dtype != dtype {
        return Err(c.field(
            name,
            format!("dtype {}, expected {}", f.dtype.name(), dtype.name()),
        ));
    }
    if f.shape.len() != rank {
        return Err(c.field(
            name,
            format!(
                "rank {} (shape {:?}), expected {rank}",
                f.shape.len(),
                f.shape
            ),
        ));
    }
    Ok(f)
}

/// The `float32` values of `f`, widened, each checked by `ok` (which names what it wants).
fn floats(c: &Ctx, f: &Field, ok: impl Fn(f64) -> bool, want: &str) -> Result<Vec<f64>, RglError> {
    let mut out = Vec::with_capacity(f.data.len() / 4);
    for (k, b) in f.data.chunks_exact(4).enumerate() {
        let v = f32::from_le_bytes(b.try_into().unwrap()) as f64;
        if !ok(v) {
            return Err(c.field(&f.name, format!("element {k} is {v}, expected {want}")));
        }
        out.push(v);
    }
    Ok(out)
}

fn axis(c: &Ctx, f: &Field, lo: f64, hi: f64) -> Result<Vec<f64>, RglError> {
    let eps = 1e-4;
    let v = floats(
        c,
        f,
        |v| v.is_finite() && v >= lo - eps && v <= hi + eps,
        &format!("a finite value in [{lo:.6}, {hi:.6}]"),
    )?;
    if v.is_empty() {
        return Err(c.field(&f.name, "is empty"));
    }
    if let Some(k) = (1..v.len()).find(|&k| v[k] <= v[k - 1]) {
        return Err(c.field(
            &f.name,
            format!(
                "not strictly increasing: element {k} is {} after {}",
                v[k],
                v[k - 1]
            ),
        ));
    }
    Ok(v)
}

fn dims(c: &Ctx, f: &Field, want: &[Option<u64>], what: &str) -> Result<(), RglError> {
    let bad = f
        .shape
        .iter()
        .zip(want)
        .any(|(&d, w)| w.map_or(d < 2, |w| d != w));
    if bad {
        return Err(c.field(&f.name, format!("shape {:?}, expected {what}", f.shape)));
    }
    Ok(())
}

impl RglBrdf {
    /// Parses the bytes of an RGL file; `path` labels errors and gives the name (its stem).
    /// Fails with [`RglError::Header`] for a file that is not a tensor file of version 1.0
    /// (or is truncated inside its header), and [`RglError::Field`] naming the field for
    /// anything else (module doc).
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, RglError> {
        let c = Ctx { path };
        let fields = tensor::parse(bytes).map_err(|TensorError { field, problem }| {
            if field == "header" {
                RglError::Header {
                    path: path.to_owned(),
                    problem,
                }
            } else {
                c.field(&field, problem)
            }
        })?;
        let description = find(&c, &fields, "description", Dtype::U8, 1)?;
        let description = String::from_utf8_lossy(description.data)
            .trim_end_matches('\0')
            .to_string();
        let jac = find(&c, &fields, "jacobian", Dtype::U8, 1)?;
        dims(&c, jac, &[Some(1)], "[1]")?;
        let jacobian = jac.data[0] != 0;
        let theta_f = find(&c, &fields, "theta_i", Dtype::F32, 1)?;
        let theta_i = axis(&c, theta_f, 0.0, FRAC_PI_2)?;
        let phi_f = find(&c, &fields, "phi_i", Dtype::F32, 1)?;
        let phi_i = axis(&c, phi_f, -PI, PI)?;
        let (np, nt) = (phi_i.len() as u64, theta_i.len() as u64);
        let isotropic = np <= 2;
        let reduction = if isotropic {
            1
        } else {
            let span = phi_i[phi_i.len() - 1] - phi_i[0];
            let r = (2.0 * PI / span).round();
            if !(r == 1.0 || r == 2.0 || r == 4.0) || ((2.0 * PI / r) - span).abs() > 1e-3 {
                return Err(c.field(
                    "phi_i",
                    format!(
                        "spans {span:.6} rad; an anisotropic file spans 2 pi, pi or pi/2 \
                         (symmetry 1, 2 or 4)"
                    ),
                ));
            }
            r as u32
        };
        let finite_nonneg = |v: f64| v.is_finite() && v >= 0.0;
        let ndf_f = find(&c, &fields, "ndf", Dtype::F32, 2)?;
        dims(&c, ndf_f, &[None, None], "[>= 2, >= 2]")?;
        let ndf = floats(&c, ndf_f, finite_nonneg, "a finite value >= 0")?;
        let sigma_f = find(&c, &fields, "sigma", Dtype::F32, 2)?;
        dims(&c, sigma_f, &[None, None], "[>= 2, >= 2]")?;
        let sigma = floats(
            &c,
            sigma_f,
            |v| v.is_finite() && v > 0.0,
            "a finite value > 0 (a projected area)",
        )?;
        let vndf_f = find(&c, &fields, "vndf", Dtype::F32, 4)?;
        let grid = format!("[{np} (phi_i), {nt} (theta_i), >= 2, >= 2]");
        dims(&c, vndf_f, &[Some(np), Some(nt), None, None], &grid)?;
        let vndf = floats(&c, vndf_f, finite_nonneg, "a finite value >= 0")?;
        let spectral = fields.iter().any(|f| f.name == "wavelengths");
        let (spec_name, wavelengths) = if spectral {
            let w = find(&c, &fields, "wavelengths", Dtype::F32, 1)?;
            ("spectra", Some(axis(&c, w, 1.0, 1e5)?))
        } else {
            ("rgb", None)
        };
        let spec_f = find(&c, &fields, spec_name, Dtype::F32, 5)?;
        let nl = wavelengths.as_ref().map_or(3, |w| w.len() as u64);
        let want = [Some(np), Some(nt), Some(nl), None, None];
        let what = format!("[{np} (phi_i), {nt} (theta_i), {nl}, n >= 2, n]");
        dims(&c, spec_f, &want, &what)?;
        let (sh, sw) = (spec_f.shape[3], spec_f.shape[4]);
        if sh != sw {
            return Err(c.field(spec_name, format!("shape {:?}: {what}", spec_f.shape)));
        }
        let lum = find(&c, &fields, "luminance", Dtype::F32, 4)?;
        let what = format!("[{np} (phi_i), {nt} (theta_i), {sh}, {sh}] (as the spectra)");
        dims(&c, lum, &[Some(np), Some(nt), Some(sh), Some(sh)], &what)?;
        let max = crate::brdf::MAX_BRDF_VALUE as f64;
        let spectra = floats(
            &c,
            spec_f,
            |v| v.is_finite() && v.abs() <= max,
            &format!("a finite value of magnitude at most {max:e}"),
        )?;
        // To three channels of linear sRGB (colour module doc), negative samples clamped.
        let (n_grid, nl) = ((sh * sw) as usize, nl as usize);
        let cells = (np * nt) as usize;
        let rgb: Vec<f64> = match &wavelengths {
            None => spectra.iter().map(|&v| v.max(0.0)).collect(),
            Some(w) => {
                let weights = srgb_weights(w);
                let mut out = vec![0.0; cells * 3 * n_grid];
                for cell in 0..cells {
                    for (k, wk) in weights.iter().enumerate() {
                        let src = &spectra[(cell * nl + k) * n_grid..][..n_grid];
                        for ch in 0..3 {
                            let dst = &mut out[(cell * 3 + ch) * n_grid..][..n_grid];
                            for (d, &s) in dst.iter_mut().zip(src) {
                                *d += wk[ch] * s.max(0.0);
                            }
                        }
                    }
                }
                out
            }
        };
        let axes = [phi_i, theta_i];
        let (vh, vw) = (vndf_f.shape[2] as usize, vndf_f.shape[3] as usize);
        let bad_slice = |s: usize| {
            c.field(
                "vndf",
                format!(
                    "slice {s} (phi_i index {}, theta_i index {}) integrates to zero",
                    s / nt as usize,
                    s % nt as usize
                ),
            )
        };
        let (ny, nx) = (ndf_f.shape[0] as usize, ndf_f.shape[1] as usize);
        let (sy, sx) = (sigma_f.shape[0] as usize, sigma_f.shape[1] as usize);
        let n = sh as usize;
        let t64 = Tables {
            ndf: Table::interpolant(&ndf, nx, ny, &[], 1),
            sigma: Table::interpolant(&sigma, sx, sy, &[], 1),
            vndf: Table::warp(&vndf, vw, vh, &axes).map_err(bad_slice)?,
            rgb: Table::interpolant(&rgb, n, n, &axes, 3),
        };
        let t32 = Tables {
            ndf: Table::interpolant(&ndf, nx, ny, &[], 1),
            sigma: Table::interpolant(&sigma, sx, sy, &[], 1),
            vndf: Table::warp(&vndf, vw, vh, &axes).map_err(bad_slice)?,
            rgb: Table::interpolant(&rgb, n, n, &axes, 3),
        };
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "rgl".into());
        Ok(RglBrdf {
            name,
            description,
            isotropic,
            jacobian,
            reduction,
            wavelengths: wavelengths.map(|w| w.iter().map(|&v| v as f32).collect()),
            t32,
            t64,
        })
    }

    /// Reads an RGL `.bsdf` file (at most [`MAX_RGL_FILE_BYTES`]); errors name the file.
    pub fn read(path: &Path) -> Result<Self, RglError> {
        let bytes =
            crate::image_io::read_regular_file(path, MAX_RGL_FILE_BYTES, "RGL material file")?;
        Self::from_bytes(&bytes, path)
    }
}
