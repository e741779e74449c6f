//! `brdfkit export`: what a GPU build needs to draw the same frame as the oracle, written
//! into one directory from a resolved scene.
//!
//! Files (all written only after the whole scene has resolved, each atomically):
//! - `camera.json`: eye, target, up, vertical field of view, near plane, viewport, the
//!   `view_from_world`, `clip_from_view` and `clip_from_world` matrices exactly as the
//!   rasterizer builds them (f32, column-major, column vectors), and the conventions that
//!   turn clip space into pixels ([`CONVENTIONS`]).
//! - `mesh.obj`: the triangles with per-vertex normals (`v`, `vn`, `f a//a b//b c//c`,
//!   1-based, one normal per position); winding counter-clockwise seen from the side the
//!   normals point to, in the right-handed world ([`crate::mesh::Mesh`]).
//! - `lights.json` and `lights.csv` (when the scene has an `[env]`): the environment's
//!   delta lights in the light-set format of `brdfkit lights -o`
//!   ([`crate::env::lightset_io`]), after the scene's `rotation` and `intensity` (world
//!   directions, irradiances as shaded).
//! - `scene_lights.json`: every light the frame is shaded with, in shading order (the
//!   scene's `[[light]]` tables, then the environment's): directional lights with their
//!   unit `to_light` and RGB irradiance (W/m^2), point lights with their position and RGB
//!   intensity (W/sr).
//! - `material.json`: the material's model and parameters; an SH data set or D-BRDF is
//!   also written (or copied) as `material.exr` in its own format ([`crate::sh::file`],
//!   [`crate::brdf::dbrdf::file`]).
//! - `scene.toml`: the scene resolved: the same `[render]` and `[output]` (no output path),
//!   `mesh.source = "mesh.obj"`, the camera stated in full, the `[[light]]` tables as
//!   resolved, `[env] lights = "lights.json"`, and the material (a file material pointing to
//!   `material.exr`). `brdfkit render DIR/scene.toml` gives the original frame's bits, except
//!   for a UV sphere, whose exact surface (`export.json`) an OBJ cannot carry.
//! - `export.json`: the list of files and the notes above that a file cannot say itself
//!   (the exact sphere, if any).
//!
//! Refused (an error naming the field, nothing written): `[env] method` `transfer` or
//! `lightcuts` (a light set cannot hold a transfer table or a light tree).

mod camera;

pub use camera::{camera_json, CONVENTIONS};
use camera::{fa, fj};

use crate::env::lightset_io::{write_csv, write_json, LightSetHeader};
use crate::env::prepare::EnvMethod;
use crate::env::LightSet;
use crate::error::{Error, Result};
use crate::light::Light;
use crate::material::Material;
use crate::scene::{Scene, SceneFile};
use glam::Vec3;
use serde_json::json;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The f32 as a TOML float that reads back as the same f32: its shortest round-trip
/// decimal form (Rust's `Display`), not the f64 widening's 17 digits.
fn f32_value(x: f32) -> toml::Value {
    toml::Value::Float(x.to_string().parse::<f64>().expect("an f32's decimal form"))
}

fn vec_value(v: Vec3) -> toml::Value {
    toml::Value::Array(v.to_array().map(f32_value).to_vec())
}

/// The mesh as OBJ text: one `vn` per `v` (same index), faces `f a//a b//b c//c`.
pub fn mesh_obj(scene: &Scene) -> String {
    let m = &scene.mesh;
    let mut s = String::with_capacity(64 * (m.positions.len() * 2 + m.triangles.len()));
    s.push_str(
        "# brdfkit export: world-space triangles with unit per-vertex normals (vn i belongs \
         to v i).\n# Winding: counter-clockwise seen from the side the normals point to \
         (right-handed world, +y up).\n",
    );
    if let Some(sp) = &m.exact_sphere {
        let _ = writeln!(
            s,
            "# Shading intersects the exact sphere (centre {:?}, radius {}) per pixel, not these facets.",
            sp.center.to_array(),
            sp.radius
        );
    }
    for p in &m.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in &m.normals {
        let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
    }
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
    }
    s
}

/// Every light the frame is shaded with, in order, as `scene_lights.json`.
fn scene_lights_json(lights: &[Light]) -> serde_json::Value {
    let list: Vec<serde_json::Value> = lights
        .iter()
        .map(|l| match l {
            Light::Directional {
                to_light,
                irradiance,
            } => json!({
                "kind": "directional",
                "to_light": fa(&to_light.to_array()),
                "irradiance": fa(&irradiance.to_array()),
            }),
            Light::Point {
                position,
                intensity,
            } => json!({
                "kind": "point",
                "position": fa(&position.to_array()),
                "intensity": fa(&intensity.to_array()),
            }),
        })
        .collect();
    json!({ "lights": list })
}

