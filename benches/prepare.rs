//! Preparing an environment, per method and probe size: what the first render of a probe
//! costs (`brdfkit render --no-cache`), probe file read and decode included, no cache.
//!
//! Rows `prepare/<method>/<size>`: the transfer table (teal-paint, 8 bands, the default
//! 128 x 65 grid and 64 exact texels), the light tree of light cuts, and the delta-light set
//! of `method = "lights"` (the default sampler: Lloyd, 128 lights), each from the shipped
//! city probe (512 x 256) and from city upsampled bilinearly to 4096 x 2048
//! ([`upsample_bilinear`], written once to a temporary directory), the size people
//! download. Ten samples a row (the big rows take seconds each).
//!
//! ```sh
//! cargo bench --bench prepare -- --noplot
//! ```
//!
//! Measured (2026-12-03, 2 cores shared with other builds, load average 5-8): transfer
//! 3.29 s (512 x 256) and 4.43 s (4096 x 2048); light cuts 0.119 s and 8.51 s; lights
//! 0.467 s and 2.17 s. At 512 x 256 the transfer table is projected texel by texel (the
//! shipped probes keep their bits): its SH weights and per-row multiply-adds bound it.

use brdfkit::env::lightcuts::prepare_lightcuts;
use brdfkit::env::lightset::prepare::prepare;
use brdfkit::env::probe::resample::upsample_bilinear;
use brdfkit::env::reflection::prepare_reflection;
use brdfkit::env::transfer::{prepare_transfer, TransferBasis};
use brdfkit::env::{EnvMethod, EnvSpec, LoadOptions, Probe};
use brdfkit::image_io::{write_exr, Image};
use brdfkit::progress::Progress;
use brdfkit::scene::{Scene, SceneFile};
use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use glam::Vec3;
use std::path::Path;
use std::time::Duration;

/// The allocator the `brdfkit` binary uses (src/main.rs), so preparation is timed as it runs.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn prepare_rows(c: &mut Criterion) {
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let city = base.join("assets/probes/city.exr");
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let (probe, _) = Probe::load(&city, &LoadOptions::default()).expect("the shipped city probe");
    let (w, h) = (4096, 2048);
    let big = tmp.path().join(format!("city-{w}x{h}.exr"));
    let image = Image {
        width: w as u32,
        height: h as u32,
        pixels: upsample_bilinear(&probe, w, h)
            .into_iter()
            .map(Vec3::from)
            .collect(),
    };
    write_exr(&big, &image).expect("the upsampled probe written");
    drop(image);
    let teal = SceneFile::parse("[material]\nkind = \"library\"\nname = \"teal-paint\"\n")
        .expect("a scene file");
    let material = Scene::resolve(&teal, base)
        .expect("the library's teal paint")
        .material;
    let basis = TransferBasis::for_material(&material).expect("an SH data set");
    let blinn = SceneFile::parse("[material]\nkind = \"blinn-phong\"\n").expect("a scene file");
    let blinn = Scene::resolve(&blinn, base)
        .expect("the default Blinn-Phong")
        .material;
    let mut g = c.benchmark_group("prepare");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for (size, file) in [("512x256", city.clone()), ("4096x2048", big.clone())] {
        let spec = |method: EnvMethod| EnvSpec {
            method,
            ..EnvSpec::new(file.clone())
        };
        let transfer = spec(EnvMethod::Transfer);
        g.bench_function(format!("transfer/{size}"), |b| {
            b.iter(|| prepare_transfer(&transfer, base, basis, None, &Progress::hidden()).unwrap())
        });
        let cuts = spec(EnvMethod::Lightcuts);
        g.bench_function(format!("lightcuts/{size}"), |b| {
            b.iter(|| prepare_lightcuts(&cuts, base, &Progress::hidden()).unwrap())
        });
        let lights = spec(EnvMethod::Lights);
        g.bench_function(format!("lights/{size}"), |b| {
            b.iter(|| prepare(&lights, base, None).unwrap())
        });
        // A bake takes seconds: the fewest samples criterion takes, one bake each.
        let reflection = spec(EnvMethod::Reflection);
        g.sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_millis(1));
        g.bench_function(format!("reflection/{size}"), |b| {
            b.iter(|| {
                prepare_reflection(&reflection, base, &blinn, None, &Progress::hidden()).unwrap()
            })
        });
        g.sampling_mode(SamplingMode::Auto)
            .warm_up_time(Duration::from_millis(500));
    }
    g.finish();
}

criterion_group!(benches, prepare_rows);
criterion_main!(benches);
