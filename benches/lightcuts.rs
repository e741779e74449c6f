//! Frame time at 640x480 of a sphere (256 segments, ~91k shaded pixels) with
//! `[env] method = "lightcuts"` (default `cut_error` 1%, `cut_max` 1000), Blinn-Phong
//! exponent 200 and the library D-BRDF `lindt-paper`, under the shipped city and studio
//! probes; the light-cut method's target is >= 30 frames/s on this 2-core machine. The
//! light tree's build time (probe load included) is measured once per probe and printed
//! beside it, with each frame's mean cut size.
//!
//! A/B in one run: per probe and material, one frame of per-pixel cuts (the reference,
//! `ShadingPath::ScalarOracle`, timed once: it takes seconds), then the shared cuts (one cut
//! per square of <= 8 x 8 pixels, the default path) by criterion.
//!
//! Measured (2026-11-30, 2 cores shared with other helpers' builds; `cargo bench --bench
//! lightcuts -- --warm-up-time 1 --measurement-time 3 --noplot`), shade only:
//! city Blinn-Phong 200: per-pixel 3.36 s (mean cut 251) vs shared 0.705 s (4884 cuts,
//! mean cut 372), 1.4 frames/s; city lindt-paper: 12.9 s (379) vs 1.93 s (822, 40% of
//! pixels at cut_max); studio Blinn-Phong 200: 5.84 s (239) vs 1.21 s (347); studio
//! lindt-paper: 23.6 s (359) vs 2.66 s (674, 17% capped). Tree build 0.10-0.12 s.
//! Still 20-80x short of 30 frames/s. What bounds it (perf, city Blinn-Phong): 34% scalar
//! `powf` in the Blinn-Phong lane model (one per pixel and light: 162k pixels x ~370
//! lights x refine rounds), 30% the lane kernel, 16% the tile bounds and cluster
//! estimates. The D-BRDF's tile bound is loose (the `cos(polar_o)` factor and the widened
//! half-vector box), so its cuts double and often reach `cut_max`.

use brdfkit::env::lightcuts::prepare_lightcuts;
use brdfkit::progress::Progress;
use brdfkit::render::{self, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::shade::{self, ShadeOptions, ShadingPath};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::time::Instant;

/// The allocator the `brdfkit` binary uses (src/main.rs), so frames are timed as they run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn scene_text(material: &str, probe: &str) -> String {
    format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 256\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\nmethod = \"lightcuts\"\n\
         [render]\nwidth = 640\nheight = 480\n"
    )
}

fn lightcuts(c: &mut Criterion) {
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let materials = [
        ("blinn-phong-200", "kind = \"blinn-phong\"\nexponent = 200"),
        ("lindt-paper", "kind = \"library\"\nname = \"lindt-paper\""),
    ];
    let mut g = c.benchmark_group("lightcuts-sphere-640x480");
    g.sample_size(10);
    for probe in ["city", "studio"] {
        for (name, material) in materials {
            let file = SceneFile::parse(&scene_text(material, probe)).unwrap();
            let scene = Scene::resolve(&file, base).unwrap();
            let t0 = Instant::now();
            let p =
                prepare_lightcuts(file.env.as_ref().unwrap(), base, &Progress::hidden()).unwrap();
            let build = t0.elapsed().as_secs_f64();
            let vis = render::rasterize(&scene, false);
            // A: the per-pixel cut (the reference path), one frame timed here, as it takes
            // seconds; B: the shared cuts (the default path), timed by criterion.
            let per_pixel = ShadeOptions::default().with_path(ShadingPath::ScalarOracle);
            let t0 = Instant::now();
            let a = shade::shade(&scene, &vis, &per_pixel).report.cuts;
            let a_secs = t0.elapsed().as_secs_f64();
            let fast = ShadeOptions::default();
            let t0 = Instant::now();
            let b = shade::shade(&scene, &vis, &fast).report.cuts;
            let b_secs = t0.elapsed().as_secs_f64();
            eprintln!(
                "{probe} {name}: tree build (probe load included) {build:.2} s, {} nodes; \
                 {} pixels; per-pixel cuts: {a_secs:.2} s, mean cut {:.1}, largest {}, \
                 capped {}; shared cuts: {b_secs:.3} s (one frame), {} cuts, mean cut {:.1}, \
                 largest {}, capped {}",
                p.cuts.tree.len(),
                a.pixels,
                a.mean(),
                a.largest,
                a.capped,
                b.tiles,
                b.mean(),
                b.largest,
                b.capped
            );
            g.bench_function(format!("{probe}-{name}-shade"), |b| {
                b.iter(|| shade::shade(&scene, &vis, &fast))
            });
            let frame = RenderOptions::default();
            g.bench_function(format!("{probe}-{name}-frame"), |b| {
                b.iter(|| render::render(&scene, &frame))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, lightcuts);
criterion_main!(benches);
