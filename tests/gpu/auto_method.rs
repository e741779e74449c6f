//! `[env] method = "auto"` on `brdfkit render --device gpu` (cargo feature `gpu`; needs a
//! Vulkan adapter, e.g. lavapipe): where the CPU would build a light tree (a D-BRDF), the
//! GPU renders the Lloyd light set `auto` chooses for it instead
//! (`brdfkit::scene::env_method::GPU_AUTO_LIGHTS` lights), says so in one line, builds no
//! light tree, and matches the CPU's render of that same light set.
#![cfg(feature = "gpu")]

use crate::common;
use brdfkit::compare::{compare, Loaded, Thresholds};
use brdfkit::image_io::read_exr;
use brdfkit::scene::env_method::GPU_AUTO_LIGHTS;

#[test]
fn auto_on_the_gpu_renders_lloyd_lights_and_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let probe = common::city_probe();
    let base = [
        "render",
        "--env",
        probe.as_str(),
        "--material",
        "lindt-paper",
        "--width",
        "40",
        "--height",
        "30",
    ];
    let run = |extra: &[&str]| {
        common::brdfkit(d)
            .env("XDG_RUNTIME_DIR", d)
            .timeout(600)
            .run(&[&base[..], extra].concat())
    };
    let r = run(&["--device", "gpu", "-o", "gpu.exr"]);
    assert!(r.success(), "{}", r.stderr);
    let auto: Vec<&str> = r
        .stderr
        .lines()
        .filter(|l| l.starts_with("auto:"))
        .collect();
    assert_eq!(auto.len(), 1, "{}", r.stderr);
    assert!(
        auto[0].starts_with("auto: method \"lightcuts\" is CPU only")
            && auto[0].contains(&format!("{GPU_AUTO_LIGHTS} Lloyd lights")),
        "{}",
        auto[0]
    );
    assert!(
        r.stderr
            .contains(&format!("environment: {GPU_AUTO_LIGHTS} lights")),
        "the light set, no light tree: {}",
        r.stderr
    );
    assert!(!r.stderr.contains("light cuts through"), "{}", r.stderr);
    assert!(r.stderr.contains("device: gpu ("), "{}", r.stderr);
    // The CPU's render of the same light set, asked for by name.
    let n = GPU_AUTO_LIGHTS.to_string();
    let r = run(&["--sampler", "lloyd", "--lights", &n, "-o", "cpu.exr"]);
    assert!(r.success(), "{}", r.stderr);
    assert!(
        !r.stderr.contains("auto:"),
        "the CPU keeps its choice: {}",
        r.stderr
    );
    let (e, a) = (
        Loaded::from_linear(read_exr(&d.join("cpu.exr")).unwrap()),
        Loaded::from_linear(read_exr(&d.join("gpu.exr")).unwrap()),
    );
    let (m, _) = compare(&e, &a, &Thresholds::DEFAULT).unwrap();
    assert!(m.passes(&Thresholds::DEFAULT), "{m:?}");
}
