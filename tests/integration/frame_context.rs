//! Frames rendered into one frame context (`render::render_into`, `render::FrameContext`:
//! the buffers kept from one frame to the next, as the viewer, turntables, the sweep and
//! the benches draw) have the bits of a render with new buffers (`render::render`),
//! whatever the context rendered before: other scenes, sizes, tile sizes, shading paths,
//! AOVs, shards and thread counts, in both orders. A context seeded with a fault that keeps
//! the previous frame's visibility (`raster::RasterFault::PreviousFrameKept`) must fail
//! the same comparison.

use brdfkit::image_io::Image;
use brdfkit::raster::RasterFault;
use brdfkit::render::{self, FrameContext, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::shade::ShadingPath;
use brdfkit::shard::Shard;
use std::path::Path;

/// The default scene (the teapot, Blinn-Phong, one key light) at `width x height` in tiles
/// of `tile_size`, its camera at `distance` times the default distance from the target.
fn teapot(width: u32, height: u32, tile_size: u32, distance: f32) -> Scene {
    let mut s = Scene::default_scene();
    s.render.width = width;
    s.render.height = height;
    s.render.tile_size = tile_size;
    let c = &mut s.camera;
    c.position = c.target + (c.position - c.target) * distance;
    s
}

/// A sphere of `material` in a 72 x 40 frame of 16-pixel tiles under two directional lights.
fn sphere(material: &str) -> Scene {
    let lights = "[[light]]\nkind = \"directional\"\nto_light = [0.3, 0.8, 0.5]\nintensity = 4.0\n\
         [[light]]\nkind = \"directional\"\nto_light = [-0.6, 0.4, 0.7]\nintensity = 0.5\n";
    super::render_options::sphere_under(lights, material)
}

/// A 24 x 24 sphere of lindt-paper under the sky probe's light cuts (`[env] method =
/// "lightcuts"`: a term added after the lights' pass, in squares of its own).
fn lightcuts() -> Scene {
    let text = "[mesh]\nsource = \"sphere\"\nsegments = 32\n[material]\nkind = \"library\"\n\
         name = \"lindt-paper\"\n[env]\nfile = \"assets/probes/sky.exr\"\n\
         method = \"lightcuts\"\n[render]\nwidth = 24\nheight = 24\n";
    let file = SceneFile::parse(text).unwrap();
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// The frames of the test: a name, a scene and the options it is rendered with.
fn frames() -> Vec<(&'static str, Scene, RenderOptions)> {
    let stats = RenderOptions {
        stats: true,
        ..RenderOptions::default()
    };
    let near = teapot(96, 72, 16, 1.0);
    let shard = RenderOptions {
        rows: Some(render::row_bands(16, Shard::parse("2/3").unwrap())),
        ..stats.clone()
    };
    vec![
        ("teapot 96x72", near.clone(), stats.clone()),
        // The same size, the object smaller: every pixel the first frame covered and
        // this one does not must come back black.
        ("teapot 96x72 far", teapot(96, 72, 16, 2.5), stats.clone()),
        (
            "teapot 96x72 tiles of 8",
            teapot(96, 72, 8, 1.3),
            stats.clone(),
        ),
        ("teapot 64x40", teapot(64, 40, 32, 0.9), stats.clone()),
        ("teapot 96x72 shard 2/3", near.clone(), shard),
        (
            "teapot 96x72 2 threads",
            near.clone(),
            RenderOptions {
                threads: Some(2),
                ..stats.clone()
            },
        ),
        (
            "teapot 96x72 1 thread",
            near.clone(),
            RenderOptions {
                threads: Some(1),
                ..stats.clone()
            },
        ),
        (
            "teapot normal AOV",
            near.clone(),
            RenderOptions {
                aov: Some(brdfkit::aov::Aov::Normal),
                ..stats.clone()
            },
        ),
        (
            "teapot coverage AOV",
            near.clone(),
            RenderOptions {
                aov: Some(brdfkit::aov::Aov::Coverage),
                ..stats.clone()
            },
        ),
        ("sphere blue-silk", sphere("blue-silk"), stats.clone()),
        ("sphere teal-paint", sphere("teal-paint"), stats.clone()),
        (
            "sphere blue-silk scalar oracle",
            sphere("blue-silk"),
            stats.clone().with_path(ShadingPath::ScalarOracle),
        ),
        (
            "sphere teal-paint f64",
            sphere("teal-paint"),
            stats.clone().with_path(ShadingPath::F64NoSkips),
        ),
        ("lightcuts 24x24", lightcuts(), stats.clone()),
        ("teapot 96x72 again", near, stats),
    ]
}

fn bits(img: &Image) -> (u32, u32, Vec<[u32; 3]>) {
    let px = img
        .pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    (img.width, img.height, px)
}

/// Renders `frames` in order into `ctx`; the names of those whose image or stats differ
/// from a render with new buffers.
fn differing(
    ctx: &mut FrameContext,
    frames: &[(&'static str, Scene, RenderOptions)],
) -> Vec<String> {
    let mut bad = Vec::new();
    for (name, scene, opts) in frames {
        let fresh = render::render(scene, opts);
        let kept = render::render_into(scene, opts, ctx);
        if bits(kept.image) != bits(&fresh.image) || kept.stats != fresh.stats {
            bad.push(name.to_string());
        }
    }
    bad
}

#[test]
fn one_context_renders_the_bits_of_new_buffers_whatever_it_rendered_before() {
    let mut frames = frames();
    let mut ctx = FrameContext::default();
    assert_eq!(differing(&mut ctx, &frames), Vec::<String>::new());
    // Every transition the other way round, with the context as the first pass left it.
    frames.reverse();
    assert_eq!(differing(&mut ctx, &frames), Vec::<String>::new());
    // The checks see what they check: the near teapot covers pixels the far one leaves
    // black, and the shard leaves rows black that the whole frame shades.
    let (near, far) = (&frames[frames.len() - 1], &frames[frames.len() - 2]);
    let (a, b) = (
        render::render(&near.1, &near.2),
        render::render(&far.1, &far.2),
    );
    let lit = |i: &Image| i.pixels.iter().filter(|p| **p != glam::Vec3::ZERO).count();
    assert!(
        lit(&a.image) > lit(&b.image) + 500,
        "{} {}",
        lit(&a.image),
        lit(&b.image)
    );
}

/// The seeded fault: a context whose rasterizer keeps the previous frame's visibility
/// (triangle and depth per pixel) fails the comparison (it differs, or it panics on a
/// triangle index of the previous frame's set-up list).
#[test]
fn a_context_that_keeps_the_previous_visibility_fails() {
    // The first two frames only (the others' scenes are not built): the near teapot, then
    // the far one at the same size.
    let stats = RenderOptions {
        stats: true,
        ..RenderOptions::default()
    };
    let frames = [
        ("teapot 96x72", teapot(96, 72, 16, 1.0), stats.clone()),
        ("teapot 96x72 far", teapot(96, 72, 16, 2.5), stats),
    ];
    let faulty = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut ctx = FrameContext::with_fault(RasterFault::PreviousFrameKept);
        differing(&mut ctx, &frames)
    }));
    // A panic is a failure as well; without one, the second frame must differ.
    if let Ok(bad) = faulty {
        assert_eq!(bad, ["teapot 96x72 far"], "the fault went unseen");
    }
}
