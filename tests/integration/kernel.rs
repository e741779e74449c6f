//! The kernels against the scalar oracle, and the work they skip against not skipping it.

use crate::shading_paths;

use brdfkit::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use brdfkit::kernel::{KERNEL_TOLERANCE, SH_KERNEL_TOLERANCE};
use brdfkit::lanes::{Dispatch, KernelPath};
use brdfkit::render;
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use brdfkit::shade::{self, FramePrep, ShadeOptions};
use shading_paths::scalar_oracle;
use std::path::Path;

fn scene(material: MaterialSpec, lights: usize) -> Scene {
    let mut f = SceneFile::default();
    f.render.width = 64;
    f.render.height = 48;
    f.material = material;
    let mut env =
        EnvSpec::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr"));
    env.sampler = SamplerKind::MedianCut;
    env.count = lights;
    env.method = EnvMethod::Lights;
    f.env = Some(env);
    // Plus a point light, which takes the scalar path inside the kernel's frame loop.
    f.lights = Some(
        SceneFile::parse(
            "[[light]]\nkind = \"point\"\nposition = [3.0, 5.0, 4.0]\nintensity = 10.0\n",
        )
        .unwrap()
        .lights
        .unwrap(),
    );
    Scene::resolve(&f, Path::new("/")).unwrap()
}

/// Where a failing comparison leaves its `expected | difference | actual` strip.
fn failure_png(what: &str) -> std::path::PathBuf {
    let name: String = what
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target/kernel-failures")
        .join(format!("{name}.png"))
}

fn assert_close(
    a: &brdfkit::image_io::Image,
    oracle: &brdfkit::image_io::Image,
    tol: f32,
    what: &str,
) {
    let mut worst = 0.0f32;
    let mut failed = None;
    let peak = oracle
        .pixels
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0f32, f32::max);
    for (p, q) in a.pixels.iter().zip(&oracle.pixels) {
        let d = (*p - *q).abs().max_element();
        // Relative to the pixel, or to 1% of the image's peak where SH terms cancel.
        let scale = q.abs().max_element().max(1e-2 * peak);
        worst = worst.max(d / scale);
        // Written so that a NaN difference fails.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        let over = !(d <= tol * scale + 1e-6);
        if over && failed.is_none() {
            failed = Some(format!("{what}: kernel {p:?} vs oracle {q:?}"));
        }
    }
    if let Some(msg) = failed {
        let png = failure_png(what);
        std::fs::create_dir_all(png.parent().unwrap()).unwrap();
        brdfkit::golden::write_triptych(&png, oracle, a).unwrap();
        panic!(
            "{msg} (worst relative difference {worst:.2e}; oracle | difference | kernel in {})",
            png.display()
        );
    }
    assert!(
        oracle
            .pixels
            .iter()
            .filter(|p| p.max_element() > 0.0)
            .count()
            > 500,
        "{what}: too few lit pixels"
    );
    eprintln!("{what}: worst relative difference {worst:.2e}");
}

/// The fast path on every instruction set this CPU runs (portable, AVX2, AVX-512).
fn every_path(
    s: &Scene,
    vis: &brdfkit::raster::VisBuffer,
) -> Vec<(String, brdfkit::image_io::Image)> {
    let on = |d: Dispatch| {
        let opts = ShadeOptions {
            kernel: Some(d.path()),
            ..ShadeOptions::default()
        };
        (d.name().to_string(), shade::shade(s, vis, &opts).image)
    };
    assert_eq!(
        FramePrep::new(s).dispatch().path(),
        Dispatch::detect().path(),
        "a frame takes the widest path by default"
    );
    let paths = crate::common::kernel_paths("kernel");
    assert!(paths.contains(&KernelPath::Portable));
    paths
        .into_iter()
        .map(|p| on(Dispatch::choose(p).unwrap()))
        .collect()
}

#[test]
fn sh_kernel_matches_scalar_oracle_for_library_materials() {
    for name in [
        "blue-silk",
        "magenta-plastic",
        "gold-dust-paint-sh-ringing",
        "red-velvet",
    ] {
        let s = scene(
            MaterialSpec::Library {
                name: name.into(),
                lookup: None,
            },
            64,
        );
        assert!(
            s.material.as_sh().is_some(),
            "{name} should be an SH data set"
        );
        let vis = render::rasterize(&s, false);
        let oracle = scalar_oracle(&s, &vis);
        for (path, img) in every_path(&s, &vis) {
            assert_close(
                &img,
                &oracle,
                SH_KERNEL_TOLERANCE,
                &format!("{name} {path}"),
            );
        }
    }
}

#[test]
fn generic_kernel_matches_scalar_oracle_for_analytic_materials() {
    for m in [
        "[material]\nkind = \"lambert\"\n",
        "[material]\nkind = \"blinn-phong\"\nexponent = 200.0\n",
        "[material]\nkind = \"library\"\nname = \"lindt-paper\"\n",
    ] {
        let spec = SceneFile::parse(m).unwrap().material;
        let s = scene(spec, 128);
        let vis = render::rasterize(&s, false);
        let oracle = scalar_oracle(&s, &vis);
        for (path, img) in every_path(&s, &vis) {
            let what = format!("{} {path}", m.trim());
            assert_close(&img, &oracle, KERNEL_TOLERANCE, &what);
        }
    }
}

