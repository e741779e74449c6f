//! `brdfkit export`: what a GPU build needs to draw the same frame as the oracle, written
//! into one directory from a resolved scene.
//!
//! Design rule: every file holds resolved values, each f32 in its shortest round-trip
//! decimal form (or raw bits), and each value is written once; `scene.toml` reads those
//! files back, or keeps what the scene wrote where the resolver's own arithmetic must run
//! again to give the same bits (the `[[light]]` tables as written, a UV sphere's
//! `[mesh]`), so `brdfkit render DIR/scene.toml` gives the original frame's bits.
//!
//! Files (all written only after the whole scene has resolved, each atomically):
//! - `camera.json`: eye, target, up, vertical field of view, near plane, viewport, the
//!   `view_from_world`, `clip_from_view` and `clip_from_world` matrices exactly as the
//!   rasterizer builds them (f32, column-major, column vectors), and the conventions that
//!   turn clip space into pixels ([`CONVENTIONS`]).
//! - `mesh.obj`: the triangles with per-vertex normals (`v`, `vn`, `f a//a b//b c//c`,
//!   1-based, one normal per position); winding counter-clockwise seen from the side the
//!   normals point to, in the right-handed world ([`crate::mesh::Mesh`]). An OBJ mesh's
//!   texture coordinates follow as `vt` (faces `f a/a/a ...`), and a mesh with tangents
//!   (the frame of anisotropic materials) lists them as `# vtan x y z` comments, one per
//!   `v`.
//! - `scene_lights.json`: the scene's own lights (its `[[light]]` tables, or the default
//!   light), in shading order: directional lights with their unit `to_light` and RGB
//!   irradiance (W/m^2), point lights with their position and RGB intensity (W/sr); and
//!   `env_lights`, which names `lights.json` and its count (shaded after these).
//! - `lights.json` (when the scene has an `[env]`): the environment's delta lights in the
//!   light-set format of `brdfkit lights -o` ([`crate::env::lightset::file`]), after the
//!   scene's `rotation` and `intensity` (world directions, irradiances as shaded); for
//!   `method = "transfer"` the brightest texels the table leaves out. The one copy of them.
//! - `transfer.json` and `transfer.bin` (when the scene shades with a transfer table):
//!   the table's header and raw f32 values ([`crate::env::transfer::file`]).
//! - `material.json`: the material's model and parameters; an SH data set or D-BRDF is
//!   also written (or copied) as `material.exr` in its own format ([`crate::sh::file`],
//!   [`crate::brdf::dbrdf::file`]).
//! - `scene.toml`: the scene resolved: the same `[render]` and `[output]` (no output path),
//!   `mesh.source = "mesh.obj"` (a UV sphere keeps its `[mesh]`: its shading intersects the
//!   exact sphere, which an OBJ cannot carry; so does the teapot, whose tangents come from
//!   its patches), the camera stated in full, the `[[light]]`
//!   tables as written, `[env] lights = "lights.json"`, `[transfer] table =
//!   "transfer.json"`, and the material (a file material pointing to `material.exr`).
//! - `export.json`: the list of files, the AOV the frame is (`--aov`, if any) and the
//!   command that renders it, and the notes a file cannot say itself (the exact sphere).
//!
//! Refused (an error naming the field, nothing written): `[env] method = "lightcuts"` (a
//! light tree is refined per pixel; neither a light set nor a table holds it).

mod camera;
mod lights;
mod material;
mod mesh;

pub use camera::{camera_json, CONVENTIONS};
pub use mesh::mesh_obj;

use crate::aov::Aov;
use crate::env::schema::EnvMethod;
use crate::error::{Error, Result};
use crate::scene::{env_method, Scene, SceneFile};
use camera::{fa, fj};
use glam::Vec3;
use serde_json::json;
use std::path::{Path, PathBuf};

/// The f32 as a TOML float that reads back as the same f32: its shortest round-trip
/// decimal form (Rust's `Display`), not the f64 widening's 17 digits.
fn f32_value(x: f32) -> toml::Value {
    toml::Value::Float(x.to_string().parse::<f64>().expect("an f32's decimal form"))
}

fn vec_value(v: Vec3) -> toml::Value {
    toml::Value::Array(v.to_array().map(f32_value).to_vec())
}

