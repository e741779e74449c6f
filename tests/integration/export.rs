//! `brdfkit export`: the files read back as the scene they came from. The OBJ (through
//! tobj) equals the mesh; the exported matrices put every vertex where the rasterizer puts
//! it (1e-4 px) and where an independent f64 look-at and pinhole put it; the light set is
//! the one `brdfkit lights` writes after rotation and intensity; the exported scene renders
//! the original frame's bits.

use brdfkit::scene::{Scene, SceneFile};
use glam::{DMat4, DVec3, DVec4};
use std::path::Path;

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
    let (_, mut want) = brdfkit::env::lightset_io::read_json(&p.join("ref.json")).unwrap();
    want.scale_irradiance(1.5);
    let (_, got) = brdfkit::env::lightset_io::read_json(&g.join("lights.json")).unwrap();
    assert_eq!(got, want);
    assert_eq!(
        brdfkit::env::lightset_io::read_csv(&g.join("lights.csv")).unwrap(),
        want
    );
    let all = json(&g.join("scene_lights.json"));
    let all = all["lights"].as_array().unwrap();
    assert_eq!(all.len(), 17);
    assert_eq!(all[0]["kind"], "point");
    assert_eq!(f64s(&all[0]["intensity"]), vec![20.0; 3]);

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
            "[material]\nkind = \"lambert\"\n[env]\nfile = \"{}\"\nmethod = \"transfer\"\n",
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
