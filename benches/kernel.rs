//! Benches of the shading kernel (docs/benchmarks.md):
//! (a) SH kernel throughput in (pixel x light x SH term) per second, beside this machine's
//!     f32 multiply-add peak measured in the same run by a companion micro-bench;
//! (b) frame time of the 640x480 teapot in the thesis's configurations: 5 and 8 orders with
//!     one point light, 5 and 8 orders with 128 median-cut lights, D-BRDF with 1 and 128;
//! (c) the same frames and a 640x480 sphere (the llvmpipe comparison scene) on each kernel
//!     path this CPU runs, plus the default scene on the scalar oracle (the kernel path must
//!     beat it), for A/B runs of one path against another.

use brdfkit::conventions::ShadingFrame;
use brdfkit::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use brdfkit::kernel::cluster::DirLights;
use brdfkit::kernel::gather::Scratch;
use brdfkit::kernel::sh::{shade_pixel, ShRecurrence};
use brdfkit::lanes::{Arith, Dispatch, Isa, Kernel, KernelPath, Width};
use brdfkit::light::Light;
use brdfkit::render::{self, RenderOptions};
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use brdfkit::shade::{ShadeOptions, ShadingPath};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec3;
use std::hint::black_box;
use std::path::Path;

/// The allocator the `brdfkit` binary uses (src/main.rs), so frames are timed as they run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Independent fused multiply-add chains on the path's widest vectors ([`Arith::fma`], the
/// kernel's instruction: 8-lane FMA on AVX2, 16-lane on AVX-512): the path's peak for the
/// kernel's mix.
struct MaddPeak {
    iters: usize,
    seed: f32,
}