/// The transfer table's header and values files.
const TRANSFER_JSON: &str = "transfer.json";
const TRANSFER_BIN: &str = "transfer.bin";

/// What [`export`] wrote.
#[derive(Debug)]
pub struct Exported {
    pub files: Vec<PathBuf>,
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    crate::image_io::write_atomic(path, text.as_bytes())
        .map_err(|e| Error::io(path, "cannot write", e))
}

fn pretty(v: &serde_json::Value) -> String {
    serde_json::to_string_pretty(v).expect("JSON values serialize") + "\n"
}

/// The AOV's name as `--aov` takes it (`light-polar`).
fn aov_name(aov: Aov) -> String {
    json!(aov).as_str().expect("an AOV is a string").to_string()
}

/// Exports the scene file `scene_path` into `dir` (created if missing); `aov`, the debug
/// output the frame is (a golden entry's `aov`), is recorded in `export.json` and
/// `scene.toml`'s header with the command that renders it. The scene is resolved first
/// (errors name the scene file and field); nothing is written unless it resolves and its
/// environment is exportable, and no file appears in `dir` unless all were written (they
/// are staged in a temporary directory inside `dir`, then moved).
pub fn export(scene_path: &Path, dir: &Path, aov: Option<Aov>) -> Result<Exported> {
    let text = crate::image_io::read_regular_text(
        scene_path,
        crate::scene::MAX_SCENE_BYTES,
        "scene file",
    )?;
    let mut file = SceneFile::parse(&text).map_err(|m| Error::format(scene_path, m))?;
    let base = scene_path.parent().unwrap_or(Path::new("."));
    // `auto` made concrete: it may stand for light cuts.
    let auto = file
        .env
        .as_ref()
        .is_some_and(|e| e.method == EnvMethod::Auto);
    file.resolve_env_method();
    // Export writes delta lights, or a transfer table and its exact lights; a light tree
    // and a reflection-space table are neither.
    let refused = file
        .env
        .as_ref()
        .filter(|e| env_method::export_unsupported(e.method));
    if let Some(env) = refused {
        let why = if auto {
            format!(
                "env.method: \"auto\" is \"{}\" for this material ({}), and export writes \
                 delta lights or a transfer table (state method = \"lights\" with a sampler \
                 and count, or \"transfer\")",
                env.method.name(),
                env.method.prepares()
            )
        } else {
            format!(
                "env.method: export writes delta lights or a transfer table, and \"{}\" is \
                 {} (use method = \"lights\" or \"transfer\")",
                env.method.name(),
                env.method.prepares()
            )
        };
        return Err(Error::format(scene_path, why));
    }
    let scene = Scene::resolve(&file, base).map_err(|e| match e {
        Error::Field { .. } => Error::format(scene_path, e.to_string()),
        other => other,
    })?;
    let mut raw: toml::Table =
        toml::from_str(&text).map_err(|e| Error::format(scene_path, e.to_string()))?;
    if dir.exists() && !dir.is_dir() {
        return Err(Error::format(dir, "-o: exists and is not a directory"));
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "cannot create directory", e))?;
    // Every file is written into a staging directory inside `dir` and moved beside it only
    // when all are written: a failure leaves none of them (the staging directory is removed
    // on drop).
    let staging = tempfile::Builder::new()
        .prefix(".brdfkit-export-")
        .tempdir_in(dir)
        .map_err(|e| Error::io(dir, "cannot create a staging directory in", e))?;
    let final_dir = dir;
    let dir = staging.path();
    let mut files = Vec::new();
    let put = |files: &mut Vec<PathBuf>, name: &str, text: &str| -> Result<()> {
        let p = dir.join(name);
        write_text(&p, text)?;
        files.push(p);
        Ok(())
    };

    put(&mut files, "camera.json", &pretty(&camera_json(&scene)))?;
    put(&mut files, "mesh.obj", &mesh::mesh_obj(&scene))?;
    // A UV sphere keeps its `[mesh]` (the exact sphere is rebuilt from it), and so does a
    // mesh whose tangents do not come from texture coordinates (the teapot's, from its
    // patches: an OBJ reader would not rebuild them); every other mesh reads the OBJ, which
    // holds its positions, normals and texture coordinates bit for bit.
    let rebuilt_from_table = scene.mesh.exact_sphere.is_some()
        || (!scene.mesh.tangents.is_empty() && scene.mesh.texcoords.is_empty());
    if !rebuilt_from_table {
        let mut mesh = toml::Table::new();
        mesh.insert("source".into(), "mesh.obj".into());
        raw.insert("mesh".into(), mesh.into());
    }

    // The scene's own lights (`scene.lights`) and the environment's delta lights (a light
    // set, or a transfer table's exact lights). The `[[light]]` tables stay as written: the resolver normalises `to_light` and
    // multiplies `color` by `intensity`, and only the same operands give the same bits (a
    // normalised f32 vector normalised again may change in its last bit).
    let (own, env_lights) = (&scene.lights, scene.environment.delta_lights());
    put(
        &mut files,
        "scene_lights.json",
        &pretty(&lights::scene_lights_json(
            own,
            file.env.as_ref().map(|_| env_lights.len()),
        )),
    )?;
    if let Some(spec) = &file.env {
        files.push(lights::write_env_lights(dir, spec, base, env_lights)?);
        let mut env = toml::Table::new();
        env.insert("lights".into(), lights::ENV_LIGHTS.into());
        env.insert("method".into(), "lights".into());
        raw.insert("env".into(), env.into());
    }
    raw.remove("transfer");
    if let Some(table) = scene.environment.transfer_table() {
        let (j, b) = (dir.join(TRANSFER_JSON), dir.join(TRANSFER_BIN));
        crate::env::transfer::file::write_table(&j, &b, table)?;
        files.extend([j, b]);
        let mut t = toml::Table::new();
        t.insert("table".into(), TRANSFER_JSON.into());
        raw.insert("transfer".into(), t.into());
    }

    let data_file = material::write_data_file(&file.material, &scene, base, scene_path, dir)?;
    let data_name = data_file
        .as_ref()
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned());
    files.extend(data_file);
    put(
        &mut files,
        "material.json",
        &pretty(&material::material_json(
            &scene.material,
            data_name.as_deref(),
        )),
    )?;
    // A file material now reads the written copy (same data); a library or analytic
    // material stays as the scene wrote it.
    if let Some(toml::Value::Table(m)) = raw.get_mut("material") {
        if m.contains_key("path") && data_name.as_deref() == Some("material.exr") {
            m.insert("path".into(), "material.exr".into());
        }
    }

    let c = &scene.camera;
    let mut cam = toml::Table::new();
    cam.insert("position".into(), vec_value(c.position));
    cam.insert("target".into(), vec_value(c.target));
    cam.insert("up".into(), vec_value(c.up));
    cam.insert("fov_y_deg".into(), f32_value(c.fov_y_deg));
    cam.insert("near".into(), f32_value(c.near));
    raw.insert("camera".into(), cam.into());
    if let Some(toml::Value::Table(o)) = raw.get_mut("output") {
        o.remove("path");
    }
    let render = match aov {
        Some(a) => format!("brdfkit render scene.toml --aov {}", aov_name(a)),
        None => "brdfkit render scene.toml".to_string(),
    };
    let scene_toml = format!(
        "# brdfkit export of {}: the scene resolved (camera stated, mesh, lights and tables as \
         files).\n# The frame: `{render}` (in this directory).\n{}",
        scene_path.display(),
        toml::to_string(&raw).map_err(|e| Error::Message(format!("scene.toml: {e}")))?
    );
    put(&mut files, "scene.toml", &scene_toml)?;

    let names: Vec<String> = files
        .iter()
        .chain(std::iter::once(&dir.join("export.json")))
        .filter_map(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .collect();
    let index = json!({
        "source": scene_path.display().to_string(),
        "files": names,
        "aov": aov.map(aov_name),
        "render": render,
        "exact_sphere": scene.mesh.exact_sphere.as_ref().map(|s| json!({
            "center": fa(&s.center.to_array()),
            "radius": fj(s.radius),
            "note": "shading intersects each pixel's camera ray with this sphere instead of \
                     interpolating the facets of mesh.obj",
        })),
    });
    put(&mut files, "export.json", &pretty(&index))?;
    let mut moved = Vec::with_capacity(files.len());
    for f in files {
        let to = final_dir.join(f.file_name().expect("a file name"));
        std::fs::rename(&f, &to).map_err(|e| Error::io(&to, "cannot move into place", e))?;
        moved.push(to);
    }
    Ok(Exported { files: moved })
}
