//! Scenes: the TOML scene file, its defaults, and its resolution into renderable parts.
//!
//! Design rule: every field has a default, so an empty file (or no file) is the default
//! scene; unknown fields are errors; every value is checked here, once, with an error
//! that names the file and the field. Later stages trust what a [`Scene`] holds.
//!
//! The format, every field with its default and examples, is `docs/scene-format.md`,
//! included below as the one description (the README and `brdfkit render --help` point to it;
//! `tests/docs_examples.rs` loads its examples).
//!
#![doc = include_str!("../../docs/scene-format.md")]

pub mod camera;

use crate::brdf::{BlinnPhong, Brdf, Lambert};
use crate::env::prepare::{self, CacheDir, EnvSpec};
use crate::error::{Error, Result};
use crate::image_io::Tonemap;
use crate::kernel::lanes::KernelPath;
use crate::light::Light;
use crate::mesh::{self, Mesh};
use crate::raster::Cull;
use crate::sh::dataset::Lookup;
use camera::Camera;
use glam::Vec3;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Largest accepted image side (pixels).
pub const MAX_SIDE: u32 = 16384;
/// Largest scene file read (bytes).
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// The scene file as written (all optional).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneFile {
    pub camera: Option<CameraSpec>,
    pub mesh: MeshSpec,
    pub material: MaterialSpec,
    #[serde(rename = "light")]
    pub lights: Option<Vec<LightSpec>>,
    /// Environment light: a probe collapsed into directional lights.
    pub env: Option<EnvSpec>,
    pub render: RenderSpec,
    pub output: OutputSpec,
}

#[derive(Debug, Default, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraSpec {
    pub position: Option<[f32; 3]>,
    pub target: Option<[f32; 3]>,
    pub up: Option<[f32; 3]>,
    pub fov_y_deg: Option<f32>,
    pub near: Option<f32>,
}

#[derive(Debug, Clone, Deserialize)]
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

#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MaterialSpec {
    Lambert {
        #[serde(default = "default_albedo")]
        albedo: [f32; 3],
    },
    BlinnPhong {
        #[serde(default = "default_kd")]
        kd: [f32; 3],
        #[serde(default = "default_ks")]
        ks: [f32; 3],
        #[serde(default = "default_exponent")]
        exponent: f32,
    },
    /// A library material by name (`brdfkit materials`), built at load time
    /// ([`crate::materials::build`]).
    Library {
        name: String,
        /// Coefficient-table filter for SH materials; `None` keeps the library's (bilinear).
        /// A D-BRDF material with a lookup is an error naming `material.lookup`.
        #[serde(default)]
        lookup: Option<Lookup>,
    },
    /// An SH data set file ([`crate::sh::read_sh_dataset`]), path relative to the scene file.
    ShFile {
        path: PathBuf,
        /// Coefficient-table filter; `None` keeps the file's default (nearest).
        #[serde(default)]
        lookup: Option<Lookup>,
    },
    /// A D-BRDF file ([`crate::acquire::dbrdf_file::read_dbrdf`]), path relative to the
    /// scene file.
    DbrdfFile { path: PathBuf },
}

impl MaterialSpec {
    /// The spec for a `--material` value: a library name, else a file path whose kind (SH
    /// data set or D-BRDF) is read from its `brdfkit.format` header. Fails with a field
    /// error naming `--material` when the value is neither.
    pub fn from_cli(value: &str) -> Result<MaterialSpec> {
        if crate::materials::find(value).is_some() {
            return Ok(MaterialSpec::Library {
                name: value.to_string(),
                lookup: None,
            });
        }
        let path = PathBuf::from(value);
        let path = if path.is_absolute() {
            path
        } else {
            std::env::current_dir()
                .map(|d| d.join(&path))
                .unwrap_or(path)
        };
        use crate::acquire::dbrdf_file::{read_dbrdf, DbrdfFileError};
        match read_dbrdf(&path) {
            Ok(_) => Ok(MaterialSpec::DbrdfFile { path }),
            Err(DbrdfFileError::NotDbrdf { found: Some(f), .. })
                if f == crate::sh::file::FORMAT_NAME =>
            {
                Ok(MaterialSpec::ShFile { path, lookup: None })
            }
            Err(DbrdfFileError::Io { .. } | DbrdfFileError::File(_)) if !path.exists() => {
                Err(Error::field(
                "--material",
                format!(
                    "{value:?} is neither a library material (see `brdfkit materials`) nor an existing file"
                ),
            ))
            }
            Err(e) => Err(Error::field("--material", e.to_string())),
        }
    }
}

