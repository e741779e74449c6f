//! The scene file as written: its schema (every field optional, with its default) and
//! reading it.
//!
//! Design rule: this is the TOML as the user writes it, nothing checked beyond its syntax
//! and types (unknown fields are errors, `deny_unknown_fields`); every value is checked
//! once, later, in `resolve.rs` ([`Scene::resolve`](super::Scene::resolve)). The material
//! part of the schema lives with the rest of the material in `material.rs`.

use super::MaterialSpec;
use crate::env::schema::EnvSpec;
use crate::error::{Error, Result};
use crate::image_io::Tonemap;
use crate::lanes::KernelPath;
use crate::raster::Cull;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Largest scene file read (bytes).
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// The scene file as written (all optional).
#[derive(Debug, Default, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneFile {
    pub camera: Option<CameraSpec>,
    pub mesh: MeshSpec,
    pub material: MaterialSpec,
    #[serde(rename = "light")]
    pub lights: Option<Vec<LightSpec>>,
    /// Environment light: a probe, shaded by `[env] method` (delta lights, a transfer
    /// table or light cuts; `auto`: [`super::env_method`]). Read and written as the table
    /// states it (`env_table.rs`: a field of another method is an error).
    #[serde(
        deserialize_with = "super::env_table::deserialize",
        serialize_with = "super::env_table::serialize"
    )]
    pub env: Option<EnvSpec>,
    /// A transfer table read from a file (`brdfkit export` writes one for `[env] method =
    /// "transfer"`): its term is added to the lights' as that method adds its own table's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transfer: Option<TransferFileSpec>,
    pub render: RenderSpec,
    pub output: OutputSpec,
}

/// `[transfer]`: a transfer table file ([`crate::env::transfer::file`], the format in
/// docs/file-formats.md) that the scene shades with, beside its lights. Its basis must fit
/// the material (an SH data set's bands and cosine, or Lambert's irradiance), and the
/// scene's `[env]`, if any, must not build a table of its own.
#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct TransferFileSpec {
    /// The table's JSON header (relative to the scene file); its values file lies beside it.
    pub table: PathBuf,
}

#[derive(Debug, Default, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraSpec {
    pub position: Option<[f32; 3]>,
    pub target: Option<[f32; 3]>,
    pub up: Option<[f32; 3]>,
    pub fov_y_deg: Option<f32>,
    pub near: Option<f32>,
}

#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct MeshSpec {
    pub source: String,
    pub segments: u32,
}

impl Default for MeshSpec {
    fn default() -> Self {
        MeshSpec {
            source: "teapot".into(),
            segments: 16,
        }
    }
}

#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LightSpec {
    Directional {
        to_light: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "default_intensity")]
        intensity: f32,
    },
    Point {
        position: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "default_intensity")]
        intensity: f32,
    },
}

fn white() -> [f32; 3] {
    [1.0, 1.0, 1.0]
}
fn default_intensity() -> f32 {
    3.0
}

/// The default light: a white key light from above, front right (thesis Fig. 3.9 left:
/// "a directional light illuminates the teapot from above").
pub fn default_lights() -> Vec<LightSpec> {
    vec![LightSpec::Directional {
        to_light: [0.4, 1.0, 0.6],
        color: white(),
        intensity: default_intensity(),
    }]
}

#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct RenderSpec {
    pub width: u32,
    pub height: u32,
    pub cull: Cull,
    pub tile_size: u32,
    pub threads: usize,
    /// Arithmetic of the shaded image (not of AOVs); default [`Precision::F32`].
    pub precision: Precision,
    /// Fraction of the total directional irradiance that may be dropped, weakest lights
    /// first (0 <= x < 1; 0 turns it off), and the largest change it may make to any pixel
    /// relative to that pixel's value: pixels it could change more get the dropped lights
    /// back. See [`crate::kernel::skip`]. Not used by the f64 path, which shades every light.
    pub drop_lights: f32,
    /// Whether SH data sets are shaded with only the bands their declared threshold needs.
    pub band_skip: bool,
    /// The kernel path of the f32 shading ([`crate::lanes`]); every path gives the
    /// same bits, so this changes only speed. [`Scene::resolve`](super::Scene::resolve)
    /// refuses a path this CPU cannot run.
    pub kernel: KernelPath,
}

/// Arithmetic of the shading stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Precision {
    /// The fast path: the kernels of [`crate::kernel`] in f32, with the skips
    /// ([`crate::shade::ShadingPath::Kernels`]).
    #[default]
    F32,
    /// Frames, directions, the BRDF ([`crate::brdf::Brdf::eval_f64`]) and the light sum in
    /// f64, every light, no light culling, rounded to f32 once per pixel
    /// ([`crate::shade::ShadingPath::F64NoSkips`]). This also turns off every skip: every
    /// light is shaded (`drop_lights` ignored) with every SH band (`band_skip` ignored).
    /// Several times slower.
    F64,
}

impl Default for RenderSpec {
    fn default() -> Self {
        RenderSpec {
            width: 640,
            height: 480,
            cull: Cull::None,
            tile_size: 32,
            threads: 0,
            precision: Precision::F32,
            drop_lights: crate::kernel::skip::DEFAULT_DROP_LIGHTS,
            band_skip: true,
            kernel: KernelPath::Auto,
        }
    }
}

#[derive(Debug, Clone, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSpec {
    pub path: Option<PathBuf>,
    pub exposure: f32,
    pub tonemap: Tonemap,
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            path: None,
            exposure: 0.0,
            tonemap: Tonemap::Aces,
        }
    }
}

impl SceneFile {
    /// Reads and parses a scene file. Errors name the file, and for content errors the
    /// field, line and column. Files that are not regular files (directories, devices,
    /// FIFOs) or over [`MAX_SCENE_BYTES`] are refused before they are read.
    pub fn load(path: &Path) -> Result<SceneFile> {
        let text = crate::image_io::read_regular_text(path, MAX_SCENE_BYTES, "scene file")?;
        SceneFile::parse(&text).map_err(|m| Error::format(path, m))
    }

    /// Parses scene TOML text, once; the error is one line. An `[env]` table that states
    /// `sampler` or `count` and no `method` asks for a delta light set: its method becomes
    /// `lights` ([`super::env_method`]); a stated `method = "auto"` stays `auto`. A field of
    /// `[env]` that belongs to another method than the table's is an error naming the field
    /// and its method (`env_table.rs`).
    pub fn parse(text: &str) -> std::result::Result<SceneFile, String> {
        toml::from_str(text).map_err(|e| crate::error::toml_message(text, &e))
    }

    /// Replaces `[env] method = "auto"` by the method it stands for under this scene's
    /// material ([`super::env_method::auto_method`]); other methods are kept.
    pub fn resolve_env_method(&mut self) {
        if let Some(env) = self.env.as_mut() {
            env.method = super::env_method::concrete_method(env, &self.material);
        }
    }

    /// The scene's light specifications: its `[[light]]` tables; none when it has only an
    /// `[env]`; [`default_lights`] when it has neither.
    pub fn light_specs(&self) -> Vec<LightSpec> {
        match (&self.lights, &self.env) {
            (Some(l), _) => l.clone(),
            (None, Some(_)) => Vec::new(),
            (None, None) => default_lights(),
        }
    }
}
