//! The scene `brdfkit sweep` renders when no `--scene` is given.
//!
//! Design rule: it is the render defaults (sampler, light count, material lookup) on a
//! small frame, so the sweep's default row is what `brdfkit render` does out of the box.

use crate::env::prepare::EnvSpec;
use crate::error::{Error, Result};
use crate::scene::{MaterialSpec, SceneFile};
use std::path::PathBuf;

/// The scene a sweep renders: the default is the teapot in `blue-silk` (library SH
/// material, 8 bands, its own bilinear lookup) under `assets/probes/city.exr`, 160x120,
/// environment sampler and count at their defaults (the render defaults).
pub fn default_scene_file() -> Result<SceneFile> {
    let rel = PathBuf::from("assets/probes/city.exr");
    let probe = if rel.is_file() {
        std::env::current_dir().map(|d| d.join(&rel)).unwrap_or(rel)
    } else {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(&rel)
    };
    if !probe.is_file() {
        return Err(Error::format(
            &probe,
            "the default sweep scene's probe is missing: run from the repository or give --scene",
        ));
    }
    let mut f = SceneFile {
        material: MaterialSpec::Library {
            name: "blue-silk".into(),
            lookup: None,
        },
        env: Some(EnvSpec::new(probe)),
        ..SceneFile::default()
    };
    f.render.width = 160;
    f.render.height = 120;
    Ok(f)
}
