//! Frame time at 640x480 of the teapot (the default camera) under `[env] method =
//! "reflection"` (the default table: 64 x 64 cells, 13 + 1 slices, 64 exact lights), beside
//! the same frame under 128 Lloyd lights (the fast, inaccurate light set) and under light
//! cuts (`method = "lightcuts"`, the default 1% cut error: the accurate method `auto`
//! chooses for these materials), for the library D-BRDF `gold-dust-paint` and
//! Blinn-Phong 200 (isotropic: a table), and the anisotropic library D-BRDF `lindt-paper`
//! (filtered importance sampling, the default 128 half vectors per pixel and 64 exact
//! lights; its preparation is printed in place of a bake); the table's target is >= 30
//! frames/s. The table's bake time (a
//! 512 x 256 probe) and size are measured once per row and printed beside it (a bake runs
//! once per scene and probe, far too long for criterion's samples). The probes benched are
//! `BRDFKIT_BENCH_PROBES` (comma-separated, default `city`; the frame's cost does not depend
//! on the probe: one lookup and 64 lights per pixel whatever it holds; light cuts' does).
//! `BRDFKIT_BENCH_MATERIALS` (comma-separated names of the rows, default all) prepares
//! only those materials (every row's scene is prepared before criterion's filter applies).
//!
//! ```sh
//! BRDFKIT_BENCH_PROBES=city,studio,sky cargo bench --bench reflection -- --noplot
//! BRDFKIT_BENCH_MATERIALS=lindt-paper BRDFKIT_BENCH_ORDERS= cargo bench --bench reflection -- 'frame-reflection$'
//! ```
//!
//! The order of the series in psi (`[env] reflection_order`): the same teapot frame,
//! Blinn-Phong 200 (the sweep's glossy class, `kd = 0.05`, `ks = 0.9`) under city, with a
//! table of each order of `BRDFKIT_BENCH_ORDERS` (comma-separated, default `2,6`; the
//! bake time and size printed as above). An empty `BRDFKIT_BENCH_PROBES` skips the
//! comparison of methods above, so this runs alone:
//!
//! ```text
//! BRDFKIT_BENCH_PROBES= cargo bench --bench reflection -- order --noplot
//! ```

use brdfkit::render::{self, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::time::Instant;

/// The allocator the `brdfkit` binary uses (src/main.rs), so frames are timed as they run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const MATERIALS: [(&str, &str); 3] = [
    (
        "gold-dust-paint",
        "kind = \"library\"\nname = \"gold-dust-paint\"",
    ),
    ("blinn-phong-200", "kind = \"blinn-phong\"\nexponent = 200"),
    ("lindt-paper", "kind = \"library\"\nname = \"lindt-paper\""),
];

fn scene(material: &str, probe: &str, env: &str) -> Scene {
    let text = format!(
        "[material]\n{material}\n[env]\nfile = \"assets/probes/{probe}.exr\"\n{env}\n\
         [render]\nwidth = 640\nheight = 480\n"
    );
    let file = SceneFile::parse(&text).unwrap();
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn reflection(c: &mut Criterion) {
    let probes = std::env::var("BRDFKIT_BENCH_PROBES").unwrap_or_else(|_| "city".into());
    let only = std::env::var("BRDFKIT_BENCH_MATERIALS").unwrap_or_default();
    let chosen = |name: &str| only.is_empty() || only.split(',').any(|m| m == name);
    for probe in probes.split(',').filter(|p| !p.is_empty()) {
        for (name, material) in MATERIALS.into_iter().filter(|(n, _)| chosen(n)) {
            let t0 = Instant::now();
            let table = scene(material, probe, "method = \"reflection\"");
            let t = table
                .environment
                .reflection_term()
                .expect("a reflection term");
            eprintln!(
                "{name} under {probe}: {}; prepared in {:.2} s (probe load and material \
                 included), {:.1} MB, measured error {:?}",
                t.path().describe(),
                t0.elapsed().as_secs_f64(),
                t.bytes() as f64 / 1e6,
                t.table().map(|t| t.error())
            );
            let lloyd = scene(material, probe, "method = \"lights\"\ncount = 128");
            let mut g = c.benchmark_group(format!("teapot-640x480-{name}-{probe}"));
            g.sample_size(20);
            let frame = RenderOptions::default();
            g.bench_function("frame-reflection", |b| {
                b.iter(|| render::render(&table, &frame))
            });
            g.bench_function("frame-lloyd-128", |b| {
                b.iter(|| render::render(&lloyd, &frame))
            });
            // The accurate method `auto` chooses for these materials: 0.15-4 s a frame, so
            // ten samples (the cut and its tree prepared once, outside the samples).
            let cuts = scene(material, probe, "method = \"lightcuts\"");
            g.sample_size(10);
            g.measurement_time(std::time::Duration::from_secs(1));
            g.bench_function("frame-lightcuts", |b| {
                b.iter(|| render::render(&cuts, &frame))
            });
            g.finish();
        }
    }
}

/// The frame at each order of `BRDFKIT_BENCH_ORDERS` (module doc).
fn psi_order(c: &mut Criterion) {
    let orders = std::env::var("BRDFKIT_BENCH_ORDERS").unwrap_or_else(|_| "2,6".into());
    let glossy = "kind = \"blinn-phong\"\nkd = [0.05, 0.05, 0.05]\nks = [0.9, 0.9, 0.9]\n\
                  exponent = 200";
    let mut g = c.benchmark_group("teapot-640x480-blinn-phong-200-glossy-city");
    g.sample_size(20);
    for order in orders.split(',').filter(|o| !o.is_empty()) {
        let t0 = Instant::now();
        let s = scene(
            glossy,
            "city",
            &format!("method = \"reflection\"\nreflection_order = {order}"),
        );
        let t = s.environment.reflection_term().expect("a reflection term");
        eprintln!(
            "order {order}: prepared in {:.2} s (probe load and material included), {:.1} MB, \
             measured error {:?}",
            t0.elapsed().as_secs_f64(),
            t.bytes() as f64 / 1e6,
            t.table().map(|t| t.error())
        );
        let frame = RenderOptions::default();
        g.bench_function(format!("frame-reflection-order-{order}"), |b| {
            b.iter(|| render::render(&s, &frame))
        });
    }
    g.finish();
}

criterion_group!(benches, reflection, psi_order);
criterion_main!(benches);
