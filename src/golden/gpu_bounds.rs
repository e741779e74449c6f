//! `golden/gpu-bounds.toml`: GPU-side bounds for a GPU build's image of an entry, each with
//! the measurement behind it: FLIP bounds that replace the entry's manifest bounds, and the
//! radiometric bounds ([`RadiometricBounds`]) that only this file sets. Read by `golden check
//! --device gpu`, `brdfkit compare --bounds` and `golden list`, through this one parser.
//!
//! Design rule: one file, one parser, one resolution ([`entry_bounds`]): an entry the file
//! lists takes its bounds, every other entry its manifest bounds ([`Entry::thresholds`]),
//! wherever the bounds are applied.
//!
//! ```toml
//! [fig3-10-blue-silk-nearest]
//! mean = 0.004             # FLIP mean bound (unset: the manifest's)
//! percentile = 0.99
//! at_percentile = 0.05     # FLIP bound at that percentile
//! mean_error = 3e-4        # largest |mean ratio - 1| of a channel (unset: not checked)
//! rel_rmse = 1e-3          # largest relative RMSE
//! rel_error = 5e-3         # largest per-pixel relative error at the percentile
//! coverage_mismatch = 0.01 # largest share of pixels covered in one image only
//! why = "..."              # the measurement behind the bounds
//! ```

use super::*;
use std::collections::BTreeMap;

/// GPU-side bounds of one entry (golden/gpu-bounds.toml), with the reason: FLIP bounds
/// that replace the manifest's (each unset one keeps the manifest's), and radiometric
/// bounds ([`RadiometricBounds`], unset: not checked).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GpuBound {
    /// Largest passing FLIP mean, in [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean: Option<f32>,
    /// Percentile of the FLIP bound and of the relative error's, in (0, 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub percentile: Option<f32>,
    /// Largest passing FLIP value at `percentile`, in [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at_percentile: Option<f32>,
    /// Largest `|mean ratio - 1|` of a channel, >= 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_error: Option<f32>,
    /// Largest relative RMSE, >= 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rel_rmse: Option<f32>,
    /// Largest per-pixel relative error at `percentile`, >= 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rel_error: Option<f32>,
    /// Largest share of the covered pixels covered in one image only, in [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coverage_mismatch: Option<f32>,
    pub why: String,
}

impl GpuBound {
    /// `base` (the entry's manifest bounds) with what this table sets in their place.
    pub fn thresholds(&self, base: Thresholds) -> Thresholds {
        Thresholds {
            flip_mean: self.mean.unwrap_or(base.flip_mean),
            percentile: self.percentile.unwrap_or(base.percentile),
            flip_at_percentile: self.at_percentile.unwrap_or(base.flip_at_percentile),
            radiometric: RadiometricBounds {
                mean_error: self.mean_error.or(base.radiometric.mean_error),
                rel_rmse: self.rel_rmse.or(base.radiometric.rel_rmse),
                rel_error_at_percentile: self
                    .rel_error
                    .or(base.radiometric.rel_error_at_percentile),
                coverage_mismatch: self
                    .coverage_mismatch
                    .or(base.radiometric.coverage_mismatch),
            },
        }
    }
}

/// The file of GPU-side bounds beside the manifest.
pub const GPU_BOUNDS_FILE: &str = "gpu-bounds.toml";

/// Largest GPU bounds file read (bytes), as for the manifest.
pub const MAX_GPU_BOUNDS_BYTES: u64 = MAX_MANIFEST_BYTES;

/// Reads `dir/gpu-bounds.toml` (none: no overrides) and checks it against `manifest`
/// ([`load_gpu_bounds_file`]).
pub fn load_gpu_bounds(dir: &Path, manifest: &Manifest) -> Result<BTreeMap<String, GpuBound>> {
    let path = dir.join(GPU_BOUNDS_FILE);
    match std::fs::symlink_metadata(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(BTreeMap::new()),
        _ => load_gpu_bounds_file(&path, manifest),
    }
}

/// Reads a GPU bounds file. Errors name the file: not a regular file or over
/// [`MAX_GPU_BOUNDS_BYTES`], a TOML error (with its line), an unknown field, bounds out of
/// range, or an entry name not in `manifest`.
pub fn load_gpu_bounds_file(
    path: &Path,
    manifest: &Manifest,
) -> Result<BTreeMap<String, GpuBound>> {
    let text = crate::image_io::read_regular_text(path, MAX_GPU_BOUNDS_BYTES, "GPU bounds file")?;
    let bounds = parse_gpu_bounds(&text).map_err(|m| Error::format(path, m))?;
    for name in bounds.keys() {
        if !manifest.entries.iter().any(|e| &e.name == name) {
            return Err(Error::format(
                path,
                format!("[{name}]: no such golden entry"),
            ));
        }
    }
    Ok(bounds)
}

