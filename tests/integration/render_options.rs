//! The one render entry point and its options (`render::render`, `RenderOptions`,
//! `shade::ShadeOptions`): every shading path counts each tile of the frame exactly once
//! into the caller's progress (whatever the thread count, empty tiles included), the
//! scalar oracle's tile loop gives exactly `shade_point` at every pixel, and the f64 path
//! ignores every skip while the kernels apply them.

use brdfkit::progress::Progress;
use brdfkit::render::{self, tile_count, RenderOptions};
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use brdfkit::shade::{self, shade_point, surface_at, FramePrep, ShadeOptions, ShadingPath};
use glam::Vec3;
use std::path::Path;

/// A sphere in a 72 x 40 frame of 16-pixel tiles (5 x 3 tiles, the last column and row
/// partial, the corners empty) under a strong and several weak directional lights.
fn scene(material: &str) -> Scene {
    let mut lights = String::from(
        "[[light]]\nkind = \"directional\"\nto_light = [0.3, 0.8, 0.5]\nintensity = 4.0\n",
    );
    for (i, d) in [
        [-0.6, 0.4, 0.7],
        [0.7, -0.2, 0.7],
        [0.0, 0.3, -0.95],
        [-0.5, -0.5, 0.7],
    ]
    .iter()
    .enumerate()
    {
        lights += &format!(
            "[[light]]\nkind = \"directional\"\nto_light = [{}, {}, {}]\nintensity = {}\n",
            d[0],
            d[1],
            d[2],
            0.004 * (i + 1) as f32
        );
    }
    sphere_under(&lights, material)
}

/// A sphere of `material` in a 72 x 40 frame of 16-pixel tiles under `lights` (`[[light]]`
/// tables); the frame-context tests use it too.
pub(crate) fn sphere_under(lights: &str, material: &str) -> Scene {
    let mut f = SceneFile::parse(lights).unwrap();
    f.render.width = 72;
    f.render.height = 40;
    f.render.tile_size = 16;
    f.mesh.source = "sphere".into();
    f.material = MaterialSpec::from_cli(material).unwrap();
    Scene::resolve(&f, Path::new("/")).unwrap()
}

fn on_path(path: ShadingPath) -> RenderOptions {
    RenderOptions {
        stats: true,
        ..RenderOptions::default().with_path(path)
    }
}

#[test]
fn every_path_counts_each_tile_once_for_any_thread_count() {
    let s = scene("blue-silk");
    assert_eq!(tile_count(&s), 15);
    for path in [
        ShadingPath::Kernels,
        ShadingPath::ScalarOracle,
        ShadingPath::F64NoSkips,
    ] {
        let mut first = None;
        for threads in [None, Some(1), Some(3)] {
            let progress = Progress::hidden();
            let mut opts = on_path(path);
            opts.threads = threads;
            opts.shading.progress = progress.clone();
            let r = render::render(&s, &opts);
            let stats = r.stats.unwrap();
            assert_eq!(
                (progress.position(), stats.tiles),
                (15, 15),
                "{path:?} on {threads:?} threads"
            );
            if path == ShadingPath::Kernels {
                // Empty tiles are counted too (skipped without looking at a pixel).
                assert!(stats.shade.tiles_skipped > 0, "no empty tile in the frame");
                assert_eq!(stats.shade.tiles_skipped + stats.shade.tiles_shaded, 15);
            }
            assert!(r.image.pixels.iter().any(|p| *p != Vec3::ZERO));
            // Counting changes nothing: the same bits on every thread count.
            match &first {
                None => first = Some(r.image),
                Some(img) => assert!(*img == r.image, "{path:?}: {threads:?} threads differ"),
            }
        }
    }
    // An AOV render shades nothing and counts nothing.
    let progress = Progress::hidden();
    let mut opts = RenderOptions {
        aov: Some(brdfkit::aov::Aov::Normal),
        ..RenderOptions::default()
    };
    opts.shading.progress = progress.clone();
    render::render(&s, &opts);
    assert_eq!(progress.position(), 0);
}