/// Directional lights as a light set (bit-exact: the inverse of
/// [`crate::env::prepare::to_scene_lights`]).
fn light_set_of(lights: &[Light]) -> LightSet {
    let mut ls = LightSet::default();
    for l in lights {
        if let Light::Directional {
            to_light,
            irradiance,
        } = l
        {
            ls.dir_x.push(to_light.x);
            ls.dir_y.push(to_light.y);
            ls.dir_z.push(to_light.z);
            ls.irradiance_r.push(irradiance.x);
            ls.irradiance_g.push(irradiance.y);
            ls.irradiance_b.push(irradiance.z);
        }
    }
    ls
}

/// A D-BRDF's constants and table size (thesis 2.3.6; the table itself is in the file).
fn dbrdf_json(d: &crate::brdf::dbrdf::DBrdf) -> serde_json::Value {
    json!({ "c": fj(d.c), "rs": fa(&d.rs.to_array()), "half_vector_texels": d.grid() })
}

/// The material's model and parameters (`material.json`); `file` names the written data
/// file, if any.
fn material_json(m: &Material, file: Option<&str>) -> serde_json::Value {
    let mut v = match m {
        Material::Lambert(l) => json!({ "albedo": fa(&l.albedo.to_array()) }),
        Material::Phong(p) => json!({
            "kd": fa(&p.kd.to_array()), "ks": fa(&p.ks.to_array()), "exponent": fj(p.exponent),
        }),
        Material::BlinnPhong(p) => json!({
            "kd": fa(&p.kd.to_array()), "ks": fa(&p.ks.to_array()), "exponent": fj(p.exponent),
        }),
        Material::AshikhminShirley(a) => json!({
            "nu": fj(a.nu), "nv": fj(a.nv), "rs": fa(&a.rs.to_array()), "rd": fa(&a.rd.to_array()),
        }),
        Material::LambertDbrdf(l) => json!({
            "rd": fa(&l.rd.to_array()),
            "lobe": dbrdf_json(&l.lobe),
        }),
        Material::DBrdf(d) => dbrdf_json(d),
        Material::Sh(ds) => json!({
            "bands": ds.bands(),
            "view_texels": ds.grid(),
            "coeff_lookup": ds.coeff_lookup,
            "cosine_included": ds.cosine_included(),
        }),
        Material::Merl(_) => json!({}),
    };
    v["model"] = json!(m.name());
    v["file"] = json!(file);
    if matches!(m, Material::Merl(_)) {
        v["note"] = json!("MERL tables are not exported: use the scene's table file");
    }
    v
}

/// What [`export`] wrote.
#[derive(Debug)]
pub struct Exported {
    pub files: Vec<PathBuf>,
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    crate::env::lightset_io::write_atomic(path, text.as_bytes())
        .map_err(|e| Error::io(path, "cannot write", e))
}

fn pretty(v: &serde_json::Value) -> String {
    serde_json::to_string_pretty(v).expect("JSON values serialize") + "\n"
}