/// Parses GPU bounds text and checks each table's range (mean and at_percentile in [0, 1],
/// percentile in (0, 1)); the error is one line naming the table or the TOML line.
pub fn parse_gpu_bounds(text: &str) -> std::result::Result<BTreeMap<String, GpuBound>, String> {
    let bounds: BTreeMap<String, GpuBound> =
        toml::from_str(text).map_err(|e| crate::error::toml_message(text, &e))?;
    for (name, b) in &bounds {
        let unit = |v: Option<f32>| v.is_none_or(|v| (0.0..=1.0).contains(&v));
        let non_negative = |v: Option<f32>| v.is_none_or(|v| v >= 0.0 && v.is_finite());
        let in_range = unit(b.mean)
            && b.percentile.is_none_or(|p| p > 0.0 && p < 1.0)
            && unit(b.at_percentile)
            && non_negative(b.mean_error)
            && non_negative(b.rel_rmse)
            && non_negative(b.rel_error)
            && unit(b.coverage_mismatch);
        if !in_range {
            return Err(format!(
                "[{name}]: bounds out of range (mean, at_percentile, coverage_mismatch in [0, 1]; \
                 percentile in (0, 1); mean_error, rel_rmse, rel_error finite and >= 0)"
            ));
        }
    }
    Ok(bounds)
}

/// The FLIP bounds a GPU build's image of `entry` is held to: the GPU-side ones of
/// `overrides` when it lists the entry (`true`), else the entry's manifest bounds
/// ([`Entry::thresholds`], `false`).
pub fn entry_bounds(entry: &Entry, overrides: &BTreeMap<String, GpuBound>) -> (Thresholds, bool) {
    let base = entry.thresholds().expect("checked by parse_manifest");
    match overrides.get(&entry.name) {
        Some(b) => (b.thresholds(base), true),
        None => (base, false),
    }
}

/// Where [`bounds_from_file`] took an entry's bounds from.
#[derive(Clone, Debug)]
pub struct ResolvedBounds {
    pub thresholds: Thresholds,
    /// The file whose entry gave them: the file given, or the manifest beside a GPU
    /// bounds file that does not list the entry.
    pub from: PathBuf,
    /// The bounds came from a GPU bounds file.
    pub gpu_side: bool,
}

/// The FLIP bounds of entry `name` from `path`, which is a golden manifest (its entry's
/// bounds, [`Entry::thresholds`]) or a GPU bounds file such as golden/gpu-bounds.toml,
/// with the manifest beside it (the bounds `golden check --device gpu` applies,
/// [`entry_bounds`]). A file with an `[[entry]]` array is a manifest. Errors name the file:
/// unreadable or invalid ([`load_manifest_file`], [`load_gpu_bounds_file`]), or no entry
/// `name` (the entries listed).
pub fn bounds_from_file(path: &Path, name: &str) -> Result<ResolvedBounds> {
    let text = crate::image_io::read_regular_text(path, MAX_MANIFEST_BYTES, "bounds file")?;
    let is_manifest = toml::from_str::<toml::Table>(&text)
        .ok()
        .is_some_and(|t| t.get("entry").is_some_and(toml::Value::is_array));
    if is_manifest {
        let manifest = load_manifest_file(path)?;
        let entry = Entry::find(&manifest, path, name)?;
        return Ok(ResolvedBounds {
            thresholds: entry.thresholds().expect("checked by parse_manifest"),
            from: path.to_path_buf(),
            gpu_side: false,
        });
    }
    let manifest_file = manifest_path(path.parent().unwrap_or(Path::new("")));
    let manifest = load_manifest_file(&manifest_file)?;
    let overrides = load_gpu_bounds_file(path, &manifest)?;
    let entry = Entry::find(&manifest, &manifest_file, name)?;
    let (thresholds, gpu_side) = entry_bounds(entry, &overrides);
    Ok(ResolvedBounds {
        thresholds,
        from: if gpu_side {
            path.to_path_buf()
        } else {
            manifest_file
        },
        gpu_side,
    })
}
