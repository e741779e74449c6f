//! `brdfkit render --device auto|cpu|gpu`: `cpu` is the default and the oracle; `auto` falls
//! back to the CPU with one line saying why (here: a build without the `gpu` feature, or a
//! request the GPU does not render) and renders the same bits as `cpu`; `gpu` that cannot
//! be had is a one-line error, exit 2, nothing written.

use crate::common;

use brdfkit::image_io::read_exr;

fn small(extra: &[&str]) -> Vec<String> {
    let mut a: Vec<String> = ["render", "--width", "40", "--height", "30"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    a.extend(extra.iter().map(|s| s.to_string()));
    a
}

/// Runs `brdfkit args` in `dir`, with `XDG_RUNTIME_DIR` set for the child (Mesa's Vulkan
/// drivers print a line about it to stderr when it is unset).
fn run(dir: &std::path::Path, args: &[String]) -> common::Run {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    common::brdfkit(dir).env("XDG_RUNTIME_DIR", dir).run(&args)
}

#[test]
fn auto_falls_back_to_the_cpu_with_one_line_and_the_same_bits() {
    let tmp = tempfile::tempdir().unwrap();
    let cpu = tmp.path().join("cpu.exr");
    let auto = tmp.path().join("auto.exr");
    let r = run(tmp.path(), &small(&["-o", cpu.to_str().unwrap()]));
    assert!(r.success(), "{}", r.stderr);
    assert!(
        !r.stderr.contains("device:"),
        "cpu is the default: {}",
        r.stderr
    );
    // The coverage debug output is never rendered on the GPU: auto says so and renders on
    // the CPU.
    let r = run(
        tmp.path(),
        &small(&[
            "--device",
            "auto",
            "--aov",
            "coverage",
            "-o",
            auto.to_str().unwrap(),
        ]),
    );
    assert!(r.success(), "{}", r.stderr);
    let lines: Vec<&str> = r
        .stderr
        .lines()
        .filter(|l| l.starts_with("device:"))
        .collect();
    assert_eq!(lines.len(), 1, "{}", r.stderr);
    assert!(lines[0].starts_with("device: cpu ("), "{}", lines[0]);
    #[cfg(not(feature = "gpu"))]
    {
        let r = run(
            tmp.path(),
            &small(&["--device", "auto", "-o", auto.to_str().unwrap()]),
        );
        assert!(r.success(), "{}", r.stderr);
        assert!(
            r.stderr
                .contains("device: cpu (this brdfkit was built without the `gpu` feature"),
            "{}",
            r.stderr
        );
        assert_eq!(read_exr(&cpu).unwrap(), read_exr(&auto).unwrap());
    }
}

#[test]
fn gpu_that_cannot_be_had_is_a_one_line_error() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x.png");
    let mut cases = vec![small(&[
        "--device",
        "gpu",
        "--aov",
        "coverage",
        "-o",
        out.to_str().unwrap(),
    ])];
    if !cfg!(feature = "gpu") {
        cases.push(small(&["--device", "gpu", "-o", out.to_str().unwrap()]));
    }
    for args in cases {
        let r = run(tmp.path(), &args);
        assert_eq!(r.code, Some(2), "{args:?}: {}", r.stderr);
        assert_eq!(r.stderr.trim().lines().count(), 1, "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains("--device gpu:"), "{}", r.stderr);
        assert!(!out.exists(), "nothing written");
    }
    // Light cuts stated for the GPU are refused as such, with or without the feature: before
    // the scene (and its light tree) is prepared, not by the GPU renderer after it.
    let probe = format!("{}/assets/probes/studio.exr", env!("CARGO_MANIFEST_DIR"));
    let args = small(&[
        "--device",
        "gpu",
        "--env",
        &probe,
        "--env-method",
        "lightcuts",
        "-o",
        out.to_str().unwrap(),
    ]);
    {
        let r = run(tmp.path(), &args);
        assert_eq!(r.code, Some(2), "{args:?}: {}", r.stderr);
        assert_eq!(r.stderr.trim().lines().count(), 1, "{args:?}: {}", r.stderr);
        assert!(
            r.stderr
                .contains("--device gpu: [env] method = \"lightcuts\" refines"),
            "{}",
            r.stderr
        );
        assert!(!out.exists(), "nothing written");
    }
}

/// With the feature and an adapter, `--device gpu` renders the default scene (small) close
/// to the CPU oracle: FLIP mean within the default GPU bound.
#[cfg(feature = "gpu")]
#[test]
fn gpu_renders_the_default_scene_close_to_the_cpu() {
    use brdfkit::compare::{compare, Loaded, Thresholds};
    let tmp = tempfile::tempdir().unwrap();
    let cpu = tmp.path().join("cpu.exr");
    let gpu = tmp.path().join("gpu.exr");
    let r = run(tmp.path(), &small(&["-o", cpu.to_str().unwrap()]));
    assert!(r.success(), "{}", r.stderr);
    let r = run(
        tmp.path(),
        &small(&["--device", "gpu", "-o", gpu.to_str().unwrap()]),
    );
    assert!(r.success(), "{}", r.stderr);
    assert!(r.stderr.contains("device: gpu ("), "{}", r.stderr);
    let (e, a) = (
        Loaded::from_linear(read_exr(&cpu).unwrap()),
        Loaded::from_linear(read_exr(&gpu).unwrap()),
    );
    let (m, _) = compare(&e, &a, &Thresholds::DEFAULT).unwrap();
    assert!(m.passes(&Thresholds::DEFAULT), "{m:?}");
}
