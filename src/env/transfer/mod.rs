//! Transfer tables: the environment seen by a material, tabulated over normals.
//!
//! For an SH data set (thesis Def. 12: `f(wi, wo) = sum_k c_k(wo) Y_k(wi)` in the local
//! shading frame of [`crate::conventions`]) under a distant environment of radiance `L`,
//! the outgoing radiance is
//! `L_o(n, wo) = sum_k c_k(wo) T_k(n)` with
//! `T_k(n) = integral_{wi.n > 0} L(wi) Y_k(local_n(wi)) [cos polar_i] dwi`,
//! the cosine present only when the data set excludes it. `T` depends on the normal only,
//! so it is tabulated once per probe, rotation and basis, and each pixel interpolates `T` at
//! its normal and dots it with its view coefficients `c(wo)`: the per-pixel cost no longer
//! grows with the number of lights. A Lambert surface (`f = albedo / pi`) is the one-term
//! case: `T(n)` is the irradiance `E(n) = integral_{wi.n > 0} L(wi) cos polar_i dwi`
//! ([`TransferBasis::Irradiance`]).
//!
//! The integral is the exact sum over every probe texel with its exact solid angle
//! ([`crate::conventions::probe_texel_solid_angle`]) and the hemisphere clip at the texel
//! centre (for a probe wider than [`build::RESIDUAL_WIDTH`], over its residual downsampled
//! with power summed exactly, [`build`]'s "Residual"), as the converged reference sums the
//! full probe
//! ([`crate::render::RenderOptions::converged_reference`] on `sampler = "full"`). The `K`
//! brightest texels (luminance x solid angle) may be left out of the table and summed
//! exactly per pixel as directional lights through the ordinary kernels: each light that
//! crosses a normal's horizon makes `T` jump, which no grid interpolates, and under a probe
//! with a few dominant sources those jumps are most of the table's error (studio:
//! [`crate::env::schema::DEFAULT_EXACT_LIGHTS`] says by how much).
//!
//! # Grid of normals
//! Latitude-longitude in the probe's own convention ([`crate::conventions`], "Light
//! probes"): node `(i, j)` is the normal of polar angle `pi j / (nv - 1)` from +y (both
//! poles are rows) and probe azimuth `2 pi i / nu`, before the probe rotation. `T` is stored
//! in the shading frame of each node's normal, which is a smooth function of the grid's
//! angles (its tangent is `(cos p sin a, sin p, -cos p cos a)` at polar `p`, azimuth `a`,
//! also on the pole rows, where it is the limit along the node's meridian). So near `+-y`
//! the table interpolates a smooth function; a pixel's frame is
//! [`crate::conventions::ShadingFrame::from_normal`], which equals the grid's frame at the
//! pixel's own angles.
//!
//! # Layout
//! - [`table`]: [`TransferTable`] (values, grid, bilinear lookup in normal);
//! - [`build`]: building a table from a probe ([`build::build_table`]) and choosing the
//!   brightest texels ([`build::brightest_texels`]); `weights.rs`, the per-row SH weights
//!   it sums, four columns at a time; `correlate.rs`, the FFT correlation of one table row
//!   over the probe rows, its multiply-adds on the f64 lanes of [`crate::lanes`];
//! - [`cache`]: the disk cache of tables beside the light-set cache (`brdfkit render` and
//!   `brdfkit view` only; `brdfkit cache` lists and cleans it);
//! - [`file`](mod@file): the table as `brdfkit export` writes it for a GPU build (a JSON header and
//!   the raw values) and a scene's `[transfer] table` reads it back.

pub mod build;
pub mod cache;
mod correlate;
mod fault;
pub mod file;
pub mod table;
mod weights;

pub use build::{brightest_texels, build_table};
pub use fault::BuildFault;
pub use table::TransferTable;

/// Largest difference allowed between the fast path's transfer term
/// (`crate::shade`'s lane lookup in the tile loop, polynomial angles, fused eight-lane
/// sums, the data set truncated to its effective bands) and the scalar oracle's
/// ([`TransferTable::radiance_with`] in a pass of its own, `std` angles, every band), per
/// pixel and channel, relative to the pixel (or to 1% of the image's peak where SH terms
/// cancel), as [`crate::kernel::SH_KERNEL_TOLERANCE`] holds the lights' kernels
/// (tests/integration/transfer_scene.rs).
pub const FAST_PATH_TOLERANCE: f32 = 1e-3;

/// What a transfer table projects the environment onto.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransferBasis {
    /// The real SH of [`crate::sh::basis`] with `bands` bands, times `cos(polar_i)` when
    /// `cosine` (for data sets that exclude the cosine, [`crate::brdf::Brdf::includes_cosine`]
    /// false): `T_k(n)` in W/(m^2 sr) x sr = W/m^2 per unit of `Y_k`.
    Sh { bands: usize, cosine: bool },
    /// One term: the irradiance `E(n)` (W/m^2 for a probe in W/(m^2 sr)), for Lambert.
    Irradiance,
}

impl TransferBasis {
    /// The basis a table needs to shade `material`: its SH data set's bands (the cosine
    /// when the data set excludes it) or, for Lambert, the irradiance; `None` for other
    /// materials, which a transfer table cannot shade.
    pub fn for_material(material: &crate::material::Material) -> Option<TransferBasis> {
        use crate::material::TransferModel;
        Some(match material.transfer_model()? {
            TransferModel::Sh(ds) => TransferBasis::Sh {
                bands: ds.bands(),
                cosine: !ds.cosine_included(),
            },
            TransferModel::Lambert(_) => TransferBasis::Irradiance,
        })
    }

