//! `brdfkit golden check --device gpu` (cargo feature `gpu`): every entry the wgpu renderer
//! ([`crate::gpu`]) supports rendered on the GPU and compared with the stored oracle image
//! at the entry's FLIP bounds ([`Entry::thresholds`], unless `golden/gpu-bounds.toml` sets
//! GPU-side bounds for it, each with its reason); every other entry listed as skipped with
//! the reason. A GPU build never matches bits (another rasterizer, another evaluation
//! order), so only the FLIP bounds apply, plus: no non-finite value.
//!
//! `golden/gpu-bounds.toml` (optional):
//! ```toml
//! [fig3-10-blue-silk-nearest]
//! mean = 0.004          # FLIP mean bound
//! percentile = 0.99
//! at_percentile = 0.05  # FLIP bound at that percentile
//! why = "..."           # the measurement behind the change
//! ```

use super::*;
use crate::gpu::{self, Faults, Gpu};
use std::collections::BTreeMap;

/// GPU-side FLIP bounds of one entry (golden/gpu-bounds.toml), with the reason.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GpuBound {
    pub mean: f32,
    pub percentile: f32,
    pub at_percentile: f32,
    pub why: String,
}

/// The file of GPU-side bounds beside the manifest.
pub const GPU_BOUNDS_FILE: &str = "gpu-bounds.toml";

/// Reads `dir/gpu-bounds.toml` (none: no overrides). Errors name the file; an entry name
/// not in `manifest` is an error.
pub fn load_gpu_bounds(dir: &Path, manifest: &Manifest) -> Result<BTreeMap<String, GpuBound>> {
    let path = dir.join(GPU_BOUNDS_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(BTreeMap::new()),
        Err(e) => return Err(Error::io(&path, "cannot read", e)),
    };
    let bounds: BTreeMap<String, GpuBound> = toml::from_str(&text)
        .map_err(|e| Error::format(&path, e.to_string().trim().to_string()))?;
    for (name, b) in &bounds {
        if !manifest.entries.iter().any(|e| &e.name == name) {
            return Err(Error::format(
                &path,
                format!("[{name}]: no such golden entry"),
            ));
        }
        let in_range = (0.0..=1.0).contains(&b.mean)
            && b.percentile > 0.0
            && b.percentile < 1.0
            && (0.0..=1.0).contains(&b.at_percentile);
        if !in_range {
            return Err(Error::format(
                &path,
                format!("[{name}]: bounds out of range (mean, at_percentile in [0, 1]; percentile in (0, 1))"),
            ));
        }
    }
    Ok(bounds)
}

/// One entry of the GPU check.
#[derive(Debug)]
pub struct GpuOutcome {
    pub name: String,
    /// `None`: skipped (`message` says why).
    pub passed: Option<bool>,
    pub flip_mean: f32,
    pub flip_p99: f32,
    pub flip_at_percentile: f32,
    pub max_abs: f32,
    /// The bounds applied, and whether they are GPU-side ones.
    pub bounds: Thresholds,
    pub gpu_side_bounds: bool,
    pub message: String,
}

/// Checks the named entries of `dir` (all if `names` is empty) on `gpu` with the seeded
/// `faults`; failures leave `expected | FLIP | actual` PNGs in `report_dir`.
pub fn check_gpu(
    gpu: &Gpu,
    dir: &Path,
    report_dir: &Path,
    names: &[String],
    faults: Faults,
) -> Result<Vec<GpuOutcome>> {
    let manifest = load_manifest(dir)?;
    for n in names {
        Entry::find(&manifest, &manifest_path(dir), n)?;
    }
    let overrides = load_gpu_bounds(dir, &manifest)?;
    let mut out = Vec::new();
    for entry in &manifest.entries {
        if !names.is_empty() && !names.contains(&entry.name) {
            continue;
        }
        let (_, scene) = load_scene(dir, entry, KernelPath::Auto)?;
        let (bounds, gpu_side) = match overrides.get(&entry.name) {
            Some(b) => (
                Thresholds {
                    flip_mean: b.mean,
                    percentile: b.percentile,
                    flip_at_percentile: b.at_percentile,
                },
                true,
            ),
            None => (
                entry.thresholds().expect("checked by parse_manifest"),
                false,
            ),
        };
        let mut o = GpuOutcome {
            name: entry.name.clone(),
            passed: None,
            flip_mean: f32::NAN,
            flip_p99: f32::NAN,
            flip_at_percentile: f32::NAN,
            max_abs: f32::NAN,
            bounds,
            gpu_side_bounds: gpu_side,
            message: String::new(),
        };
        if let Some(why) = gpu::unsupported(&scene, entry.aov) {
            o.message = format!("skipped: {why}");
            out.push(o);
            continue;
        }
        let expected = image_io::read_exr(&dir.join(format!("{}.exr", entry.name)))?;
        let actual = gpu.render_aov(&scene, entry.aov, faults)?;
        let (e, a) = (Loaded::from_linear(expected), Loaded::from_linear(actual));
        let (m, flip) = compare::compare(&e, &a, &bounds)?;
        let passed = m.passes(&bounds);
        o.passed = Some(passed);
        o.flip_mean = m.flip_mean;
        o.flip_p99 = m.flip_p99;
        o.flip_at_percentile = m.flip_at_percentile;
        o.max_abs = m.max_abs;
        o.message = format!(
            "FLIP mean {:.4} (<= {}), p{} {:.4} (<= {}){}{}",
            m.flip_mean,
            bounds.flip_mean,
            (bounds.percentile * 100.0).round(),
            m.flip_at_percentile,
            bounds.flip_at_percentile,
            if m.non_finite > 0 {
                format!(", {} non-finite values", m.non_finite)
            } else {
                String::new()
            },
            if gpu_side { " [gpu-bounds.toml]" } else { "" },
        );
        if !passed {
            std::fs::create_dir_all(report_dir)
                .map_err(|err| Error::io(report_dir, "cannot create", err))?;
            compare::write_report_image(
                &report_dir.join(format!("{}.png", entry.name)),
                &e,
                &a,
                &flip,
            )?;
        }
        out.push(o);
    }
    Ok(out)
}
