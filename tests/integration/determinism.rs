//! Determinism: the same scene gives the same bits for any thread count and tile size.

use brdfkit::aov::Aov;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;

/// `s` (or its AOV `aov`) rendered on a dedicated pool of `threads` threads.
fn render_on(s: &Scene, aov: Option<Aov>, threads: usize) -> brdfkit::image_io::Image {
    let opts = RenderOptions {
        aov,
        threads: Some(threads),
        ..RenderOptions::default()
    };
    render(s, &opts).image
}

fn bytes(img: &brdfkit::image_io::Image) -> Vec<u8> {
    img.pixels
        .iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect()
}

fn scene(tile: u32, mesh: &str) -> Scene {
    let mut f = SceneFile::default();
    f.render.width = 200;
    f.render.height = 150;
    f.render.tile_size = tile;
    f.mesh.source = mesh.into();
    f.lights = Some(
        brdfkit::scene::default_lights()
            .into_iter()
            .chain(
                SceneFile::parse(
                    "[[light]]\nkind = \"point\"\nposition = [-3.0, 4.0, 3.0]\nintensity = 20.0\n",
                )
                .unwrap()
                .lights
                .unwrap(),
            )
            .collect(),
    );
    Scene::resolve(&f, Path::new(".")).unwrap()
}

#[test]
fn identical_bytes_for_any_threads_and_tile_size() {
    for mesh in ["teapot", "sphere"] {
        let reference = bytes(&render_on(&scene(32, mesh), None, 1));
        assert!(reference.iter().any(|&b| b != 0));
        for tile in [32, 8, 13] {
            for threads in [1, 2, 3, 7] {
                let got = bytes(&render_on(&scene(tile, mesh), None, threads));
                assert!(
                    got == reference,
                    "{mesh}: tile {tile}, {threads} threads differ from tile 32, 1 thread"
                );
            }
        }
    }
}

#[test]
fn aovs_are_deterministic_too() {
    for aov in [
        Aov::Normal,
        Aov::Depth,
        Aov::Coverage,
        Aov::ViewAzimuth,
        Aov::LightPolar,
    ] {
        let a = bytes(&render_on(&scene(32, "teapot"), Some(aov), 1));
        let b = bytes(&render_on(&scene(8, "teapot"), Some(aov), 3));
        assert!(
            a == b,
            "{aov:?} differs between tile 32 / 1 thread and tile 8 / 3 threads"
        );
    }
}

#[test]
fn every_kernel_path_gives_the_same_bits() {
    // The determinism contract across instruction sets: both kernel paths fuse every
    // multiply-add and sum lanes in one order, so a frame is bit-identical on each path this
    // CPU runs, for every material kind the kernel has (Blinn-Phong, SH, D-BRDF) under
    // directional and point lights.
    let paths = crate::common::kernel_paths("determinism");
    eprintln!("kernel paths on this CPU: {paths:?}");
    for material in ["", "blue-silk", "lindt-paper", "red-velvet"] {
        let mut s = scene(32, "sphere");
        let render_bytes = |s: &Scene| bytes(&render_on(s, None, 2));
        if !material.is_empty() {
            let mut f = SceneFile::default();
            f.render.width = 120;
            f.render.height = 90;
            f.mesh.source = "sphere".into();
            f.material = brdfkit::scene::MaterialSpec::from_cli(material).unwrap();
            s = Scene::resolve(&f, Path::new(".")).unwrap();
        }
        let mut images = Vec::new();
        for &p in &paths {
            s.render.kernel = p;
            images.push(render_bytes(&s));
        }
        assert!(images[0].iter().any(|&b| b != 0));
        for (p, img) in paths.iter().zip(&images) {
            assert!(
                *img == images[0],
                "{material:?}: the {} path differs from the {} path",
                p.name(),
                paths[0].name()
            );
        }
    }
}

/// The contract holds under every environment method, not only delta lights: the same
/// bits for tile sizes 32, 8 and 13 and 1, 2 and 3 threads with `lights` (median cut),
/// `transfer` (an SH data set), `lightcuts` (Blinn-Phong, cuts shared per 8 x 8 square of
/// the image), `reflection` (Blinn-Phong, a small table: the bake's reduction order is
/// fixed too) and `auto` (a library D-BRDF, which `auto` shades with light cuts).
#[test]
fn every_environment_method_is_deterministic() {
    let cases = [
        (
            "lights",
            "kind = \"blinn-phong\"\nexponent = 200",
            "method = \"lights\"\ncount = 32",
        ),
        (
            "transfer",
            "kind = \"library\"\nname = \"magenta-plastic\"",
            "method = \"transfer\"",
        ),
        (
            "lightcuts",
            "kind = \"blinn-phong\"\nexponent = 200",
            "method = \"lightcuts\"",
        ),
        (
            "reflection",
            "kind = \"blinn-phong\"\nexponent = 200",
            "method = \"reflection\"\nreflection_grid = 16\nreflection_slices = 4\nreflection_residual = 64",
        ),
        ("auto", "kind = \"library\"\nname = \"lindt-paper\"", ""),
    ];
    for (method, material, env) in cases {
        let scene = |tile: u32| {
            let text = format!(
                "[mesh]\nsource = \"teapot\"\n[material]\n{material}\n\
                 [env]\nfile = \"assets/probes/studio.exr\"\n{env}\n\
                 [render]\nwidth = 96\nheight = 72\ntile_size = {tile}\n"
            );
            let f = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
            Scene::resolve(&f, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
        };
        let reference = bytes(&render_on(&scene(32), None, 1));
        assert!(reference.iter().any(|&b| b != 0), "{method}: black");
        for (tile, threads) in [(8, 2), (13, 3), (13, 1), (32, 2)] {
            let got = bytes(&render_on(&scene(tile), None, threads));
            assert!(
                got == reference,
                "{method}: tile {tile}, {threads} threads differ from tile 32, 1 thread"
            );
        }
    }
}