/// Exports the scene file `scene_path` into `dir` (created if missing). The scene is
/// resolved first (errors name the scene file and field); nothing is written unless it
/// resolves and its environment is exportable, and no file appears in `dir` unless all
/// were written (they are staged in a temporary directory inside `dir`, then moved).
pub fn export(scene_path: &Path, dir: &Path) -> Result<Exported> {
    let text = crate::image_io::read_regular_text(
        scene_path,
        crate::scene::MAX_SCENE_BYTES,
        "scene file",
    )?;
    let mut file = SceneFile::parse(&text).map_err(|m| Error::format(scene_path, m))?;
    let base = scene_path.parent().unwrap_or(Path::new("."));
    // `auto` made concrete: it may stand for a transfer table or light cuts.
    let auto = file
        .env
        .as_ref()
        .is_some_and(|e| e.method == EnvMethod::Auto);
    file.resolve_env_method();
    if let Some(env) = &file.env {
        if matches!(env.method, EnvMethod::Transfer | EnvMethod::Lightcuts) {
            let why = if auto {
                format!(
                    "env.method: \"auto\" is \"{}\" for this material, and export writes delta \
                     lights; a transfer table or light tree is not a light set (state method = \
                     \"lights\" with a sampler and count)",
                    env.method.name()
                )
            } else {
                "env.method: export writes delta lights; a transfer table or light tree is \
                 not a light set (use method = \"lights\")"
                    .to_string()
            };
            return Err(Error::format(scene_path, why));
        }
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
    put(&mut files, "mesh.obj", &mesh_obj(&scene))?;
    put(
        &mut files,
        "scene_lights.json",
        &pretty(&scene_lights_json(&scene.lights)),
    )?;

    // The scene's own lights come first in `scene.lights`, the environment's after them.
    let n_own = file.light_specs().len();
    let (own, env_lights) = scene.lights.split_at(n_own);
    if let Some(spec) = &file.env {
        let ls = light_set_of(env_lights);
        let t = ls.total_irradiance();
        let header = LightSetHeader {
            sampler: match &spec.lights {
                Some(_) => "file".to_string(),
                None => spec.sampler_config().name().to_string(),
            },
            n: ls.len(),
            seed: spec.lights.is_none().then_some(spec.seed),
            probe_file: Some(base.join(&spec.file).display().to_string()),
            total_irradiance: [t.x, t.y, t.z],
        };
        let (j, c) = (dir.join("lights.json"), dir.join("lights.csv"));
        write_json(&j, &header, &ls).map_err(|e| Error::Message(e.to_string()))?;
        write_csv(&c, &ls).map_err(|e| Error::Message(e.to_string()))?;
        files.extend([j, c]);
        let mut env = toml::Table::new();
        env.insert("lights".into(), "lights.json".into());
        env.insert("method".into(), "lights".into());
        raw.insert("env".into(), env.into());
    }
    let own_tables: Vec<toml::Value> = own
        .iter()
        .map(|l| {
            let mut t = toml::Table::new();
            match l {
                Light::Directional {
                    to_light,
                    irradiance,
                } => {
                    t.insert("kind".into(), "directional".into());
                    t.insert("to_light".into(), vec_value(*to_light));
                    t.insert("color".into(), vec_value(*irradiance));
                }
                Light::Point {
                    position,
                    intensity,
                } => {
                    t.insert("kind".into(), "point".into());
                    t.insert("position".into(), vec_value(*position));
                    t.insert("color".into(), vec_value(*intensity));
                }
            }
            // color x 1.0 is the resolved value's bits.
            t.insert("intensity".into(), f32_value(1.0));
            t.into()
        })
        .collect();
    if own_tables.is_empty() {
        raw.remove("light");
    } else {
        raw.insert("light".into(), toml::Value::Array(own_tables));
    }

    // The material: a data set copied (file materials) or written (library materials)
    // beside the scene as material.exr.
    let source_file = match &file.material {
        crate::scene::MaterialSpec::ShFile { path, .. }
        | crate::scene::MaterialSpec::DbrdfFile { path } => Some(base.join(path)),
        _ => None,
    };
    let data_file = match &scene.material {
        _ if source_file.is_some() => {
            let src = source_file.as_deref().expect("checked");
            let bytes = crate::image_io::read_regular_file(
                src,
                crate::image_io::MAX_EXR_FILE_BYTES,
                "material file",
            )?;
            let p = dir.join("material.exr");
            crate::env::lightset_io::write_atomic(&p, &bytes)
                .map_err(|e| Error::io(&p, "cannot write", e))?;
            Some(p)
        }
        Material::Sh(ds) => {
            let p = dir.join("material.exr");
            crate::sh::file::write_sh_dataset(&p, ds).map_err(|e| Error::Message(e.to_string()))?;
            Some(p)
        }
        Material::DBrdf(d) => {
            let p = dir.join("material.exr");
            crate::brdf::dbrdf::file::write_dbrdf(
                &p,
                d,
                &format!("brdfkit export of {}", scene_path.display()),
            )
            .map_err(|e| Error::Message(e.to_string()))?;
            Some(p)
        }
        Material::LambertDbrdf(l) => {
            let p = dir.join("material-lobe.exr");
            crate::brdf::dbrdf::file::write_dbrdf(
                &p,
                &l.lobe,
                &format!("brdfkit export of {} (lobe)", scene_path.display()),
            )
            .map_err(|e| Error::Message(e.to_string()))?;
            Some(p)
        }
        _ => None,
    };
    let data_name = data_file
        .as_ref()
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned());
    if let Some(p) = data_file {
        files.push(p);
    }
    put(
        &mut files,
        "material.json",
        &pretty(&material_json(&scene.material, data_name.as_deref())),
    )?;
    // A file material now reads the written copy (same data); a library or analytic
    // material stays as the scene wrote it.
    if let Some(toml::Value::Table(m)) = raw.get_mut("material") {
        if m.contains_key("path") && data_name.as_deref() == Some("material.exr") {
            m.insert("path".into(), "material.exr".into());
        }
    }

    let mut mesh = toml::Table::new();
    mesh.insert("source".into(), "mesh.obj".into());
    raw.insert("mesh".into(), mesh.into());
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
    let scene_toml = format!(
        "# brdfkit export of {}: the scene resolved (camera stated, mesh and lights as \
         files).\n{}",
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
