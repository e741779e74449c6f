//! The wgpu renderer against a closed form (cargo feature `gpu`; needs an adapter): a Lambert
//! sphere under one directional light reflects `L = albedo / pi * E * max(0, n.l)` (thesis
//! 2.2.1, Def. 10), with `n` the exact sphere's normal where the pixel centre's camera ray
//! meets it. The rays and normals are computed here from the camera's position, target and
//! field of view, independently of both renderers.
#![cfg(feature = "gpu")]

use brdfkit::gpu::{Faults, Gpu};
use brdfkit::scene::{Scene, SceneFile};
use glam::DVec3;
use std::path::Path;

#[test]
fn lambert_sphere_under_a_directional_light_matches_the_closed_form() {
    let file = SceneFile::parse(
        "[mesh]\nsource = \"sphere\"\nsegments = 32\n\
         [material]\nkind = \"lambert\"\nalbedo = [0.8, 0.5, 0.2]\n\
         [[light]]\nkind = \"directional\"\nto_light = [0.3, 0.8, 0.5]\nintensity = 2.0\n\
         [camera]\nposition = [0.0, 0.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 40.0\n\
         [render]\nwidth = 64\nheight = 48\n",
    )
    .unwrap();
    let scene = Scene::resolve(&file, Path::new(".")).unwrap();
    let gpu = Gpu::new().expect("a GPU adapter (lavapipe: mesa-vulkan-drivers)");
    // The check itself: the correct render passes it, the seeded missing-cosine fault fails.
    let img = gpu.render(&scene, Faults::NONE).unwrap();
    let (checked, worst) = check(&scene, &img.pixels).expect("correct render");
    assert!(checked > 500, "{checked} pixels checked");
    eprintln!("{checked} pixels, largest difference {worst:.3e}");
    let faulty = gpu
        .render(&scene, Faults::parse("no-cosine").unwrap())
        .unwrap();
    let why = check(&scene, &faulty.pixels).expect_err("the no-cosine fault must fail");
    eprintln!("no-cosine: {why}");
}

/// Compares `pixels` with the closed form at every pixel away from the silhouette:
/// `(pixels checked, largest difference)`, or the first pixel out of bounds.
fn check(scene: &Scene, pixels: &[glam::Vec3]) -> Result<(usize, f64), String> {
    let sphere = scene
        .mesh
        .exact_sphere
        .expect("a UV sphere names its sphere");

    let (w, h) = (64.0f64, 48.0f64);
    let eye = DVec3::new(0.0, 0.0, 4.0);
    let tan_y = (20.0f64).to_radians().tan();
    let l = DVec3::new(0.3, 0.8, 0.5).normalize();
    let albedo = DVec3::new(0.8, 0.5, 0.2);
    let (c, r) = (sphere.center.as_dvec3(), sphere.radius as f64);
    let (mut checked, mut worst) = (0, 0.0f64);
    for y in 0..48 {
        for x in 0..64 {
            // The camera looks down -z with +y up: the ray through the pixel centre.
            let ndc_x = 2.0 * (x as f64 + 0.5) / w - 1.0;
            let ndc_y = 1.0 - 2.0 * (y as f64 + 0.5) / h;
            let d = DVec3::new(ndc_x * tan_y * w / h, ndc_y * tan_y, -1.0).normalize();
            let o = eye - c;
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - r * r);
            let got = pixels[y * 64 + x].as_dvec3();
            // Pixels near the silhouette (the facets' outline differs from the sphere's) are
            // left out; away from the sphere the image is black.
            if disc < 0.0 {
                if disc < -0.05 && got != DVec3::ZERO {
                    return Err(format!("({x}, {y}) off the sphere: {got}"));
                }
                continue;
            }
            if disc < 0.05 {
                continue;
            }
            let t = -b - disc.sqrt();
            let n = (o + t * d) / r;
            let want = albedo / std::f64::consts::PI * 2.0 * n.dot(l).max(0.0);
            let err = (got - want).abs().max_element();
            worst = worst.max(err);
            if err > 2e-5 + 1e-4 * want.max_element() {
                return Err(format!("({x}, {y}): {got} vs {want}"));
            }
            checked += 1;
        }
    }
    Ok((checked, worst))
}
