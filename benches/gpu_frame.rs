//! GPU frame time beside the CPU's (cargo feature `gpu`; `cargo bench --features gpu --bench
//! gpu_frame`): the 640x480 teapot in the thesis's configurations (as benches/kernel.rs:
//! 5 and 8 SH orders with one point light and with 128 median-cut city lights, D-BRDF with 1
//! and 128), each rendered by the CPU kernels (`render::render`) and by the wgpu renderer
//! (`Gpu::render`: upload, draw, read-back; the device opened once), alternately in one
//! run. On this machine the adapter is lavapipe (Mesa's CPU Vulkan driver), so the GPU
//! numbers are a software rasterizer's, not a GPU's.
//!
//! Group `llvmpipe-scene-640x480`: the scene of the comparison with Mesa's llvmpipe (a GLSL
//! port of the SH-sum shader on the same two cores), so that anyone can run it: a UV sphere
//! of 128 segments x 80 stacks (20,224 triangles, vertex normals interpolated, no exact
//! sphere), 640 x 480, vertical field of view 40 degrees, camera at (0, 0, 4) looking at
//! the origin, in the configurations 5 bands x 1 point light, 5 x 128 median-cut city
//! lights, 8 x 1 and 8 x 128. The `cpu/` rows are brdfkit's side of that comparison. The
//! `gpu/` rows are not llvmpipe's frame: like every row of this bench they time a whole
//! `Gpu::render` call (upload, pipeline creation, lavapipe's compilation of the shader,
//! draw, read-back), where the comparison timed frames of a GLSL program compiled once.
//! Measured (2026-12-04, both cores shared with two builds, load average about 5):
//! cpu 28.5 / 106 / 25.4 / 119 ms, gpu 0.92 / 6.96 / 0.98 / 13.8 s for 5x1 / 5x128 / 8x1 /
//! 8x128.
//!
//! ```sh
//! cargo bench --features gpu --bench gpu_frame -- llvmpipe-scene --noplot
//! ```

use brdfkit::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use brdfkit::gpu::{Faults, Gpu};
use brdfkit::mesh::Mesh;
use brdfkit::render;
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use std::f32::consts::{PI, TAU};
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

/// The comparison's sphere: unit radius, `segments` x `stacks`, a ring of vertices per
/// stack boundary (the seam's column duplicated, as a textured GL sphere has it), normals
/// equal to positions, triangles counter-clockwise from outside.
fn uv_sphere_grid(segments: u32, stacks: u32) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..=stacks {
        let (sp, cp) = (PI * i as f32 / stacks as f32).sin_cos();
        for j in 0..=segments {
            let (sa, ca) = (TAU * j as f32 / segments as f32).sin_cos();
            m.positions.push(Vec3::new(sp * sa, cp, sp * ca));
        }
    }
    let at = |i: u32, j: u32| i * (segments + 1) + j;
    for i in 0..stacks {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            // The poles' quads are triangles: skip the one with two pole vertices.
            if i + 1 < stacks {
                m.triangles.push([a, b, c]);
            }
            if i > 0 {
                m.triangles.push([a, c, d]);
            }
        }
    }
    m.normals = m.positions.clone();
    m
}

fn llvmpipe_scene(c: &mut Criterion) {
    let gpu = Gpu::new().expect("a GPU adapter (lavapipe: apt-get install mesa-vulkan-drivers)");
    let mut g = c.benchmark_group("llvmpipe-scene-640x480");
    g.sample_size(10);
    let sphere = std::sync::Arc::new(uv_sphere_grid(128, 80));
    let lib = |n: &str| MaterialSpec::Library {
        name: n.into(),
        lookup: None,
    };
    for (name, material, env) in [
        ("sh5-point", lib("magenta-plastic"), None),
        ("sh5-128", lib("magenta-plastic"), Some(128)),
        ("sh8-point", lib("gold-dust-paint-sh-ringing"), None),
        ("sh8-128", lib("gold-dust-paint-sh-ringing"), Some(128)),
    ] {
        let mut s = scene(material, env);
        s.mesh = sphere.clone();
        s.camera.position = Vec3::new(0.0, 0.0, 4.0);
        s.camera.target = Vec3::ZERO;
        s.camera.up = Vec3::Y;
        s.camera.fov_y_deg = 40.0;
        g.bench_function(format!("cpu/{name}"), |b| {
            b.iter(|| render::render(&s, &Default::default()).image)
        });
        g.bench_function(format!("gpu/{name}"), |b| {
            b.iter(|| gpu.render(&s, Faults::NONE).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, frames, llvmpipe_scene);
criterion_main!(benches);
