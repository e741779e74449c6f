//! GPU frame time beside the CPU's (cargo feature `gpu`; `cargo bench --features gpu --bench
//! gpu_frame`): the 640x480 teapot in the thesis's configurations (as benches/kernel.rs:
//! 5 and 8 SH orders with one point light and with 128 median-cut city lights, D-BRDF with 1
//! and 128), each rendered by the CPU kernels (`render::render`) and by the wgpu renderer
//! (`Gpu::render`: upload, draw, read-back; the device opened once), alternately in one
//! run. On this machine the adapter is lavapipe (Mesa's CPU Vulkan driver), so the GPU
//! numbers are a software rasterizer's, not a GPU's.

use brdfkit::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use brdfkit::gpu::{Faults, Gpu};
use brdfkit::render;
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;

/// The allocator the `brdfkit` binary uses (src/main.rs), so frames are timed as they run.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn scene(material: MaterialSpec, env_lights: Option<usize>) -> Scene {
    let mut f = SceneFile {
        material,
        ..SceneFile::default()
    };
    match env_lights {
        Some(n) => {
            let mut env =
                EnvSpec::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr"));
            env.method = EnvMethod::Lights;
            env.sampler = SamplerKind::MedianCut;
            env.count = n;
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
    let gpu = Gpu::new().expect("a GPU adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    let mut g = c.benchmark_group("gpu-vs-cpu-640x480");
    g.sample_size(10);
    let lib = |n: &str| MaterialSpec::Library {
        name: n.into(),
        lookup: None,
    };
    for (name, material, env) in [
        ("sh5-point", lib("magenta-plastic"), None),
        ("sh8-point", lib("gold-dust-paint-sh-ringing"), None),
        ("sh5-128", lib("magenta-plastic"), Some(128)),
        ("sh8-128", lib("gold-dust-paint-sh-ringing"), Some(128)),
        ("dbrdf-point", lib("lindt-paper"), None),
        ("dbrdf-128", lib("lindt-paper"), Some(128)),
    ] {
        let s = scene(material, env);
        g.bench_function(format!("cpu/{name}"), |b| {
            b.iter(|| render::render(&s, &Default::default()).image)
        });
        g.bench_function(format!("gpu/{name}"), |b| {
            b.iter(|| gpu.render(&s, Faults::NONE).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
