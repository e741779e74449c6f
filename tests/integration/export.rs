//! `brdfkit export`: the files read back as the scene they came from. The OBJ (through
//! tobj) equals the mesh; the exported matrices put every vertex where the rasterizer puts
//! it (1e-4 px) and where an independent f64 look-at and pinhole put it; the light set is
//! the one `brdfkit lights` writes after rotation and intensity, written once; every golden
//! entry's export (directional lights, UV spheres, transfer tables, AOVs) renders the
//! entry's bits as the golden check renders them; a transfer table that does not fit, or
//! is damaged, is refused in one line.
//!
//! (Past 400 lines because every test round-trips the one export through its readers, and
//! they share the scene, JSON and pixel helpers at the top.)

use brdfkit::golden;
use brdfkit::scene::env_method::export_unsupported;
use brdfkit::scene::{Scene, SceneFile};
use glam::{DMat4, DVec3, DVec4};
use std::path::Path;
use std::time::Instant;

use crate::common;

use common::{city_probe as probe, run_120s as run};

fn teapot_scene(dir: &Path) {
    std::fs::write(
        dir.join("s.toml"),
        format!(
            "[mesh]\nsegments = 6\n\
             [material]\nkind = \"blinn-phong\"\nexponent = 30.0\n\
             [[light]]\nkind = \"point\"\nposition = [2.5, 4.0, 3.0]\nintensity = 20.0\n\
             [env]\nfile = \"{}\"\nsampler = \"median-cut\"\ncount = 16\nrotation = 30.0\n\
             intensity = 1.5\nmethod = \"lights\"\n\
             [render]\nwidth = 64\nheight = 48\n",
            probe()
        ),
    )
    .unwrap();
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

fn f64s(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn bits(img: &brdfkit::image_io::Image) -> Vec<u32> {
    img.pixels
        .iter()
        .flat_map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// Pixel position of clip-space `c` by the documented viewport mapping.
fn to_pixel(c: DVec4, w: f64, h: f64) -> (f64, f64) {
    ((c.x / c.w * 0.5 + 0.5) * w, (0.5 - c.y / c.w * 0.5) * h)
}

#[test]
fn exported_files_read_back_as_the_scene() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    teapot_scene(p);
    let (code, out, err) = run(p, &["export", "s.toml", "-o", "gpu"]);
    assert_eq!(code, 0, "{out}{err}");
    let g = p.join("gpu");
    let scene = Scene::resolve(&SceneFile::load(&p.join("s.toml")).unwrap(), p).unwrap();
    let mesh = &scene.mesh;

    // The OBJ through tobj (which numbers vertices in order of first use): every corner of
    // every triangle has the mesh's position and normal, bit for bit, in the mesh's
    // triangle order and winding.
    let opts = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(g.join("mesh.obj"), &opts).unwrap();
    assert_eq!(models.len(), 1);
    let m = &models[0].mesh;
    assert_eq!(m.positions.len(), 3 * mesh.positions.len());
    assert_eq!(m.indices.len(), 3 * mesh.triangles.len());
    let at = |v: &[f32], i: u32| [0, 1, 2].map(|k| v[3 * i as usize + k].to_bits());
    for (k, &i) in mesh.triangles.iter().flatten().enumerate() {
        let (pi, ni) = (m.indices[k], m.normal_indices[k]);
        assert_eq!(
            at(&m.positions, pi),
            mesh.positions[i as usize].to_array().map(f32::to_bits),
            "corner {k}"
        );
        assert_eq!(
            at(&m.normals, ni),
            mesh.normals[i as usize].to_array().map(f32::to_bits),
            "corner {k}"
        );
    }

    // The camera: clip_from_world as exported, against the rasterizer's clip positions
    // mapped to pixels, its snapped positions, and an independent f64 pinhole.
    let cam = json(&g.join("camera.json"));
    let (w, h) = (
        cam["viewport"]["width"].as_f64().unwrap(),
        cam["viewport"]["height"].as_f64().unwrap(),
    );
    assert_eq!((w, h), (64.0, 48.0));
    let m_cols = f64s(&cam["clip_from_world"]);
    let clip_from_world = DMat4::from_cols_array(&m_cols.clone().try_into().unwrap());
    let transposed = clip_from_world.transpose(); // seeded fault: read row-major
    let raster_clip = brdfkit::render::clip_positions(&scene);
    let eye = DVec3::from_slice(&f64s(&cam["eye"]));
    let target = DVec3::from_slice(&f64s(&cam["target"]));
    let up = DVec3::from_slice(&f64s(&cam["up"]));
    let tan_half = (0.5 * cam["fov_y_deg"].as_f64().unwrap())
        .to_radians()
        .tan();
    let near = cam["near"].as_f64().unwrap();
    let fwd = (target - eye).normalize();
    let right = fwd.cross(up).normalize();
    let true_up = right.cross(fwd);
    let (mut worst_raster, mut worst_snap, mut worst_pinhole, mut worst_fault) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut projected = 0;
    for (i, v) in mesh.positions.iter().enumerate() {
        let pw = v.as_dvec3().extend(1.0);
        let c = clip_from_world * pw;
        if c.w <= near {
            continue;
        }
        projected += 1;
        let (x, y) = to_pixel(c, w, h);
        let rc = raster_clip[i].as_dvec4();
        let (rx, ry) = to_pixel(rc, w, h);
        worst_raster = worst_raster.max((x - rx).abs()).max((y - ry).abs());
        let (sx, sy) = brdfkit::raster::setup::snap(raster_clip[i], 64, 48);
        let one = brdfkit::raster::setup::ONE as f64;
        worst_snap = worst_snap
            .max((x - sx as f64 / one).abs())
            .max((y - sy as f64 / one).abs());
        // Pinhole: view-space depth along fwd, image plane at distance 1.
        let dv = v.as_dvec3() - eye;
        let z = dv.dot(fwd);
        let px = (dv.dot(right) / (z * tan_half * w / h) * 0.5 + 0.5) * w;
        let py = (0.5 - dv.dot(true_up) / (z * tan_half) * 0.5) * h;
        worst_pinhole = worst_pinhole.max((x - px).abs()).max((y - py).abs());
        // Depth convention: ndc_z = near / w.
        assert!((c.z / c.w - near / c.w).abs() < 1e-9);
        let (fx, fy) = to_pixel(transposed * pw, w, h);
        worst_fault = worst_fault.max((fx - rx).abs()).max((fy - ry).abs());
    }
    eprintln!(
        "{projected} vertices: exported vs rasterizer {worst_raster:.2e} px, vs snapped \
         {worst_snap:.2e} px, vs f64 pinhole {worst_pinhole:.2e} px; transposed {worst_fault:.1} px"
    );
    assert!(projected > 100);
    assert!(worst_raster <= 1e-4, "{worst_raster} px");
    assert!(worst_snap <= 0.5 / 256.0 + 1e-4, "{worst_snap} px");
    assert!(worst_pinhole <= 1e-3, "{worst_pinhole} px");
    assert!(worst_fault > 1.0, "a transposed matrix went unnoticed");

    // The light set: `brdfkit lights` with the scene's sampler and rotation, scaled by
    // the scene's intensity (one f32 product per value).
    let (code, out, err) = run(
        p,
        &[
            "lights",
            &probe(),
            "--sampler",
            "median-cut",
            "-n",
            "16",
            "--rotation",
            "30",
            "-o",
            "ref.json",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let (_, mut want) = brdfkit::env::lightset::file::read_json(&p.join("ref.json")).unwrap();
    want.scale_irradiance(1.5);
    let (_, got) = brdfkit::env::lightset::file::read_json(&g.join("lights.json")).unwrap();
    assert_eq!(got, want);
    // One copy of the environment's lights: scene_lights.json holds the scene's own light
    // and names lights.json for the other 16.
    assert!(
        !g.join("lights.csv").exists(),
        "a second copy of the light set"
    );
    let all = json(&g.join("scene_lights.json"));
    let own = all["lights"].as_array().unwrap();
    assert_eq!(own.len(), 1);
    assert_eq!(own[0]["kind"], "point");
    assert_eq!(f64s(&own[0]["intensity"]), vec![20.0; 3]);
    assert_eq!(all["env_lights"]["file"], "lights.json");
    assert_eq!(all["env_lights"]["count"], 16);

    // The exported scene renders the original frame's bits.
    for (scene, out) in [("s.toml", "a.exr"), ("gpu/scene.toml", "b.exr")] {
        let (code, o, e) = run(p, &["render", scene, "-o", out]);
        assert_eq!(code, 0, "{scene}: {o}{e}");
    }
    let a = brdfkit::image_io::read_exr(&p.join("a.exr")).unwrap();
    let b = brdfkit::image_io::read_exr(&p.join("b.exr")).unwrap();
    assert!(a.pixels.iter().any(|v| v.max_element() > 0.0));
    assert!(
        bits(&a) == bits(&b),
        "the exported scene renders other bits"
    );
}

#[test]
fn file_materials_are_copied_and_the_exact_sphere_is_named() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let sh = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden/magenta-plastic-5b-8x4.exr");
    std::fs::write(
        p.join("s.toml"),
        format!(
            "[mesh]\nsource = \"sphere\"\nsegments = 8\n\
             [material]\nkind = \"sh-file\"\npath = \"{}\"\n\
             [render]\nwidth = 32\nheight = 24\n",
            sh.display()
        ),
    )
    .unwrap();
    let (code, out, err) = run(p, &["export", "s.toml", "-o", "gpu"]);
    assert_eq!(code, 0, "{out}{err}");
    let g = p.join("gpu");
    assert_eq!(
        std::fs::read(g.join("material.exr")).unwrap(),
        std::fs::read(&sh).unwrap()
    );
    let m = json(&g.join("material.json"));
    assert_eq!(m["model"], "sh-dataset");
    assert_eq!(m["bands"], 5);
    assert_eq!(m["view_texels"], serde_json::json!([8, 4]));
    let e = json(&g.join("export.json"));
    assert_eq!(e["exact_sphere"]["radius"], 1.0);
    assert!(!g.join("lights.json").exists(), "no [env], no light set");
}

#[test]
fn unexportable_scenes_write_nothing() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(
        p.join("t.toml"),
        format!(
            "[material]\nkind = \"lambert\"\n[env]\nfile = \"{}\"\nmethod = \"lightcuts\"\n",
            probe()
        ),
    )
    .unwrap();
    let (code, _, err) = run(p, &["export", "t.toml", "-o", "gpu"]);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("t.toml") && err.contains("env.method"),
        "{err}"
    );
    let (code, _, err) = run(p, &["export", "missing.toml", "-o", "gpu"]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.toml"), "{err}");
    std::fs::write(p.join("bad.toml"), "[render]\nwidth = 0\n").unwrap();
    let (code, _, err) = run(p, &["export", "bad.toml", "-o", "gpu"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bad.toml") && err.contains("render.width"),
        "{err}"
    );
    assert!(!p.join("gpu").exists(), "nothing written");
}

/// Bytes of every file in `dir`.
fn dir_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len())
        .sum()
}

#[test]
fn every_golden_entry_exports_to_its_bits() {
    // Each entry of golden/manifest.toml exported by the command line (with its --aov),
    // then the export rendered as the golden check renders an entry (the scene file the
    // export wrote, the AOV its export.json names) against the original entry's render:
    // every bit must agree, on any machine (both renders are made here).
    let gold = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let manifest = golden::load_manifest(&gold).unwrap();
    assert!(manifest.entries.len() >= 30);
    let tmp = tempfile::tempdir().unwrap();
    let mut failed = Vec::new();
    let mut kinds = std::collections::BTreeSet::new();
    for e in &manifest.entries {
        let t = Instant::now();
        let out = tmp.path().join(&e.name);
        let scene = gold.join(&e.scene);
        let aov = e
            .aov
            .map(|a| serde_json::json!(a).as_str().unwrap().to_string());
        let mut args = vec![
            "export".to_string(),
            scene.display().to_string(),
            "-o".into(),
            out.display().to_string(),
        ];
        args.extend(aov.iter().flat_map(|a| ["--aov".to_string(), a.clone()]));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, o, err) = run(tmp.path(), &args);
        // A method export does not write (a reflection table: the `env-reflection-*`
        // entries, which the GPU build's tests need) is refused in one line naming the field.
        let method = SceneFile::load(&scene).unwrap().env.map(|env| env.method);
        if method.is_some_and(export_unsupported) {
            assert_eq!(code, 2, "{}: {o}{err}", e.name);
            assert_eq!(err.trim().lines().count(), 1, "{}: {err}", e.name);
            assert!(err.contains("env.method"), "{}: {err}", e.name);
            continue;
        }
        assert_eq!(code, 0, "{}: {o}{err}", e.name);
        let t_export = t.elapsed().as_secs_f64();
        let index = json(&out.join("export.json"));
        assert_eq!(index["aov"].as_str(), aov.as_deref(), "{}: aov", e.name);
        let exported = golden::Entry {
            scene: "scene.toml".into(),
            aov: serde_json::from_value(index["aov"].clone()).unwrap(),
            ..e.clone()
        };
        let want = golden::render_entry(&gold, e).unwrap();
        let got = golden::render_entry(&out, &exported).unwrap();
        assert_eq!((got.width, got.height), (want.width, want.height));
        let (mut differ, mut max_abs) = (0usize, 0.0f32);
        for (a, b) in want.pixels.iter().zip(&got.pixels) {
            if a.to_array().map(f32::to_bits) != b.to_array().map(f32::to_bits) {
                differ += 1;
                max_abs = max_abs.max((*a - *b).abs().max_element());
            }
        }
        // One copy of the lights: scene_lights.json holds the scene's own lights only.
        let own = SceneFile::load(&scene).unwrap().light_specs().len();
        let sl = json(&out.join("scene_lights.json"));
        assert_eq!(sl["lights"].as_array().unwrap().len(), own, "{}", e.name);
        assert!(!out.join("lights.csv").exists(), "{}", e.name);
        for f in ["transfer.json", "lights.json", "material.exr"] {
            if out.join(f).exists() {
                kinds.insert(f);
            }
        }
        if index["exact_sphere"].is_object() {
            kinds.insert("exact sphere");
        }
        eprintln!(
            "{}: {differ} of {} pixels differ (max abs {max_abs:.1e}); export {} bytes, \
             {t_export:.1} s, renders {:.1} s",
            e.name,
            want.pixels.len(),
            dir_bytes(&out),
            t.elapsed().as_secs_f64() - t_export
        );
        if differ > 0 {
            failed.push(format!("{}: {differ} pixels", e.name));
        }
    }
    // The set covers what the export must carry.
    assert_eq!(kinds.len(), 4, "{kinds:?}");
    assert!(
        failed.is_empty(),
        "exports that render other bits: {}",
        failed.join(", ")
    );
}