    /// Number of terms per colour.
    pub fn terms(self) -> usize {
        match self {
            TransferBasis::Sh { bands, .. } => bands * bands,
            TransferBasis::Irradiance => 1,
        }
    }
}

use crate::env::schema::EnvSpec;
use crate::env::{LightSet, LoadOptions, LoadReport, Probe};
use crate::error::Result;
use crate::progress::Progress;
use std::path::{Path, PathBuf};

/// What [`prepare_table`] made for a scene's `[env]` of a tabulated method: a transfer
/// table ([`PreparedTransfer`]) or a reflection table
/// ([`crate::env::reflection::PreparedReflection`]).
#[derive(Clone, Debug)]
pub struct PreparedTable<T> {
    /// The table of every texel but the brightest `exact_lights`.
    pub table: T,
    /// The brightest `exact_lights` texels as directional lights ([`build::texel_lights`]).
    pub lights: LightSet,
    /// The probe loader's report.
    pub report: LoadReport,
    /// True when the table came from the disk cache.
    pub cache_hit: bool,
    /// Why an existing cache entry was not used (damaged, another version, ...).
    pub cache_rejected: Option<String>,
    /// The cache file used (read or written), if any.
    pub cache_file: Option<PathBuf>,
}

/// What [`prepare_transfer`] made for a scene's `[env]` with `method = "transfer"`.
pub type PreparedTransfer = PreparedTable<TransferTable>;

/// How [`prepare_table`] names and writes one method's cache entries.
pub struct TableCache<T> {
    /// The entry file of a key in a cache directory.
    pub file_name: fn(&Path, u64) -> PathBuf,
    /// The bytes of a table's entry under a key.
    pub encode: fn(&T, u64) -> Vec<u8>,
}

/// The preparation every tabulated method shares: loads the probe of `spec` (relative to
/// `base`), computes its cache key from the probe file's bytes, the loader options and the
/// decoded probe (`key`, which also checks the method's parameters against the probe),
/// reads the table from its entry in `cache_dir` when `read` (entry file, key, the probe's
/// rotation) finds a valid one, else bakes it from the probe without the brightest
/// `spec.exact_lights` texels (`bake`, given their indices) and writes it there
/// atomically; those texels become lights scaled by `spec.intensity`. The probe is decoded
/// either way (milliseconds; the brightest texels come from it). Errors name the file or
/// the field; a cache that cannot be written only costs time and is not one.
pub fn prepare_table<T>(
    spec: &EnvSpec,
    base: &Path,
    cache_dir: Option<&Path>,
    cache: TableCache<T>,
    key: impl FnOnce(&[u8], &LoadOptions, &Probe) -> Result<u64>,
    read: impl FnOnce(&Path, u64, f64) -> std::result::Result<Option<T>, String>,
    bake: impl FnOnce(&Probe, &[usize]) -> Result<T>,
) -> Result<PreparedTable<T>> {
    spec.check()?;
    let path = base.join(&spec.file);
    let bytes = crate::image_io::read_regular_file(
        &path,
        crate::env::probe::MAX_PROBE_FILE_BYTES,
        "light probe",
    )?;
    let opts = spec.load_options();
    let (probe, report) = crate::env::probe::load_probe(&path, &opts)?;
    let key = key(&bytes, &opts, &probe)?;
    drop(bytes);
    let exact = brightest_texels(&probe, spec.exact_lights);
    let file = cache_dir.map(|d| (cache.file_name)(d, key));
    let (mut cached, mut cache_rejected) = (None, None);
    if let Some(f) = &file {
        match read(f, key, probe.rotation()) {
            Ok(t) => cached = t,
            Err(why) => cache_rejected = Some(why),
        }
    }
    let cache_hit = cached.is_some();
    let table = match cached {
        Some(t) => t,
        None => {
            let t = bake(&probe, &exact)?;
            if let Some(f) = &file {
                // A cache that cannot be written only costs time: ignore the error.
                if std::fs::create_dir_all(f.parent().unwrap_or(Path::new("."))).is_ok() {
                    let _ = crate::image_io::write_atomic(f, &(cache.encode)(&t, key));
                }
            }
            t
        }
    };
    Ok(PreparedTable {
        lights: build::texel_lights(&probe, &exact, spec.intensity),
        table,
        report,
        cache_hit,
        cache_rejected,
        cache_file: file,
    })
}

/// Loads the probe of `spec` (relative to `base`) and builds its transfer table for
/// `basis` on the spec's grid, the brightest `spec.exact_lights` texels split off as
/// lights; `spec.intensity` scales both. With `cache_dir`, the table is read from its
/// cache entry when one is valid, else built and written there ([`cache`],
/// [`prepare_table`]). `progress` counts table rows when the table is built (nothing on a
/// cache hit). Errors name the file or the field.
pub fn prepare_transfer(
    spec: &EnvSpec,
    base: &Path,
    basis: TransferBasis,
    cache_dir: Option<&Path>,
    progress: &Progress,
) -> Result<PreparedTransfer> {
    let params = cache::TableParams {
        basis,
        grid: (spec.transfer_azimuth, spec.transfer_polar),
        exact_lights: spec.exact_lights,
        intensity: spec.intensity,
    };
    prepare_table(
        spec,
        base,
        cache_dir,
        cache::TABLE_CACHE,
        |bytes, opts, _| Ok(cache::table_cache_key(bytes, opts, &params)),
        |f, key, rotation| cache::read_entry(f, key, basis, params.grid, rotation),
        |probe, exact| {
            build_table(
                probe,
                basis,
                params.grid,
                exact,
                spec.intensity,
                progress,
                BuildFault::None,
            )
        },
    )
}

#[cfg(test)]
mod tests;
