//! `[env] method = "reflection"` on `brdfkit render --device gpu` (cargo feature `gpu`; needs
//! a Vulkan adapter, e.g. lavapipe): the table path of isotropic materials is drawn (the
//! golden check holds it to the CPU: the `env-reflection-*` entries of tests/gpu/golden.rs),
//! at any order of its series in psi (the golden entries are order 2; a table of order 4 is
//! held to the CPU's image here), and an anisotropic D-BRDF, which the CPU shades by
//! filtered importance sampling, is refused in one line that names why, with a non-zero exit
//! and no image written.
#![cfg(feature = "gpu")]

use crate::common;
use brdfkit::gpu::{Faults, Gpu};
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::env_method::REFLECTION_FILTERED_NOT_ON_GPU;
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;

#[test]
fn the_filtered_path_is_refused_on_the_gpu_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let probe = common::city_probe();
    // The golden set's anisotropic D-BRDF file (lindt paper's fit: no library fit to wait for).
    let lindt = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden/lindt-paper-16x8.exr");
    let r = common::brdfkit(d)
        .env("XDG_RUNTIME_DIR", d)
        .timeout(600)
        .run(&[
            "render",
            "--env",
            probe.as_str(),
            "--env-method",
            "reflection",
            "--material",
            lindt.to_str().unwrap(),
            "--width",
            "16",
            "--height",
            "12",
            "--device",
            "gpu",
            "-o",
            "out.exr",
        ]);
    assert_eq!(r.code, Some(2), "{}{}", r.stdout, r.stderr);
    let errors: Vec<&str> = r.stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "{}", r.stderr);
    assert!(
        errors[0].ends_with(&format!("--device gpu: {REFLECTION_FILTERED_NOT_ON_GPU}")),
        "{}",
        r.stderr
    );
    assert!(!d.join("out.exr").exists());
}

/// Relative RMSE of `got` against `want` (the CPU's image), over every pixel.
fn rel_rmse(got: &[glam::Vec3], want: &[glam::Vec3]) -> f64 {
    let (mut se, mut sy) = (0.0f64, 0.0f64);
    for (g, w) in got.iter().zip(want) {
        se += (*g - *w).as_dvec3().length_squared();
        sy += w.as_dvec3().length_squared();
    }
    (se / sy).sqrt()
}

/// A glossy sphere under the city probe (box-downsampled to 128 x 64) through a small table
/// of order 4 (`reflection_order`, the shader's `REFL_ORDER`): the GPU's image is the CPU's
/// within the golden set's default radiometric bound (relative RMSE 1e-3), while the CPU's
/// order-2 image of the same scene is farther than that from it (so the check tells the
/// orders apart) and the seeded `reflection-psi-sign` fault fails it. About a second of
/// bake and three small draws.
#[test]
fn a_table_of_another_order_is_drawn_as_the_cpu_shades_it() {
    let tmp = tempfile::tempdir().unwrap();
    let probe = common::small_city_probe(tmp.path());
    let scene_of = |order: usize| {
        let text = format!(
            "[mesh]\nsource = \"sphere\"\nsegments = 48\n\
             [material]\nkind = \"blinn-phong\"\nkd = [0.05, 0.05, 0.05]\n\
             ks = [0.9, 0.9, 0.9]\nexponent = 50\n\
             [env]\nfile = \"{probe}\"\nmethod = \"reflection\"\nexact_lights = 16\n\
             reflection_grid = 8\nreflection_slices = 3\nreflection_residual = 32\n\
             reflection_order = {order}\n\
             [render]\nwidth = 48\nheight = 36\n"
        );
        Scene::resolve(&SceneFile::parse(&text).unwrap(), Path::new("/")).unwrap()
    };
    let scene = scene_of(4);
    let cpu = render(&scene, &RenderOptions::default()).image;
    let cpu_order2 = render(&scene_of(2), &RenderOptions::default()).image;
    let gpu = Gpu::new().expect("a GPU adapter (lavapipe: mesa-vulkan-drivers)");
    let drawn = gpu.render(&scene, Faults::NONE).unwrap();
    let faulty = gpu
        .render(&scene, Faults::parse("reflection-psi-sign").unwrap())
        .unwrap();
    let (e, e2, ef) = (
        rel_rmse(&drawn.pixels, &cpu.pixels),
        rel_rmse(&cpu_order2.pixels, &cpu.pixels),
        rel_rmse(&faulty.pixels, &cpu.pixels),
    );
    eprintln!("order 4: GPU against CPU {e:.2e}; CPU order 2 {e2:.2e}; psi-sign fault {ef:.2e}");
    assert!(e < 1e-3, "the GPU's order-4 image is {e} from the CPU's");
    assert!(e2 > 1e-3, "orders 2 and 4 too close to tell apart: {e2}");
    assert!(ef > 1e-3, "the psi-sign fault passed at order 4: {ef}");
}