#[test]
fn normal_cone_culling_changes_no_bit_and_skips_work() {
    for name in ["blue-silk", "magenta-plastic"] {
        let s = scene(
            MaterialSpec::Library {
                name: name.into(),
                lookup: None,
            },
            256,
        );
        let vis = render::rasterize(&s, false);
        let culled = shade::shade(&s, &vis, &ShadeOptions::default()).image;
        let no_culling = ShadeOptions {
            cull_lights: false,
            ..ShadeOptions::default()
        };
        let full = shade::shade(&s, &vis, &no_culling).image;
        assert!(culled == full, "{name}: culling changed the image");
    }
    // And it does skip: city's lights are mostly in the sky, so a tile of downward normals
    // (the teapot's underside) drops most chunks.
    let s = scene(
        MaterialSpec::Library {
            lookup: None,
            name: "magenta-plastic".into(),
        },
        256,
    );
    let prep = FramePrep::new(&s);
    let down = brdfkit::kernel::cluster::Cone::around(
        [-glam::Vec3::Y, glam::Vec3::new(0.1, -0.99, 0.0).normalize()].into_iter(),
    )
    .unwrap();
    let kept = prep.dir.chunks_for(Some(down)).len();
    let all = prep.dir.chunks_for(None).len();
    assert!(
        kept * 2 < all,
        "only {} of {all} chunks culled for a downward tile",
        all - kept
    );
}

#[test]
fn kernels_match_scalar_oracle_on_golden_light_sets() {
    // Bright studio lights (a wide dynamic range) and many weak uniform ones.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    for name in ["fig3-8-lloyd-studio", "fig3-6-uniform-city"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.toml"))).unwrap();
        let f = SceneFile::parse(&text).unwrap();
        let s = Scene::resolve(&f, &dir).unwrap();
        let vis = render::rasterize(&s, false);
        let oracle = scalar_oracle(&s, &vis);
        for (path, img) in every_path(&s, &vis) {
            assert_close(&img, &oracle, KERNEL_TOLERANCE, &format!("{name} {path}"));
        }
    }
}

#[test]
fn pixel_packed_point_light_path_matches_oracle_and_tile_size() {
    // SH data sets under point lights only take the pixel-per-lane path.
    let points = "[[light]]\nkind = \"point\"\nposition = [3.0, 5.0, 4.0]\nintensity = 10.0\n\
                  [[light]]\nkind = \"point\"\nposition = [-4.0, -1.0, 2.0]\nintensity = 6.0\n";
    let mut images = Vec::new();
    for tile in [16, 13] {
        for name in ["magenta-plastic", "teal-paint"] {
            let mut f = SceneFile::default();
            f.render.width = 64;
            f.render.height = 48;
            f.render.tile_size = tile;
            f.material = MaterialSpec::Library {
                name: name.into(),
                lookup: None,
            };
            f.lights = Some(SceneFile::parse(points).unwrap().lights.unwrap());
            let s = Scene::resolve(&f, Path::new("/")).unwrap();
            let vis = render::rasterize(&s, false);
            let oracle = scalar_oracle(&s, &vis);
            for (path, img) in every_path(&s, &vis) {
                let what = format!("{name} points tile {tile} {path}");
                assert_close(&img, &oracle, SH_KERNEL_TOLERANCE, &what);
                images.push((format!("{name} {path}"), img));
            }
        }
    }
    let (a, b) = images.split_at(images.len() / 2);
    for ((na, ia), (_, ib)) in a.iter().zip(b) {
        assert!(ia == ib, "{na}: tile size 16 and 13 differ");
    }
}

#[test]
fn pixel_packed_analytic_path_matches_oracle_and_tile_size() {
    // Lambert and Blinn-Phong under at most PACKED_MAX_LIGHTS lights take the
    // pixel-per-lane path (one key light: the default scene); with more, the per-pixel one.
    let dir = |x: f32, y: f32, z: f32| {
        format!("[[light]]\nkind = \"directional\"\nto_light = [{x}, {y}, {z}]\nintensity = 2.0\n")
    };
    let point = |x: f32, y: f32, z: f32| {
        format!("[[light]]\nkind = \"point\"\nposition = [{x}, {y}, {z}]\nintensity = 12.0\n")
    };
    let one_dir = dir(0.3, 0.8, 0.5);
    let one_point = point(3.0, 5.0, 4.0);
    let five = [
        dir(0.3, 0.8, 0.5),
        dir(-0.7, 0.2, 0.4),
        dir(0.0, -1.0, 0.1),
        point(3.0, 5.0, 4.0),
        point(-4.0, -1.0, 2.0),
    ]
    .concat();
    let nine: String = (0..9).map(|k| dir(k as f32 - 4.0, 1.0, 0.5)).collect();
    let mut images = Vec::new();
    for tile in [16, 13] {
        for m in [
            "[material]\nkind = \"lambert\"\n",
            "[material]\nkind = \"blinn-phong\"\nexponent = 200.0\n",
        ] {
            for (lights, packed) in [
                (&one_dir, true),
                (&one_point, true),
                (&five, true),
                (&nine, false),
            ] {
                let mut f = SceneFile::parse(m).unwrap();
                f.render.width = 96;
                f.render.height = 72;
                f.render.tile_size = tile;
                f.lights = Some(SceneFile::parse(lights).unwrap().lights.unwrap());
                let s = Scene::resolve(&f, Path::new("/")).unwrap();
                assert_eq!(FramePrep::new(&s).packs_analytic(), packed, "{m} {lights}");
                let vis = render::rasterize(&s, false);
                let oracle = scalar_oracle(&s, &vis);
                for (path, img) in every_path(&s, &vis) {
                    let what = format!("{} {} lights tile {tile} {path}", m.trim(), s.lights.len());
                    assert_close(&img, &oracle, KERNEL_TOLERANCE, &what);
                    images.push((what, img));
                }
            }
        }
    }
    let (a, b) = images.split_at(images.len() / 2);
    for ((na, ia), (_, ib)) in a.iter().zip(b) {
        assert!(ia == ib, "{na}: tile size 16 and 13 differ");
    }
}
