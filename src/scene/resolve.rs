//! Resolution: a checked, loaded, renderable [`Scene`] from a [`SceneFile`].
//!
//! Design rule: every value of the file is checked here, once, with an error that names
//! the file and the field; later stages trust what a [`Scene`] holds. Relative paths
//! resolve against the scene file's directory (`base`). The material is built by
//! `material.rs` ([`MaterialSpec`](super::MaterialSpec)), an environment light set by
//! [`crate::env::lightset::prepare`].

use super::camera::{self, Camera};
use super::environment::{build_environment, EnvSummary, Environment, ProbeSource};
use super::fields::{nonneg, rgb, vec3};
use super::material::resolve_material;
use super::{LightSpec, OutputSpec, RenderSpec, SceneFile};
use crate::env::lightset::prepare::CacheDir;
use crate::env::transfer::TransferBasis;
use crate::error::{Error, Result};
use crate::lanes::KernelPath;
use crate::light::Light;
use crate::material::Material;
use crate::mesh::{self, Mesh};
use crate::progress::Progress;
use std::path::Path;
use std::sync::Arc;

/// Largest accepted image side (pixels).
pub const MAX_SIDE: u32 = 16384;

/// A scene ready to render: everything loaded and checked.
#[derive(Clone)]
pub struct Scene {
    pub mesh: Arc<Mesh>,
    pub camera: Camera,
    /// The material, built once here ([`Material`], the closed set of shadeable models).
    pub material: Material,
    /// The scene's own delta lights (its `[[light]]` tables, or the default light); the
    /// environment's are in `environment` ([`Scene::delta_lights`] gives both).
    pub lights: Vec<Light>,
    pub render: RenderSpec,
    pub output: OutputSpec,
    /// How the environment is shaded and what its method prepared ([`Environment`]).
    pub environment: Environment,
    /// What environment preparation did, when the scene has an `[env]`.
    pub env: Option<EnvSummary>,
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

    /// [`Scene::resolve`] with the light-set cache `cache` ([`crate::env::lightset::prepare::prepare`]): the
    /// command line passes the user's ([`CacheDir::user`]), everything else none.
    pub fn resolve_with_cache(file: &SceneFile, base: &Path, cache: &CacheDir) -> Result<Scene> {
        Scene::resolve_with_progress(file, base, cache, &Progress::hidden())
    }

