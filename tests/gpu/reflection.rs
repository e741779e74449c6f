//! `[env] method = "reflection"` on `brdfkit render --device gpu` (cargo feature `gpu`; needs
//! a Vulkan adapter, e.g. lavapipe): the table path of isotropic materials is drawn (the
//! golden check holds it to the CPU: the `env-reflection-*` entries of tests/gpu/golden.rs),
//! and an anisotropic D-BRDF, which the CPU shades by filtered importance sampling, is
//! refused in one line that names why, with a non-zero exit and no image written.
#![cfg(feature = "gpu")]

use crate::common;
use brdfkit::scene::env_method::REFLECTION_FILTERED_NOT_ON_GPU;
use std::path::Path;

#[test]
fn the_filtered_path_is_refused_on_the_gpu_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let probe = common::city_probe();
    // The golden set's anisotropic D-BRDF file (lindt paper's fit: no library fit to wait for).
    let lindt = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden/lindt-paper-16x8.exr");
    let r = common::brdfkit(d)
        .env("XDG_RUNTIME_DIR", d)
        .timeout(600)
        .run(&[
            "render",
            "--env",
            probe.as_str(),
            "--env-method",
            "reflection",
            "--material",
            lindt.to_str().unwrap(),
            "--width",
            "16",
            "--height",
            "12",
            "--device",
            "gpu",
            "-o",
            "out.exr",
        ]);
    assert_eq!(r.code, Some(2), "{}{}", r.stdout, r.stderr);
    let errors: Vec<&str> = r.stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "{}", r.stderr);
    assert!(
        errors[0].ends_with(&format!("--device gpu: {REFLECTION_FILTERED_NOT_ON_GPU}")),
        "{}",
        r.stderr
    );
    assert!(!d.join("out.exr").exists());
}
