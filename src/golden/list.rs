//! `brdfkit golden list`: every entry of a golden directory with what a script needs to
//! render and check it (scene file, FLIP bounds, AOV).
//!
//! Design rule: the listed bounds are the ones the checks apply, resolved by the same
//! functions ([`Entry::thresholds`] for `brdfkit compare --bounds golden/manifest.toml`,
//! [`entry_bounds`] for `golden check --device gpu` and `compare --bounds
//! golden/gpu-bounds.toml`), never recomputed here.

use super::*;

/// One entry as `golden list` prints it.
#[derive(Clone, Debug, Serialize)]
pub struct Listed {
    pub name: String,
    /// The scene file: the golden directory joined with the manifest's `scene`.
    pub scene: PathBuf,
    /// The debug output rendered instead of the shaded image, if any.
    pub aov: Option<Aov>,
    /// The manifest's tolerance name (the CPU check's per-pixel tolerance).
    pub tolerance: String,
    /// The entry's FLIP bounds from the manifest ([`Entry::thresholds`]).
    pub bounds: Thresholds,
    /// The bounds a GPU build's image is held to ([`entry_bounds`]: gpu-bounds.toml's, else
    /// the manifest's).
    pub gpu_bounds: Thresholds,
    /// Whether `gpu_bounds` come from gpu-bounds.toml.
    pub gpu_side: bool,
}

impl Listed {
    /// The line for scripts, tab-separated: name, scene file, FLIP bounds
    /// (`mean=M,pP=V`: the manifest's), the bounds a GPU build is held to (the same form),
    /// AOV (`-` for a shaded image).
    pub fn line(&self) -> String {
        let b = |t: &Thresholds| {
            format!(
                "mean={},{}={}",
                t.flip_mean,
                compare::percentile_label(t.percentile),
                t.flip_at_percentile
            )
        };
        let aov = self.aov.map_or("-".to_string(), |a| {
            use clap::ValueEnum;
            a.to_possible_value()
                .map(|v| v.get_name().to_string())
                .unwrap_or_default()
        });
        format!(
            "{}\t{}\t{}\t{}\t{aov}",
            self.name,
            self.scene.display(),
            b(&self.bounds),
            b(&self.gpu_bounds)
        )
    }
}

/// The entries of `dir/manifest.toml` in manifest order, with `dir/gpu-bounds.toml`'s
/// bounds where it lists them. Errors as [`load_manifest`] and [`load_gpu_bounds`].
pub fn list(dir: &Path) -> Result<Vec<Listed>> {
    let manifest = load_manifest(dir)?;
    let overrides = load_gpu_bounds(dir, &manifest)?;
    Ok(manifest
        .entries
        .iter()
        .map(|e| {
            let (gpu_bounds, gpu_side) = entry_bounds(e, &overrides);
            Listed {
                name: e.name.clone(),
                scene: dir.join(&e.scene),
                aov: e.aov,
                tolerance: e.tolerance.clone(),
                bounds: e.thresholds().expect("checked by parse_manifest"),
                gpu_bounds,
                gpu_side,
            }
        })
        .collect())
}
