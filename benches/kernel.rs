//! Kernel benches (issue "fast shading kernel"):
//! (a) SH kernel throughput in (pixel x light x SH term) per second, beside this machine's
//!     f32 multiply-add peak measured in the same run by a companion micro-bench;
//! (b) frame time of the 640x480 teapot in the thesis's configurations: 5 and 8 orders with
//!     one point light, 5 and 8 orders with 128 median-cut lights, D-BRDF with 1 and 128.

use brdfkit::conventions::ShadingFrame;
use brdfkit::env::prepare::{EnvMethod, EnvSpec, SamplerKind};
use brdfkit::kernel::cluster::DirLights;
use brdfkit::kernel::gather::Scratch;
use brdfkit::kernel::lanes::{Dispatch, F32x8, Isa, Kernel, LANES};
use brdfkit::kernel::sh::{shade_pixel, ShRecurrence};
use brdfkit::light::Light;
use brdfkit::render;
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::path::Path;

/// The allocator the `brdfkit` binary uses (src/main.rs), so frames are timed as they run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Independent fused multiply-add chains on eight lanes ([`F32x8::mul_add`], the kernel's
/// instruction: FMA on the AVX2+FMA path): the machine's peak for the kernel's mix.
struct MaddPeak {
    iters: usize,
    seed: f32,
}

impl Kernel for MaddPeak {
    type Out = f32;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> f32 {
        let m = s.splat(0.999_999);
        let a = s.splat(1e-7);
        let mut acc = [s.splat(self.seed); 10];
        for _ in 0..self.iters {
            for v in acc.iter_mut() {
                *v = v.mul_add(m, a);
            }
        }
        acc.iter().map(|v| v.sum()).sum()
    }
}

/// Many pixels through the SH kernel, on the dispatched instruction set.
struct ShPixels<'a> {
    rec: &'a ShRecurrence,
    coeffs: &'a [f32],
    frames: &'a [ShadingFrame],
    lights: &'a DirLights,
    chunks: &'a [u32],
    scratch: &'a mut Scratch,
}

impl Kernel for ShPixels<'_> {
    type Out = Vec3;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for f in self.frames {
            sum += shade_pixel(
                s,
                self.rec,
                self.coeffs,
                true,
                f,
                self.lights,
                self.chunks,
                self.scratch,
            );
        }
        sum
    }
}

fn lights(n: usize) -> DirLights {
    let ls: Vec<Light> = (0..n)
        .map(|i| {
            let t = i as f32 / n as f32;
            let polar = (1.0 - 2.0 * ((i as f32 * 0.618_034) % 1.0)).acos();
            let az = std::f32::consts::TAU * t * 13.0;
            Light::Directional {
                to_light: Vec3::new(polar.sin() * az.cos(), polar.cos(), polar.sin() * az.sin()),
                irradiance: Vec3::splat(0.1),
            }
        })
        .collect();
    DirLights::from_lights(&ls)
}

fn kernel_throughput(c: &mut Criterion) {
    let mut g = c.benchmark_group("madd-peak");
    let iters = 100_000;
    let isa = Dispatch::detect();
    eprintln!("kernel instruction set: {}", isa.name());
    // 10 chains x 8 lanes x 1 fused multiply-add per iteration: count multiply-adds.
    g.throughput(Throughput::Elements((iters * 10 * LANES) as u64));
    g.bench_function(format!("f32x8-{}", isa.name()), |b| {
        b.iter(|| {
            isa.run(MaddPeak {
                iters: black_box(iters),
                seed: black_box(1.0),
            })
        })
    });
    g.finish();

    let mut g = c.benchmark_group("sh-kernel");
    for bands in [5usize, 8] {
        let t = bands * bands;
        let rec = ShRecurrence::new(bands);
        let coeffs: Vec<f32> = (0..3 * t).map(|k| 1.0 / (1.0 + k as f32)).collect();
        let dl = lights(128);
        let all: Vec<u32> = (0..dl.chunks() as u32).collect();
        let pixels = 256;
        let frames: Vec<ShadingFrame> = (0..pixels)
            .map(|i| {
                let a = i as f32 * 0.1;
                ShadingFrame::from_normal(Vec3::new(a.sin() * 0.5, 1.0, a.cos() * 0.5))
            })
            .collect();
        // Counted work: every pixel x every light x every term (lights below a pixel's horizon
        // included, as the thesis's shader does them; the kernel masks them per chunk).
        g.throughput(Throughput::Elements((pixels * dl.len() * t) as u64));
        g.bench_with_input(
            BenchmarkId::new("128-lights", format!("{bands}-orders")),
            &bands,
            |b, _| {
                let mut scratch = Scratch::default();
                scratch.reserve(dl.len());
                b.iter(|| {
                    black_box(isa.run(ShPixels {
                        rec: &rec,
                        coeffs: &coeffs,
                        frames: &frames,
                        lights: &dl,
                        chunks: &all,
                        scratch: &mut scratch,
                    }))
                })
            },
        );
    }
    g.finish();
}

fn scene(material: MaterialSpec, env_lights: Option<usize>) -> Scene {
    let mut f = SceneFile {
        material,
        ..SceneFile::default()
    };
    match env_lights {
        Some(n) => {
            let mut env =
                EnvSpec::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr"));
            env.sampler = SamplerKind::MedianCut;
            env.count = n;
            env.method = EnvMethod::Lights;
            f.env = Some(env);
        }
        None => {
            f.lights = Some(
                SceneFile::parse(
                    "[[light]]\nkind = \"point\"\nposition = [4.0, 6.0, 6.0]\nintensity = 60.0\n",
                )
                .unwrap()
                .lights
                .unwrap(),
            );
        }
    }
    Scene::resolve(&f, Path::new("/")).unwrap()
}

fn frames(c: &mut Criterion) {
    let mut g = c.benchmark_group("frame-640x480");
    g.sample_size(20);
    let lib = |n: &str| MaterialSpec::Library {
        name: n.into(),
        lookup: None,
    };
    // magenta-plastic: 5 orders; gold-dust-paint: 8 orders; lindt-paper: D-BRDF.
    for (name, material, env) in [
        ("sh5-point", lib("magenta-plastic"), None),
        ("sh8-point", lib("gold-dust-paint"), None),
        ("sh5-128", lib("magenta-plastic"), Some(128)),
        ("sh8-128", lib("gold-dust-paint"), Some(128)),
        ("dbrdf-point", lib("lindt-paper"), None),
        ("dbrdf-128", lib("lindt-paper"), Some(128)),
    ] {
        let s = scene(material, env);
        g.bench_function(name, |b| {
            b.iter(|| render::render(&s, &Default::default()).image)
        });
    }
    g.finish();
}

criterion_group!(benches, kernel_throughput, frames);
criterion_main!(benches);