#[test]
fn a_transfer_table_that_does_not_fit_or_is_damaged_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let gold = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let scene = gold.join("env-transfer-lambert-studio.toml");
    let (code, out, err) = run(p, &["export", &scene.display().to_string(), "-o", "gpu"]);
    assert_eq!(code, 0, "{out}{err}");
    let g = p.join("gpu");
    let header = json(&g.join("transfer.json"));
    assert_eq!(header["basis"], "irradiance");
    assert_eq!(
        (header["nu"].as_u64(), header["nv"].as_u64()),
        (Some(128), Some(65))
    );
    // The rotation the lookup undoes: 60 degrees, as the f32 the table holds.
    assert_eq!(
        header["rotation_rad"].as_f64().unwrap() as f32,
        60.0f64.to_radians() as f32
    );
    assert_eq!(
        std::fs::metadata(g.join("transfer.bin")).unwrap().len(),
        4 * 128 * 65 * 3
    );
    let text = std::fs::read_to_string(g.join("scene.toml")).unwrap();
    // Another material: the table's one irradiance term does not fit Blinn-Phong.
    let other = text.replace(
        "albedo = [0.8, 0.8, 0.8]\nkind = \"lambert\"",
        "kind = \"blinn-phong\"",
    );
    assert_ne!(other, text);
    std::fs::write(g.join("other.toml"), other).unwrap();
    let (code, _, err) = run(&g, &["render", "other.toml", "-o", "o.exr"]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("other.toml") && err.contains("transfer.table") && err.contains("blinn-phong"),
        "{err}"
    );
    // One value's bit flipped: the header's checksum refuses it.
    let mut bin = std::fs::read(g.join("transfer.bin")).unwrap();
    bin[4 * 1000] ^= 1;
    std::fs::write(g.join("transfer.bin"), &bin).unwrap();
    let (code, _, err) = run(&g, &["render", "scene.toml", "-o", "o.exr"]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("transfer.json") && err.contains("checksum"),
        "{err}"
    );
    assert!(!g.join("o.exr").exists());
}