impl Kernel for MaddPeak {
    type Out = f32;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> f32 {
        let w = s.wide();
        let m = w.splat(0.999_999);
        let a = w.splat(1e-7);
        let mut acc = [w.splat(self.seed); 10];
        for _ in 0..self.iters {
            for v in acc.iter_mut() {
                *v = v.fma(m, a);
            }
        }
        let mut out = [0.0f32; 16];
        acc.iter()
            .map(|v| {
                w.store(*v, &mut out);
                out.iter().sum::<f32>()
            })
            .sum()
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
    // Per path: 10 chains x N lanes x 1 fused multiply-add per iteration (one core).
    for path in KernelPath::available() {
        let d = Dispatch::choose(path).unwrap();
        let lanes = match path {
            KernelPath::Avx512 => 16,
            _ => 8,
        };
        g.throughput(Throughput::Elements((iters * 10 * lanes) as u64));
        g.bench_function(format!("f32x{lanes}-{}", d.name()), |b| {
            b.iter(|| {
                d.run(MaddPeak {
                    iters: black_box(iters),
                    seed: black_box(1.0),
                })
            })
        });
    }
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
        // On each SIMD path (portable, libm's fmaf per lane where the target has no FMA, is
        // far slower and left out).
        for path in KernelPath::available() {
            if path == KernelPath::Portable {
                continue;
            }
            let d = Dispatch::choose(path).unwrap();
            g.bench_with_input(
                BenchmarkId::new(
                    format!("128-lights-{}", path.name()),
                    format!("{bands}-orders"),
                ),
                &bands,
                |b, _| {
                    let mut scratch = Scratch::default();
                    scratch.reserve(dl.len());
                    b.iter(|| {
                        black_box(d.run(ShPixels {
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
    }
    g.finish();
}

fn scene(material: MaterialSpec, env_lights: Option<usize>) -> Scene {
    Scene::resolve(&scene_file(material, env_lights), Path::new("/")).unwrap()
}

fn scene_file(material: MaterialSpec, env_lights: Option<usize>) -> SceneFile {
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
    f
}

fn frames(c: &mut Criterion) {
    let mut g = c.benchmark_group("frame-640x480");
    g.sample_size(20);
    let lib = |n: &str| MaterialSpec::Library {
        name: n.into(),
        lookup: None,
    };
    // magenta-plastic: 5 orders; gold-dust-paint-sh-ringing: 8 orders; lindt-paper: D-BRDF.
    for (name, material, env) in [
        ("sh5-point", lib("magenta-plastic"), None),
        ("sh8-point", lib("gold-dust-paint-sh-ringing"), None),
        ("sh5-128", lib("magenta-plastic"), Some(128)),
        ("sh8-128", lib("gold-dust-paint-sh-ringing"), Some(128)),
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

/// The sphere of the llvmpipe comparison: a 640x480 UV sphere filling most of the frame,
/// with `material` and the same light choices as [`scene`].
fn sphere(material: MaterialSpec, env_lights: Option<usize>) -> Scene {
    let mut f = scene_file(material, env_lights);
    f.mesh = SceneFile::parse("[mesh]\nsource = \"sphere\"\nsegments = 64\n")
        .unwrap()
        .mesh;
    Scene::resolve(&f, Path::new("/")).unwrap()
}

fn frames_per_path(c: &mut Criterion) {
    let mut g = c.benchmark_group("frame-path");
    g.sample_size(10);
    let lib = |n: &str| MaterialSpec::Library {
        name: n.into(),
        lookup: None,
    };
    let scenes = [
        (
            "default",
            Scene::resolve(&SceneFile::default(), Path::new("/")).unwrap(),
        ),
        ("sh5-point", scene(lib("magenta-plastic"), None)),
        (
            "sh8-128",
            scene(lib("gold-dust-paint-sh-ringing"), Some(128)),
        ),
        (
            "sh8-512",
            scene(lib("gold-dust-paint-sh-ringing"), Some(512)),
        ),
        ("dbrdf-128", scene(lib("lindt-paper"), Some(128))),
        ("sphere-sh5-point", sphere(lib("magenta-plastic"), None)),
        (
            "sphere-sh8-128",
            sphere(lib("gold-dust-paint-sh-ringing"), Some(128)),
        ),
        (
            "sphere-sh8-512",
            sphere(lib("gold-dust-paint-sh-ringing"), Some(512)),
        ),
        ("sphere-dbrdf-128", sphere(lib("lindt-paper"), Some(128))),
    ];
    for (name, s) in &scenes {
        // The work of one frame, to turn times into G FMA/s: SH bands used, pixels shaded,
        // (pixel, light) pairs handed to the kernel (per tile: its pixels times the lights
        // its normal cone keeps) and those the kernels summed (`ShadeCounts::pairs_summed`).
        let st = render::render(
            s,
            &RenderOptions {
                stats: true,
                ..RenderOptions::default()
            },
        )
        .stats
        .unwrap();
        // The FMAs the frame needs: SH, 3 bands^2 per (pixel, light) pair the kernels
        // summed, to set beside madd-peak. On the per-pixel path those are the pairs above
        // the horizon (the pairs the FMA-peak target counts, docs/benchmarks.md); on the
        // pixel-packed point-light path every pixel-light pair, so there it is an upper bound.
        let bands = st.sh_bands_used as u64;
        eprintln!(
            "frame-path {name}: {} pixels shaded, {} pairs handed to the kernel, {} summed \
             in {} lane slots, SH bands {}, {:.3} G coefficient FMAs",
            st.shade.pixels_shaded,
            st.shade.light_pairs,
            st.shade.pairs_summed,
            st.shade.lane_slots,
            bands,
            (st.shade.pairs_summed * 3 * bands * bands) as f64 * 1e-9
        );
        let mut paths: Vec<(String, ShadeOptions)> = KernelPath::available()
            .into_iter()
            .filter(|p| *p != KernelPath::Portable)
            .map(|p| {
                let o = ShadeOptions {
                    kernel: Some(p),
                    ..ShadeOptions::default()
                };
                (p.name().to_string(), o)
            })
            .collect();
        if *name == "default" {
            let o = ShadeOptions {
                path: Some(ShadingPath::ScalarOracle),
                ..ShadeOptions::default()
            };
            paths.push(("scalar-oracle".into(), o));
        }
        for (path, shading) in paths {
            let opts = RenderOptions {
                shading,
                ..RenderOptions::default()
            };
            g.bench_function(format!("{name}/{path}"), |b| {
                b.iter(|| render::render(s, &opts).image)
            });
        }
    }
    g.finish();
}

criterion_group!(benches, kernel_throughput, frames, frames_per_path);
criterion_main!(benches);