#[test]
fn the_scalar_oracle_path_is_shade_point_at_every_pixel() {
    // Independently of the tile loop: shade_point per pixel, row by row, over the lights
    // and bands the frame kept, plus the dropped lights where they are restored (the scalar
    // oracle applies the kernels' skips).
    for material in ["blue-silk", "lindt-paper"] {
        let s = scene(material);
        let vis = render::rasterize(&s, false);
        let prep = FramePrep::new(&s);
        assert!(prep.dropped.dropped > 0, "{material}: nothing dropped");
        let brdf: &dyn brdfkit::brdf::Brdf = match &prep.sh {
            Some((ds, _)) => ds.as_ref(),
            None => s.material.as_brdf(),
        };
        let mut expected = Vec::new();
        for y in 0..vis.height {
            for x in 0..vis.width {
                expected.push(surface_at(&s.mesh, &vis, x, y).map_or(Vec3::ZERO, |surf| {
                    let kept = shade_point(
                        brdf,
                        &prep.dropped.kept,
                        &surf,
                        s.camera.position,
                        &prep.rule,
                    );
                    // Where leaving the dropped lights out could change the pixel by more
                    // than `drop_lights` of its value, they are shaded too (kernel::skip).
                    if brdfkit::kernel::skip::needs_restore(
                        kept,
                        prep.dropped.restore_below(surf.normal),
                    ) {
                        kept + shade_point(
                            brdf,
                            &prep.dropped.removed,
                            &surf,
                            s.camera.position,
                            &prep.rule,
                        )
                    } else {
                        kept
                    }
                }));
            }
        }
        let oracle = ShadeOptions::default().with_path(ShadingPath::ScalarOracle);
        let img = shade::shade(&s, &vis, &oracle).image;
        assert!(img.pixels == expected, "{material}: oracle off shade_point");
        // Seeded fault: the kernels (another summation order) are not bit-identical to
        // it, so the comparison above can fail.
        let kernels = shade::shade(&s, &vis, &ShadeOptions::default()).image;
        assert!(kernels.pixels != expected, "{material}: check cannot fail");
    }
}

#[test]
fn the_f64_path_ignores_every_skip_and_the_kernels_apply_them() {
    let mut with_skips = scene("blue-silk");
    with_skips.render.drop_lights = 0.5;
    with_skips.render.band_skip = true;
    let mut without = with_skips.clone();
    without.render.drop_lights = 0.0;
    without.render.band_skip = false;
    let f64_path = on_path(ShadingPath::F64NoSkips);
    let a = render::render(&with_skips, &f64_path);
    let b = render::render(&without, &f64_path);
    assert!(a.image == b.image, "the f64 path applied a skip");
    assert_eq!(a.stats.unwrap().lights_dropped, 0);
    // Seeded fault for the check above: on the kernels the same two scenes differ, so
    // equal images are not a given.
    let kernels = on_path(ShadingPath::Kernels);
    let c = render::render(&with_skips, &kernels);
    let d = render::render(&without, &kernels);
    assert!(c.stats.unwrap().lights_dropped > 0);
    assert!(
        c.image != d.image,
        "the skips changed nothing on the kernels"
    );
    // And the converged-reference options are that f64 path.
    let r = render::render(&with_skips, &RenderOptions::converged_reference());
    assert!(r.image == a.image && r.stats.is_none());
}

#[test]
fn the_kernel_option_overrides_the_scene_with_the_same_bits() {
    let s = scene("lindt-paper");
    let auto = render::render(&s, &RenderOptions::default()).image;
    for k in crate::common::kernel_paths("render_options") {
        let mut opts = RenderOptions::default();
        opts.shading.kernel = Some(k);
        assert!(render::render(&s, &opts).image == auto, "{k:?}");
    }
}
