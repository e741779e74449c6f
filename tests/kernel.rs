//! The kernels against the scalar oracle, and the work they skip against not skipping it.

use brdfkit::env::prepare::{EnvSpec, SamplerKind};
use brdfkit::kernel::{KERNEL_TOLERANCE, SH_KERNEL_TOLERANCE};
use brdfkit::render;
use brdfkit::scene::{MaterialSpec, Scene, SceneFile};
use brdfkit::shade::{self, FramePrep};
use std::path::Path;

fn scene(material: MaterialSpec, lights: usize) -> Scene {
    let mut f = SceneFile::default();
    f.render.width = 64;
    f.render.height = 48;
    f.material = material;
    let mut env =
        EnvSpec::new(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr"));
    env.sampler = SamplerKind::MedianCut;
    env.count = lights;
    f.env = Some(env);
    // Plus a point light, which takes the scalar path inside the kernel's frame loop.
    f.lights = Some(
        SceneFile::parse(
            "[[light]]\nkind = \"point\"\nposition = [3.0, 5.0, 4.0]\nintensity = 10.0\n",
        )
        .unwrap()
        .lights
        .unwrap(),
    );
    Scene::resolve(&f, Path::new("/")).unwrap()
}

fn assert_close(
    a: &brdfkit::image_io::Image,
    oracle: &brdfkit::image_io::Image,
    tol: f32,
    what: &str,
) {
    let mut worst = 0.0f32;
    let peak = oracle
        .pixels
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0f32, f32::max);
    for (p, q) in a.pixels.iter().zip(&oracle.pixels) {
        let d = (*p - *q).abs().max_element();
        // Relative to the pixel, or to 1% of the image's peak where SH terms cancel.
        let scale = q.abs().max_element().max(1e-2 * peak);
        worst = worst.max(d / scale);
        assert!(
            d <= tol * scale + 1e-6,
            "{what}: kernel {p:?} vs oracle {q:?}"
        );
    }
    assert!(
        oracle
            .pixels
            .iter()
            .filter(|p| p.max_element() > 0.0)
            .count()
            > 500,
        "{what}: too few lit pixels"
    );
    eprintln!("{what}: worst relative difference {worst:.2e}");
}

#[test]
fn sh_kernel_matches_scalar_oracle_for_library_materials() {
    for name in [
        "blue-silk",
        "magenta-plastic",
        "gold-dust-paint",
        "red-velvet",
    ] {
        let s = scene(
            MaterialSpec::Library {
                name: name.into(),
                lookup: None,
            },
            64,
        );
        assert!(
            s.material.as_sh().is_some(),
            "{name} should be an SH data set"
        );
        let vis = render::rasterize(&s, false);
        assert_close(
            &shade::shade(&s, &vis),
            &shade::shade_reference(&s, &vis),
            SH_KERNEL_TOLERANCE,
            name,
        );
    }
}

#[test]
fn generic_kernel_matches_scalar_oracle_for_analytic_materials() {
    for m in [
        "[material]\nkind = \"lambert\"\n",
        "[material]\nkind = \"blinn-phong\"\nexponent = 200.0\n",
        "[material]\nkind = \"library\"\nname = \"lindt-paper\"\n",
    ] {
        let spec = SceneFile::parse(m).unwrap().material;
        let s = scene(spec, 128);
        let vis = render::rasterize(&s, false);
        assert_close(
            &shade::shade(&s, &vis),
            &shade::shade_reference(&s, &vis),
            KERNEL_TOLERANCE,
            m.trim(),
        );
    }
}

#[test]
fn normal_cone_culling_changes_no_bit_and_skips_work() {
    for name in ["blue-silk", "magenta-plastic"] {
        let s = scene(
            MaterialSpec::Library {
                name: name.into(),
                lookup: None,
            },
            256,
        );
        let vis = render::rasterize(&s, false);
        let culled = shade::shade(&s, &vis);
        let mut prep = FramePrep::new(&s);
        prep.cull_lights = false;
        let full = shade::shade_with(&prep, &s, &vis);
        assert!(culled == full, "{name}: culling changed the image");
    }
    // And it does skip: city's lights are mostly in the sky, so a tile of downward normals
    // (the teapot's underside) drops most chunks.
    let s = scene(
        MaterialSpec::Library {
            lookup: None,
            name: "magenta-plastic".into(),
        },
        256,
    );
    let prep = FramePrep::new(&s);
    let down = brdfkit::kernel::Cone::around(
        [-glam::Vec3::Y, glam::Vec3::new(0.1, -0.99, 0.0).normalize()].into_iter(),
    )
    .unwrap();
    let kept = prep.dir.chunks_for(Some(down)).len();
    let all = prep.dir.chunks_for(None).len();
    assert!(
        kept * 2 < all,
        "only {} of {all} chunks culled for a downward tile",
        all - kept
    );
}
