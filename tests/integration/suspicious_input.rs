//! Suspicious input is rendered, but said: a probe that is not 2:1, a probe with no light,
//! and `--lights` where every texel is a light.

use brdfkit::image_io::{write_exr, Image};
use glam::Vec3;
use std::path::Path;

use crate::common;

/// Runs `brdfkit args` in `dir` (its own light-set cache): (exit code, stderr).
fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let r = common::brdfkit(dir).run(args);
    (r.code, r.stderr)
}

fn probe(dir: &Path, name: &str, w: u32, h: u32, value: f32) -> String {
    let mut img = Image::new(w, h);
    img.pixels.iter_mut().for_each(|p| *p = Vec3::splat(value));
    write_exr(&dir.join(name), &img).unwrap();
    name.to_string()
}

#[test]
fn suspicious_inputs_are_warned_about() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let small = [
        "--width",
        "32",
        "--height",
        "24",
        "--no-cache",
        "-o",
        "out.exr",
    ];
    let render = |env: &str, extra: &[&str]| {
        let mut args = vec!["render", "--env", env];
        args.extend_from_slice(&small);
        args.extend_from_slice(extra);
        run(d, &args)
    };

    let square = probe(d, "square.exr", 16, 16, 1.0);
    let (code, err) = render(&square, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("square.exr: 16x16 is not 2:1"), "{err}");

    // Through the light-set cache: the first run decodes the probe and stores its load
    // report with the lights, the second reads the entry without decoding, and both warn.
    for pass in ["computed", "cached"] {
        // Delta lights (`--env-method lights`): the light-set cache is theirs.
        let mut args = vec![
            "render",
            "--env",
            &square,
            "--env-method",
            "lights",
            "-o",
            "cached.exr",
        ];
        args.extend_from_slice(&small[..4]);
        let (code, err) = run(d, &args);
        assert_eq!(code, Some(0), "{pass}: {err}");
        assert_eq!(err.contains("(cached)"), pass == "cached", "{pass}: {err}");
        assert!(err.contains("16x16 is not 2:1"), "{pass}: {err}");
    }

    let black = probe(d, "black.exr", 16, 8, 0.0);
    let (code, err) = render(&black, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("black.exr: the probe carries no light"),
        "{err}"
    );

    let ok = probe(d, "ok.exr", 16, 8, 1.0);
    let (code, err) = render(&ok, &["--sampler", "full", "--lights", "8"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("--lights is ignored"), "{err}");

    // A clean probe and a sampler that uses the count: no warning at all.
    let (code, err) = render(&ok, &["--sampler", "median-cut", "--lights", "8"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("warning"), "{err}");
}
