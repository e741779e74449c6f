//! Preparing an environment, per method and probe size: what the first render of a probe
//! costs (`brdfkit render --no-cache`), probe file read and decode included, no cache.
//!
//! Rows `prepare/<method>/<size>`: the transfer table (teal-paint, 8 bands, the default
//! 128 x 65 grid and 64 exact texels), the light tree of light cuts, the delta-light set
//! of `method = "lights"` (the default sampler: Lloyd, 128 lights), and the reflection table
//! of the default Blinn-Phong (`kind = "blinn-phong"`, exponent 60; the default 64 x 64
//! cells, 13 + 1 slices, 64 exact lights), each from the shipped city probe (512 x 256) and
//! from city upsampled bilinearly to 4096 x 2048 ([`upsample_bilinear`], written once to a
//! temporary directory), the size people download. Ten samples a row (the big rows take
//! seconds each; a reflection bake one per sample, flat sampling, no warm-up to speak of).
//!
//! ```sh
//! cargo bench --bench prepare -- --noplot
//! cargo bench --bench prepare -- --noplot 'prepare/transfer'
//! ```
//!
//! Measured (2026-12-04, 2 cores shared with two other sessions' builds, load average
//! 3.3-4.1; wall times move by 2x with the load, so the transfer rows come from one
//! interleaved run, the bench binary before and after the transfer build's rework, before,
//! after, before, after):
//!
//! | row | before | after | before | after |
//! |---|---|---|---|---|
//! | transfer/512x256 | 3.01 s | 1.68 s | 2.98 s | 0.842 s |
//! | transfer/4096x2048 | 3.30 s | 1.92 s | 1.79 s | 1.75 s |
//!
//! The transfer table keeps its bits (the golden images under `method = "transfer"`): the
//! same f64 operations in the same order, fewer repeated ones (the SH recurrence's
//! constants once per build, four columns per recurrence on vectorised lanes, the
//! multiply-adds on split real and imaginary arrays). What bounds it now: the
//! `65 x 256 x 32` FFTs of 512 points (a third of the profile) and the
//! `3 x 64 x 257` complex multiply-adds per table row and probe row.
//!
//! The multiply-adds on the f64 lanes (2026-12-05, `src/env/transfer/correlate.rs`: the
//! correlation's `P conj(W)` sums and the unpacking of the paired weight transforms on
//! [`F64x4`](brdfkit::lanes::F64x4), never fused, and the weights' SH recurrence compiled
//! inside the same AVX-512 kernel; the same bits on every kernel path, the golden images
//! unchanged). Main's bench binary (A) and the branch's (B), each built once and copied to
//! /tmp, run alternately A, B, A, B with
//! `perf stat -e task-clock BIN --bench --noplot 'prepare/transfer/<size>'` (criterion's
//! mean and the process's CPU time: one warm-up and ten timed iterations, plus about 1.1 s
//! of set-up, the 4096 x 2048 probe's upsampling, in every process); load average 3.5-4.0
//! on the 2 cores, so the wall times are 2-3 times the 0.842 s above:
//!
//! | row | A | B | A | B |
//! |---|---|---|---|---|
//! | transfer/512x256 wall | 2.05 s | 1.76 s | 2.63 s | 2.31 s |
//! | transfer/512x256 CPU, process | 24.5 s | 20.4 s | 29.5 s | 26.3 s |
//! | transfer/4096x2048 wall | 2.76 s | 2.64 s | 2.95 s | 2.23 s |
//! | transfer/4096x2048 CPU, process | 31.5 s | 30.6 s | 33.9 s | 25.2 s |
//!
//! About 11-17% less CPU, short of 0.5 s for 512 x 256. On the quiet machine afterwards
//! (an Intel Xeon host, load average under 2, the same two binaries alternately, A, B, A,
//! B, `--bench --noplot 'prepare/transfer'`): 512 x 256 **1.38, 1.33, 1.75, 1.48 s**;
//! 4096 x 2048 1.74, 1.86, 2.25, 2.20 s (within the noise). This host is slower than the
//! one of the 0.842 s above. The profile after
//! (`perf record` on the bench binary, samples by source line): rustfft's 512-point
//! transforms 24%, the multiply-adds 20%, the weights (SH recurrence and their term-major
//! stores) 25%, packing and unpacking the transforms 13%. Each is now the same bits done
//! as fast as four f64 lanes allow; what is left would change the bits (the mirror
//! symmetry of node row `j` and probe row `r` with `nv - 1 - j` and `h - 1 - r` halves the
//! weights and transforms, but the texel directions are not mirror images to the last bit)
//! or needs eight f64 lanes ([`brdfkit::lanes`] has four).
//!
//! The other rows, one run after (load average 3.6-4.1): light cuts 91.7 ms (512 x 256)
//! and 4.91 s (4096 x 2048); lights 333 ms and 1.48 s; reflection 9.87 s and 15.3 s.
//! Peak memory of `brdfkit render --env PROBE [--material teal-paint] --env-method METHOD
//! --no-cache --width 320 --height 240` (`/usr/bin/time -v`, the 4096 x 2048 probe from
//! `cargo run --release --example upsample_probe -- assets/probes/city.exr DIR 4096`):
//! transfer 242 MB, light cuts 943 MB, reflection 555 MB (1087 MB before its full-resolution
//! reference stopped copying the residual); at 512 x 256, transfer 85 MB, reflection 73 MB.

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
