//! Clipping and scale robustness: camera inside the mesh, triangles behind the camera,
//! huge and tiny scene scales. No panic, and no NaN or Inf in any pixel or AOV.

use brdfkit::aov::Aov;
use brdfkit::render::render;
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;

fn check_finite(scene: &Scene, what: &str) -> usize {
    let img = render(scene, &Default::default()).image;
    assert!(
        img.pixels.iter().all(|p| p.is_finite()),
        "{what}: non-finite pixel"
    );
    // Every AOV the renderer has (the command line's list), so a new one is checked too.
    for &aov in <Aov as clap::ValueEnum>::value_variants() {
        let a = render(
            scene,
            &brdfkit::render::RenderOptions {
                aov: Some(aov),
                ..Default::default()
            },
        )
        .image;
        assert!(
            a.pixels.iter().all(|p| p.is_finite()),
            "{what}: non-finite {aov:?}"
        );
    }
    img.pixels.iter().filter(|p| p.max_element() > 0.0).count()
}

fn scene_from(toml: &str) -> Scene {
    let mut f = SceneFile::parse(toml).unwrap();
    f.render.width = 120;
    f.render.height = 90;
    Scene::resolve(&f, Path::new(".")).unwrap()
}

#[test]
fn camera_inside_the_teapot() {
    // Two-sided: from inside, the inner walls are lit back faces.
    let lit = check_finite(&scene_from("[camera]\nposition = [0.0, 1.2, 0.0]\ntarget = [1.0, 1.0, 0.0]\nnear = 0.001\n[[light]]\nkind = \"point\"\nposition = [0.0, 1.5, 0.0]\nintensity = 5.0\n"), "inside teapot");
    assert!(
        lit > 100,
        "inside of the teapot should be visible and lit ({lit} lit pixels)"
    );
}

#[test]
fn camera_inside_the_sphere_and_mesh_behind_camera() {
    check_finite(&scene_from("[mesh]\nsource = \"sphere\"\n[camera]\nposition = [0.0, 0.0, 0.5]\ntarget = [0.0, 0.0, -1.0]\n"), "inside sphere");
    // Mesh entirely behind the camera: an empty image, not a mirrored one.
    let s = scene_from("[camera]\nposition = [0.0, 1.0, 10.0]\ntarget = [0.0, 1.0, 20.0]\n");
    assert_eq!(
        check_finite(&s, "behind camera"),
        0,
        "geometry behind the camera must not appear"
    );
}

#[test]
fn near_plane_cuts_through_the_mesh() {
    // The camera sits just outside the body: the near plane slices the teapot.
    let lit = check_finite(
        &scene_from(
            "[camera]\nposition = [0.0, 1.5, 2.05]\ntarget = [0.0, 1.5, 0.0]\nnear = 0.1\n",
        ),
        "near plane slice",
    );
    assert!(lit > 0);
}

#[test]
fn huge_and_tiny_scales() {
    for scale in [1e-3f32, 1e-2, 1.0, 1e2, 1e4] {
        let mut f = SceneFile::default();
        f.render.width = 96;
        f.render.height = 72;
        let mut scene = Scene::resolve(&f, Path::new(".")).unwrap();
        let mut mesh = (*scene.mesh).clone();
        mesh.transform(glam::Affine3A::from_scale(glam::Vec3::splat(scale)));
        scene.camera.position *= scale;
        scene.camera.target *= scale;
        scene.camera.near *= scale;
        scene.mesh = std::sync::Arc::new(mesh);
        let lit = check_finite(&scene, &format!("scale {scale}"));
        assert!(lit > 500, "scale {scale}: only {lit} lit pixels");
    }
}

#[test]
fn culling_back_faces_keeps_the_visible_surface() {
    // For an outward-facing mesh, back-face culling only removes what the depth test hides
    // anyway, except where the inside shows (the lid gap, the spout opening). An inside-out
    // mesh would show its interior instead.
    for mesh in ["teapot", "sphere"] {
        let two_sided = scene_from(&format!("[mesh]\nsource = \"{mesh}\"\n"));
        let culled = scene_from(&format!(
            "[mesh]\nsource = \"{mesh}\"\n[render]\ncull = \"back\"\n"
        ));
        let a = render(&two_sided, &Default::default()).image;
        let b = render(&culled, &Default::default()).image;
        let covered = a.pixels.iter().filter(|p| p.max_element() > 0.0).count();
        let same = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(x, y)| x.max_element() > 0.0 && x == y)
            .count();
        assert!(
            same as f32 > 0.95 * covered as f32,
            "{mesh}: only {same} of {covered} pixels agree between culled and two-sided renders"
        );
    }
}