    /// [`Scene::resolve_with_cache`], counting the environment's light-set preparation on
    /// `progress` ([`crate::env::lightset::prepare::prepare_with_progress`]: nothing on a cache hit). Counting
    /// does not change the scene.
    pub fn resolve_with_progress(
        file: &SceneFile,
        base: &Path,
        cache: &CacheDir,
        progress: &Progress,
    ) -> Result<Scene> {
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
        if crate::lanes::Dispatch::choose(r.kernel).is_none() {
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

        let material = resolve_material(&file.material, base)?;

        let specs = file.light_specs();
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

        // `auto` replaced by the method it stands for under this material.
        let env_spec = file.env.clone().map(|mut s| {
            s.method = super::env_method::concrete_method(&s, &file.material);
            s
        });
        // A probe that is not there: named as the scene wrote it, under its field (every
        // method reads the probe, unless `[env] lights` names a light set file instead).
        // An empty `file` is reported as missing where the probe is read.
        let named = |s: &&crate::env::EnvSpec| s.lights.is_none() && !s.file.as_os_str().is_empty();
        if let Some(spec) = env_spec.as_ref().filter(named) {
            if let Err(e) = std::fs::metadata(base.join(&spec.file)) {
                if e.kind() == std::io::ErrorKind::NotFound {
                    return Err(Error::field(
                        "env.file",
                        format!("\"{}\": no such file", spec.file.display()),
                    ));
                }
            }
        }
        let (mut environment, env) = match &env_spec {
            Some(spec) => {
                let source = ProbeSource::Files {
                    base,
                    cache,
                    progress,
                };
                build_environment(spec, &material, source)?
            }
            None => (Environment::None, None),
        };

        if let Some(t) = &file.transfer {
            let table = crate::env::transfer::file::read_table(&base.join(&t.table))?;
            let wanted = TransferBasis::for_material(&material);
            if wanted != Some(table.basis()) {
                use crate::env::transfer::file::basis_text;
                return Err(Error::field(
                    "transfer.table",
                    format!(
                        "a table of {} does not fit the material {} ({})",
                        basis_text(table.basis()),
                        material.name(),
                        wanted.map_or(
                            "transfer tables shade SH data sets and Lambert only".into(),
                            |b| { format!("it needs {}", basis_text(b)) }
                        )
                    ),
                ));
            }
            // The table shades beside the `[env]`'s light set, if any.
            let exact = environment
                .lights_beside_transfer_table()
                .map_err(|why| Error::field("transfer.table", why))?;
            environment = Environment::Transfer {
                table: Arc::new(table),
                exact,
            };
        }

        let aspect = r.width as f32 / r.height as f32;
        let cam = resolve_camera(&file.camera.clone().unwrap_or_default(), &mesh, aspect)?;
        Ok(Scene {
            mesh: Arc::new(mesh),
            camera: cam,
            material,
            lights,
            render: r.clone(),
            output: file.output.clone(),
            environment,
            env,
        })
    }

    /// Every delta light shading sums: the scene's own (`lights`), then the environment's
    /// ([`Environment::delta_lights`]).
    pub fn delta_lights(&self) -> std::borrow::Cow<'_, [Light]> {
        let env = self.environment.delta_lights();
        if env.is_empty() {
            std::borrow::Cow::Borrowed(&self.lights)
        } else if self.lights.is_empty() {
            std::borrow::Cow::Borrowed(env)
        } else {
            std::borrow::Cow::Owned([self.lights.as_slice(), env].concat())
        }
    }

    /// The scene with its environment turned by `degrees` about world up (+y, right-handed,
    /// as `[env] rotation` turns it): built again from its `[env]` at the rotation
    /// `rotation + degrees` ([`build_environment`]; light sets and transfer tables come
    /// from `cache` when it holds them), so the result is the scene a file stating that
    /// rotation resolves to, for every method. An environment not made from a probe (a
    /// light set file, `[env] lights`; a `[transfer] table` file) is turned rigidly
    /// ([`Environment::turned_rigidly`]). Errors: those of building it.
    pub fn with_environment_turned(&self, degrees: f64, cache: &CacheDir) -> Result<Scene> {
        let mut s = self.clone();
        match &self.env {
            // Built from a probe by its `[env]` alone (no light set file, no table file).
            Some(e)
                if e.spec.lights.is_none() && self.environment.method() == Some(e.spec.method) =>
            {
                let mut spec = e.spec.clone();
                spec.rotation += degrees;
                let source = ProbeSource::Files {
                    base: &e.base,
                    cache,
                    progress: &Progress::hidden(),
                };
                (s.environment, s.env) = build_environment(&spec, &self.material, source)?;
            }
            _ => {
                s.environment = self
                    .environment
                    .turned_rigidly(degrees.to_radians())
                    .ok_or_else(|| {
                        Error::field(
                            "env.rotation",
                            format!(
                                "the environment ({}) is turned by building it again from its \
                                 probe, and this scene names none",
                                self.environment.name()
                            ),
                        )
                    })?;
            }
        }
        Ok(s)
    }

    /// The default scene (no file).
    pub fn default_scene() -> Scene {
        Scene::resolve(&SceneFile::default(), Path::new(".")).expect("the default scene is valid")
    }
}

/// The camera a scene's `[camera]` table places for a frame of aspect ratio `aspect`
/// (width / height) around `mesh`: [`Camera::frame`] fitted to the mesh, then each field the
/// table gives. Errors name the field (`camera.fov_y_deg`, ...). [`Scene::resolve`] places
/// its camera so; the viewer ([`crate::view`]) places each orbiting frame's camera so.
pub fn resolve_camera(spec: &super::CameraSpec, mesh: &Mesh, aspect: f32) -> Result<Camera> {
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
    Ok(cam)
}
