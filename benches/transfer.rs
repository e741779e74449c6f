//! Frame time at 640x480 of an 8-band SH material (library `teal-paint`) on a sphere under
//! the shipped city probe with `[env] method = "transfer"` (128 x 65 table, 64 exact
//! lights), the transfer-table method's target being >= 100 frames/s; the table build time
//! is measured once and printed beside it (it runs once per scene, far too long for
//! criterion's samples).

use brdfkit::env::transfer::{prepare_transfer, TransferBasis};
use brdfkit::progress::Progress;
use brdfkit::render::{self, RenderOptions};
use brdfkit::scene::{Environment, Scene, SceneFile};
use brdfkit::shade::{self, ShadeOptions};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::time::Instant;

/// The allocator the `brdfkit` binary uses (src/main.rs), so frames are timed as they run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const SCENE: &str = r#"
[mesh]
source = "sphere"
segments = 256
[material]
kind = "library"
name = "teal-paint"
[env]
file = "assets/probes/city.exr"
method = "transfer"
[render]
width = 640
height = 480
"#;

fn transfer(c: &mut Criterion) {
    let file = SceneFile::parse(SCENE).unwrap();
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let t0 = Instant::now();
    let scene = Scene::resolve(&file, base).unwrap();
    eprintln!(
        "scene resolve (library material, probe load, table build): {:.2} s",
        t0.elapsed().as_secs_f64()
    );
    let ds = scene.material.as_sh().expect("an SH material");
    let basis = TransferBasis::Sh {
        bands: ds.bands(),
        cosine: !ds.cosine_included(),
    };
    let spec = file.env.as_ref().unwrap();
    let t1 = Instant::now();
    let p = prepare_transfer(spec, base, basis, None, &Progress::hidden()).unwrap();
    eprintln!(
        "table build alone ({} x {} nodes, {} terms, probe load included): {:.2} s",
        p.table.grid().0,
        p.table.grid().1,
        p.table.terms(),
        t1.elapsed().as_secs_f64()
    );
    let vis = render::rasterize(&scene, false);
    let mut g = c.benchmark_group("transfer-sphere-640x480-8bands");
    let fast = ShadeOptions::default();
    g.bench_function("shade", |b| b.iter(|| shade::shade(&scene, &vis, &fast)));
    let mut table_only = scene.clone();
    table_only.environment = Environment::Transfer {
        table: scene.environment.transfer_table().unwrap().clone(),
        exact: Vec::new(),
    };
    g.bench_function("shade-table-only", |b| {
        b.iter(|| shade::shade(&table_only, &vis, &fast))
    });
    let mut lights_only = scene.clone();
    lights_only.environment = Environment::Lights(scene.environment.delta_lights().to_vec());
    g.bench_function("shade-16-exact-lights-only", |b| {
        b.iter(|| shade::shade(&lights_only, &vis, &fast))
    });
    // The surface rebuild alone (gbuffer.rs): every visible pixel's surface, as the tile
    // loop reconstructs it once per pixel, summed so the work is kept.
    g.bench_function("surfaces-only", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for t in 0..vis.tile_occupied.len() {
                let rect = vis.tile_rect(t);
                shade::for_each_visible(&scene.mesh, &vis, rect, rect.y0, |p| {
                    sum += p.surface.normal.x
                });
            }
            sum
        })
    });
    let frame = RenderOptions::default();
    g.bench_function("frame", |b| b.iter(|| render::render(&scene, &frame)));
    g.finish();
}

criterion_group!(benches, transfer);
criterion_main!(benches);
