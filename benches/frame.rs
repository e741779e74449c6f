//! Frame time of the default scene at 640x480: rasterization (clip, set-up, binning,
//! per-tile visibility) and deferred shading measured separately, and the whole frame.

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
    let fast = ShadeOptions::default();
    g.bench_function("shade", |b| b.iter(|| shade::shade(&scene, &vis, &fast)));
    let oracle = ShadeOptions::default().with_path(ShadingPath::ScalarOracle);
    g.bench_function("shade-scalar-oracle", |b| {
        b.iter(|| shade::shade(&scene, &vis, &oracle))
    });
    let frame = RenderOptions::default();
    g.bench_function("frame", |b| b.iter(|| render::render(&scene, &frame)));
    g.finish();
}

criterion_group!(benches, frame);
criterion_main!(benches);
