//! `brdfkit golden check --device gpu` (cargo feature `gpu`): every entry the wgpu renderer
//! ([`crate::gpu`]) supports rendered on the GPU and compared with the stored oracle image
//! at the entry's FLIP bounds ([`entry_bounds`]: [`Entry::thresholds`], unless
//! `golden/gpu-bounds.toml` sets GPU-side bounds for it, each with its reason); every other
//! entry listed as skipped with the reason. A GPU build never matches bits (another
//! rasterizer, another evaluation order), so bounds apply: FLIP (what a person sees), the
//! radiometric bounds the GPU bounds file sets per entry (what the method must agree to:
//! mean, relative RMSE, relative error at the percentile, silhouette coverage), and no
//! non-finite value. The comparison is `brdfkit compare`'s ([`compare::compare_with`] over
//! the covered pixels), so `brdfkit compare --bounds golden/gpu-bounds.toml --entry NAME`
//! of the same two images gives the same verdict. The bounds file's format:
//! src/golden/gpu_bounds.rs.

use super::*;
use crate::compare::{AlphaMode, Pixels};
use crate::gpu::{self, Faults, Gpu};

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
    /// The radiometric measures (over the pixels lit in both images) and the share of
    /// covered pixels lit in one only.
    pub radiometric: crate::compare::Radiometric,
    pub coverage_mismatch: f64,
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
        let (bounds, gpu_side) = entry_bounds(entry, &overrides);
        let mut o = GpuOutcome {
            name: entry.name.clone(),
            passed: None,
            flip_mean: f32::NAN,
            flip_p99: f32::NAN,
            flip_at_percentile: f32::NAN,
            max_abs: f32::NAN,
            radiometric: Default::default(),
            coverage_mismatch: f64::NAN,
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
        let (m, flip) = compare::compare_with(&e, &a, &bounds, AlphaMode::Ignore, Pixels::Covered)?;
        let passed = m.passes(&bounds);
        o.passed = Some(passed);
        o.flip_mean = m.flip_mean;
        o.flip_p99 = m.flip_p99;
        o.flip_at_percentile = m.flip_at_percentile;
        o.max_abs = m.max_abs;
        o.radiometric = m.radiometric;
        o.coverage_mismatch = m.coverage_mismatch_share();
        let limit = |v: Option<f32>| v.map_or(String::new(), |v| format!(" (<= {v})"));
        let r = &bounds.radiometric;
        o.message = format!(
            "FLIP mean {:.4} (<= {}), p{} {:.4} (<= {}); mean error {:.2e}{}, rel RMSE {:.2e}{}, \
             rel error p{} {:.2e}{}, coverage mismatch {:.2e}{} over {} covered pixels{}{}",
            m.flip_mean,
            bounds.flip_mean,
            (bounds.percentile * 100.0).round(),
            m.flip_at_percentile,
            bounds.flip_at_percentile,
            m.radiometric.mean_error,
            limit(r.mean_error),
            m.radiometric.rel_rmse,
            limit(r.rel_rmse),
            (bounds.percentile * 100.0).round(),
            m.radiometric.rel_error_at_percentile,
            limit(r.rel_error_at_percentile),
            o.coverage_mismatch,
            limit(r.coverage_mismatch),
            m.covered,
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