fn default_albedo() -> [f32; 3] {
    [0.8, 0.8, 0.8]
}
fn default_kd() -> [f32; 3] {
    [0.55, 0.22, 0.12]
}
fn default_ks() -> [f32; 3] {
    [0.25, 0.25, 0.25]
}
fn default_exponent() -> f32 {
    60.0
}

impl Default for MaterialSpec {
    fn default() -> Self {
        MaterialSpec::BlinnPhong {
            kd: default_kd(),
            ks: default_ks(),
            exponent: default_exponent(),
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
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

#[derive(Debug, Clone, Deserialize)]
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
    /// first (0 <= x < 1; 0 turns it off). See [`crate::kernel::skip`]. Not used by the
    /// f64 path, which shades every light.
    pub drop_lights: f32,
    /// Whether SH data sets are shaded with only the bands their declared threshold needs.
    pub band_skip: bool,
    /// The kernel path of the f32 shading ([`crate::kernel::lanes`]); every path gives the
    /// same bits, so this changes only speed. [`Scene::resolve`] refuses a path this CPU
    /// cannot run.
    pub kernel: KernelPath,
}

/// Arithmetic of the shading stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Precision {
    /// The fast path: the kernels of [`crate::kernel`] in f32 ([`crate::shade::shade`]).
    #[default]
    F32,
    /// Frames, directions, the BRDF ([`crate::brdf::Brdf::eval_f64`]) and the light sum in
    /// f64, every light, no light culling, rounded to f32 once per pixel
    /// ([`crate::shade::shade_reference_f64`]). Several times slower.
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

#[derive(Debug, Clone, Deserialize)]
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

/// A scene ready to render: everything loaded and checked.
#[derive(Clone)]
pub struct Scene {
    pub mesh: Arc<Mesh>,
    pub camera: Camera,
    pub material: Arc<dyn Brdf>,
    pub lights: Vec<Light>,
    pub render: RenderSpec,
    pub output: OutputSpec,
    /// What environment preparation did, when the scene has an `[env]`.
    pub env: Option<EnvSummary>,
}

/// A summary of the environment light preparation, for the command line to report.
#[derive(Clone, Debug)]
pub struct EnvSummary {
    pub file: PathBuf,
    pub lights: usize,
    pub cache_hit: bool,
    /// Why an existing cache entry was ignored ([`prepare::Prepared::cache_rejected`]).
    pub cache_rejected: Option<String>,
    pub negative_texels: usize,
}

impl SceneFile {
    /// Reads and parses a scene file. Errors name the file, and for content errors the
    /// field, line and column. Files that are not regular files (directories, devices,
    /// FIFOs) or over [`MAX_SCENE_BYTES`] are refused before they are read.
    pub fn load(path: &Path) -> Result<SceneFile> {
        let text = crate::image_io::read_regular_text(path, MAX_SCENE_BYTES, "scene file")?;
        SceneFile::parse(&text).map_err(|m| Error::format(path, m))
    }

    /// Parses scene TOML text; the error is one line.
    pub fn parse(text: &str) -> std::result::Result<SceneFile, String> {
        toml::from_str(text).map_err(|e| {
            let msg = e.message().trim().replace('\n', " ");
            match e.span() {
                Some(span) => {
                    let line = text[..span.start].matches('\n').count() + 1;
                    format!("line {line}: {msg}")
                }
                None => msg,
            }
        })
    }
}

fn vec3(field: &str, v: [f32; 3]) -> Result<Vec3> {
    let v = Vec3::from(v);
    if !v.is_finite() {
        return Err(Error::field(field, format!("{v:?} is not finite")));
    }
    Ok(v)
}

fn nonneg(field: &str, x: f32) -> Result<f32> {
    if !(x.is_finite() && x >= 0.0) {
        return Err(Error::field(
            field,
            format!("{x} must be a finite number >= 0"),
        ));
    }
    Ok(x)
}

fn rgb(field: &str, v: [f32; 3]) -> Result<Vec3> {
    for x in v {
        nonneg(field, x)?;
    }
    Ok(Vec3::from(v))
}

/// The message of a field error without its field (to re-attach another field name).
fn strip_field(e: Error) -> String {
    match e {
        Error::Field { message, .. } => message,
        other => other.to_string(),
    }
}

/// Loads the mesh named by `source`: "teapot", "sphere" or an OBJ path (relative paths
/// resolve against `base`).
pub fn load_mesh(source: &str, segments: u32, base: &Path) -> Result<Mesh> {
    match source {
        "teapot" => Ok(mesh::teapot::teapot(segments)),
        "sphere" => Ok(mesh::sphere::uv_sphere(segments.max(2))),
        path => mesh::obj::load_obj(&base.join(path)),
    }
}

impl Scene {
    /// Checks and loads a scene description; `base` is the directory relative paths in it
    /// resolve against. Field errors name the field (e.g. `render.width`). An environment
    /// light set is computed, never read from or written to a disk cache
    /// ([`CacheDir::None`]); [`Scene::resolve_with_cache`] takes a cache.
    pub fn resolve(file: &SceneFile, base: &Path) -> Result<Scene> {
        Scene::resolve_with_cache(file, base, &CacheDir::None)
    }

    /// [`Scene::resolve`] with the light-set cache `cache` ([`prepare::prepare`]): the
    /// command line passes the user's ([`CacheDir::user`]), everything else none.
    pub fn resolve_with_cache(file: &SceneFile, base: &Path, cache: &CacheDir) -> Result<Scene> {
        let r = &file.render;
        for (name, v) in [("render.width", r.width), ("render.height", r.height)] {
            if v == 0 || v > MAX_SIDE {
                return Err(Error::field(
                    name,
                    format!("{v} is out of range (1 to {MAX_SIDE} pixels)"),
                ));
            }
        }
        if !(1..=1024).contains(&r.tile_size) {
            return Err(Error::field(
                "render.tile_size",
                format!("{} is out of range (1 to 1024)", r.tile_size),
            ));
        }
        if r.threads > 1024 {
            return Err(Error::field(
                "render.threads",
                format!("{} is out of range (0 to 1024)", r.threads),
            ));
        }
        if !(0.0..1.0).contains(&r.drop_lights) {
            return Err(Error::field(
                "render.drop_lights",
                format!("{} is out of range (0 <= fraction < 1)", r.drop_lights),
            ));
        }
        if crate::kernel::lanes::Dispatch::choose(r.kernel).is_none() {
            return Err(Error::field(
                "render.kernel",
                format!(
                    "'{}' is not available on this CPU (available: auto, {})",
                    r.kernel.name(),
                    KernelPath::available()
                        .iter()
                        .map(|p| p.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
        if !file.output.exposure.is_finite() || file.output.exposure.abs() > 64.0 {
            return Err(Error::field(
                "output.exposure",
                format!("{} is out of range (-64 to 64 stops)", file.output.exposure),
            ));
        }
        if file.mesh.segments == 0 || file.mesh.segments > 256 {
            return Err(Error::field(
                "mesh.segments",
                format!("{} is out of range (1 to 256)", file.mesh.segments),
            ));
        }
        let mesh = load_mesh(&file.mesh.source, file.mesh.segments, base)?;

        let material: Arc<dyn Brdf> = match &file.material {
            MaterialSpec::Lambert { albedo } => Arc::new(Lambert {
                albedo: rgb("material.albedo", *albedo)?,
            }),
            MaterialSpec::BlinnPhong { kd, ks, exponent } => Arc::new(BlinnPhong {
                kd: rgb("material.kd", *kd)?,
                ks: rgb("material.ks", *ks)?,
                exponent: nonneg("material.exponent", *exponent)?,
            }),
            MaterialSpec::Library { name, lookup } => {
                let m = crate::materials::build(name)
                    .map_err(|e| Error::field("material.name", strip_field(e)))?;
                match lookup {
                    None => m,
                    Some(mode) => {
                        let mut ds = m.as_sh().cloned().ok_or_else(|| {
                            Error::field(
                                "material.lookup",
                                format!(
                                    "{name:?} is not an SH data set (it is a {}); only SH \
                                     materials have a coefficient lookup",
                                    m.name()
                                ),
                            )
                        })?;
                        ds.coeff_lookup = *mode;
                        Arc::new(ds)
                    }
                }
            }
            MaterialSpec::ShFile { path, lookup } => {
                let mut ds = crate::sh::read_sh_dataset(&base.join(path))
                    .map_err(|e| Error::field("material.path", e.to_string()))?;
                if let Some(mode) = lookup {
                    ds.coeff_lookup = *mode;
                }
                Arc::new(ds)
            }
            MaterialSpec::DbrdfFile { path } => Arc::new(
                crate::acquire::dbrdf_file::read_dbrdf(&base.join(path))
                    .map_err(|e| Error::field("material.path", e.to_string()))?
                    .0,
            ),
        };

        let specs = match (&file.lights, &file.env) {
            (Some(l), _) => l.clone(),
            (None, Some(_)) => Vec::new(),
            (None, None) => default_lights(),
        };
        let mut lights = Vec::with_capacity(specs.len());
        for (i, l) in specs.iter().enumerate() {
            let f = |name: &str| format!("light[{i}].{name}");
            lights.push(match l {
                LightSpec::Directional {
                    to_light,
                    color,
                    intensity,
                } => {
                    let d = vec3(&f("to_light"), *to_light)?;
                    let d = d.try_normalize().ok_or_else(|| {
                        Error::field(f("to_light"), "must not be the zero vector")
                    })?;
                    Light::Directional {
                        to_light: d,
                        irradiance: rgb(&f("color"), *color)?
                            * nonneg(&f("intensity"), *intensity)?,
                    }
                }
                LightSpec::Point {
                    position,
                    color,
                    intensity,
                } => Light::Point {
                    position: vec3(&f("position"), *position)?,
                    intensity: rgb(&f("color"), *color)? * nonneg(&f("intensity"), *intensity)?,
                },
            });
        }

        let mut env = None;
        if let Some(spec) = &file.env {
            let prepared = prepare::prepare(spec, base, cache.path())?;
            lights.extend(prepare::to_scene_lights(&prepared.lights));
            env = Some(EnvSummary {
                file: base.join(&spec.file),
                lights: prepared.lights.len(),
                cache_hit: prepared.cache_hit,
                cache_rejected: prepared.cache_rejected,
                negative_texels: prepared.report.map_or(0, |r| r.negative_texels),
            });
        }

        let aspect = r.width as f32 / r.height as f32;
        let spec = file.camera.clone().unwrap_or_default();
        let fov = spec.fov_y_deg.unwrap_or(camera::DEFAULT_FOV_Y_DEG);
        if !(fov > 0.0 && fov < 179.0) {
            return Err(Error::field(
                "camera.fov_y_deg",
                format!("{fov} is out of range (0 to 179 degrees)"),
            ));
        }
        let bounds = mesh.bounds();
        let mut cam = Camera::frame(&bounds, mesh.radius_about(bounds.center()), aspect, fov);
        if let Some(t) = spec.target {
            cam.target = vec3("camera.target", t)?;
        }
        if let Some(p) = spec.position {
            cam.position = vec3("camera.position", p)?;
            cam.near = (cam.target - cam.position).length() * 1e-3;
        }
        if let Some(u) = spec.up {
            cam.up = vec3("camera.up", u)?;
            if cam.up.length_squared() == 0.0 {
                return Err(Error::field("camera.up", "must not be the zero vector"));
            }
        }
        if cam.position == cam.target {
            return Err(Error::field(
                "camera.position",
                "equals camera.target: no viewing direction",
            ));
        }
        if let Some(n) = spec.near {
            cam.near = n;
        }
        if !(cam.near > 0.0 && cam.near.is_finite()) {
            return Err(Error::field(
                "camera.near",
                format!("{} must be a finite number > 0", cam.near),
            ));
        }
        Ok(Scene {
            mesh: Arc::new(mesh),
            camera: cam,
            material,
            lights,
            render: r.clone(),
            output: file.output.clone(),
            env,
        })
    }

    /// The default scene (no file).
    pub fn default_scene() -> Scene {
        Scene::resolve(&SceneFile::default(), Path::new(".")).expect("the default scene is valid")
    }
}
