//! Frame time of the default scene at 640x480: rasterization (clip, set-up, binning,
//! per-tile visibility) and deferred shading measured separately, and the whole frame.
//! `raster-alone` is the rasterizer without the vertex transform (clip positions computed
//! once); `raster-reused` is that with the previous frame's buffers reused
//! (`raster::rasterize_into`); `raster-1M` is `raster-reused` on the teapot at
//! `segments = 128` (1,048,576 triangles). `frame-reused` is `frame` into a frame context
//! kept from the previous frame (`render::render_into`). `surfaces` is the fast path's
//! per-pixel surfaces, shading frames and local views of the whole frame on one thread,
//! nothing shaded (`FramePrep::surfaces_alone`).

use brdfkit::mesh::teapot::teapot;
use brdfkit::raster::{self, RasterConfig};
use brdfkit::render;
use brdfkit::render::RenderOptions;
use brdfkit::scene::Scene;
use brdfkit::shade::{self, ShadeOptions, ShadingPath};
use criterion::{criterion_group, criterion_main, Criterion};

/// The allocator the `brdfkit` binary uses (src/main.rs), so frames are timed as they run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn frame(c: &mut Criterion) {
    let scene = Scene::default_scene();
    assert_eq!((scene.render.width, scene.render.height), (640, 480));
    let vis = render::rasterize(&scene, false);
    let mut g = c.benchmark_group("default-640x480");
    g.bench_function("raster", |b| b.iter(|| render::rasterize(&scene, false)));
    let cfg = RasterConfig {
        width: scene.render.width,
        height: scene.render.height,
        tile_size: scene.render.tile_size,
        cull: scene.render.cull,
        near: scene.camera.near,
        count_coverage: false,
        kernel: brdfkit::lanes::KernelPath::Auto,
    };
    let clip = render::clip_positions(&scene);
    g.bench_function("raster-alone", |b| {
        b.iter(|| raster::rasterize(&clip, &scene.mesh.triangles, &cfg))
    });
    // The same with the buffers kept from the previous frame (the steady state of the
    // viewer and turntables): no allocation, no first-touch page faults.
    let mut scratch = raster::RasterScratch::default();
    let mut reused = raster::VisBuffer::default();
    g.bench_function("raster-reused", |b| {
        b.iter(|| {
            raster::rasterize_into(
                &clip,
                &scene.mesh.triangles,
                &cfg,
                &mut scratch,
                &mut reused,
            )
        })
    });
    // Built on first use, so a run filtered to the other rows does not build it.
    let dense = std::cell::OnceCell::new();
    g.bench_function("raster-1M", |b| {
        let (mesh, clip) = dense.get_or_init(|| {
            let mut s = scene.clone();
            s.mesh = std::sync::Arc::new(teapot(128));
            let clip = render::clip_positions(&s);
            (s.mesh, clip)
        });
        // The previous frame's buffers reused, as the viewer draws: at 1M triangles a new
        // set-up list and visibility buffer per frame would be mostly page clearing.
        let mut scratch = raster::RasterScratch::default();
        let mut vis = raster::VisBuffer::default();
        b.iter(|| raster::rasterize_into(clip, &mesh.triangles, &cfg, &mut scratch, &mut vis))
    });
    let fast = ShadeOptions::default();
    g.bench_function("shade", |b| b.iter(|| shade::shade(&scene, &vis, &fast)));
    // The fast path's surfaces alone (position, normal, shading frame, local view of every
    // visible pixel), one thread, nothing shaded: what `shade` rebuilds before any light.
    let prep = shade::FramePrep::new(&scene);
    g.bench_function("surfaces", |b| b.iter(|| prep.surfaces_alone(&scene, &vis)));
    let oracle = ShadeOptions::default().with_path(ShadingPath::ScalarOracle);
    g.bench_function("shade-scalar-oracle", |b| {
        b.iter(|| shade::shade(&scene, &vis, &oracle))
    });
    let frame = RenderOptions::default();
    g.bench_function("frame", |b| b.iter(|| render::render(&scene, &frame)));
    // The same with the previous frame's buffers (`render::FrameContext`): the steady
    // state of the viewer, turntables and the sweep.
    let mut ctx = render::FrameContext::default();
    g.bench_function("frame-reused", |b| {
        b.iter(|| {
            render::render_into(&scene, &frame, &mut ctx);
        })
    });
    g.finish();
}

criterion_group!(benches, frame);
criterion_main!(benches);
