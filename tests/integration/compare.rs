//! `brdfkit compare`: exit 0 on pass, 1 on fail (with a report image), 2 on unusable input.

use std::path::Path;

use crate::common;

/// `brdfkit args` in `dir` (killed after 60 s): (exit code, stdout, stderr).
fn run(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let r = common::brdfkit(dir).timeout(60).run(args);
    (r.code.unwrap_or(-1), r.stdout, r.stderr)
}

#[test]
fn exit_codes_and_report() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(
        p.join("dim.toml"),
        "[[light]]\nkind = \"directional\"\nto_light = [0.4, 1.0, 0.6]\nintensity = 2.5\n",
    )
    .unwrap();
    for (args, _) in [
        (
            vec!["render", "--width", "64", "--height", "48", "-o", "a.exr"],
            0,
        ),
        (
            vec!["render", "--width", "64", "--height", "48", "-o", "b.exr"],
            0,
        ),
        (
            vec![
                "render", "dim.toml", "--width", "64", "--height", "48", "-o", "dim.exr",
            ],
            0,
        ),
        (
            vec![
                "render",
                "--width",
                "32",
                "--height",
                "48",
                "-o",
                "small.exr",
            ],
            0,
        ),
        (
            vec!["render", "--width", "64", "--height", "48", "-o", "a.png"],
            0,
        ),
    ] {
        assert_eq!(run(p, &args).0, 0);
    }
    let (code, out, _) = run(p, &["compare", "a.exr", "b.exr"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("PASS"));
    let (code, out, _) = run(p, &["compare", "a.exr", "dim.exr", "--diff", "report.png"]);
    assert_eq!(code, 1, "a 17% dimmer light must fail: {out}");
    assert!(out.contains("error histogram") && out.contains("FAIL"));
    let report = image::open(p.join("report.png")).unwrap();
    assert_eq!((report.width(), report.height()), (3 * 64, 48));
    let (code, _, err) = run(p, &["compare", "a.exr", "small.exr"]);
    assert_eq!(code, 2);
    assert!(err.contains("sizes differ"), "{err}");
    let (code, _, err) = run(p, &["compare", "a.exr", "a.png"]);
    assert_eq!(code, 2);
    assert!(err.contains("channel layouts differ"), "{err}");
    let (code, _, err) = run(p, &["compare", "a.exr", "missing.exr"]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.exr"), "{err}");
    std::fs::write(p.join("junk.exr"), b"junk").unwrap();
    let (code, _, err) = run(p, &["compare", "a.exr", "junk.exr"]);
    assert_eq!(code, 2);
    assert!(err.contains("junk.exr"), "{err}");
    assert!(
        !p.join("junk.diff.png").exists() && !p.join("small.diff.png").exists(),
        "unusable input must write nothing"
    );
}

#[test]
fn image_one_pixel_off_is_caught_at_shipped_tolerances() {
    // The whole render displaced by one pixel (an off-by-one in a viewport or a half-pixel
    // centre convention): every edge moves, which the default FLIP percentile bound catches.
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    assert_eq!(
        run(
            p,
            &["render", "--width", "160", "--height", "120", "-o", "a.exr"]
        )
        .0,
        0
    );
    let img = brdfkit::image_io::read_exr(&p.join("a.exr")).unwrap();
    let mut shifted = img.clone();
    for y in 0..img.height {
        for x in 0..img.width {
            let sx = x.saturating_sub(1);
            shifted.pixels[(y * img.width + x) as usize] = img.get(sx, y);
        }
    }
    brdfkit::image_io::write_exr(&p.join("b.exr"), &shifted).unwrap();
    let (code, out, _) = run(p, &["compare", "a.exr", "b.exr"]);
    assert_eq!(code, 1, "a one-pixel shift passed: {out}");
}

#[test]
fn thresholds_come_from_the_manifest_entry_and_flags_override_them() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(
        p.join("dim.toml"),
        "[[light]]\nkind = \"directional\"\nto_light = [0.4, 1.0, 0.6]\nintensity = 2.5\n",
    )
    .unwrap();
    for args in [
        vec!["render", "--width", "48", "--height", "36", "-o", "a.exr"],
        vec![
            "render", "dim.toml", "--width", "48", "--height", "36", "-o", "dim.exr",
        ],
    ] {
        assert_eq!(run(p, &args).0, 0);
    }
    // A loose entry (a 17% dimmer light passes it) and one that keeps its tolerance's
    // defaults (it fails them, as in `exit_codes_and_report`).
    std::fs::write(
        p.join("manifest.toml"),
        "[[entry]]\nname = \"loose\"\nscene = \"s.toml\"\ntolerance = \"kernel-dispatch\"\n\
         flip = { mean = 0.9, percentile = 0.5, at_percentile = 0.99 }\n\n\
         [[entry]]\nname = \"strict\"\nscene = \"s.toml\"\ntolerance = \"cross-platform\"\n",
    )
    .unwrap();
    let m = ["--manifest", "manifest.toml", "--entry"];
    let cmp = |extra: &[&str]| {
        let mut args = vec!["compare", "a.exr", "dim.exr", "--diff", "r.png"];
        args.extend_from_slice(extra);
        run(p, &args)
    };
    let (code, out, err) = cmp(&[m[0], m[1], m[2], "loose"]);
    assert_eq!(code, 0, "entry thresholds not applied: {out}{err}");
    assert!(
        out.contains("FLIP mean <= 0.9") && out.contains("(max 0.9)"),
        "{out}"
    );
    let (code, out, _) = cmp(&[m[0], m[1], m[2], "strict"]);
    assert_eq!(
        code, 1,
        "the tolerance's default thresholds must fail: {out}"
    );
    let (code, out, _) = cmp(&[m[0], m[1], m[2], "loose", "--max-flip-mean", "0.01"]);
    assert_eq!(code, 1, "--max-flip-mean must override the entry: {out}");
    assert!(out.contains("(max 0.01)"), "{out}");
    let (code, _, err) = cmp(&[m[0], m[1], m[2], "nope"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("manifest.toml") && err.contains("no entry named 'nope'"),
        "{err}"
    );
    std::fs::write(
        p.join("bad.toml"),
        "[[entry]]\nname = \"x\"\nscene = \"s.toml\"\ntolerance = \"loose-ish\"\n",
    )
    .unwrap();
    let (code, _, err) = cmp(&["--manifest", "bad.toml", "--entry", "x"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bad.toml") && err.contains("tolerance") && err.contains("loose-ish"),
        "{err}"
    );
}

/// Writes `img` with the alpha `alpha(x, y)` as an RGBA EXR (f32, the exr crate's defaults).
fn write_rgba_exr(
    path: &Path,
    img: &brdfkit::image_io::Image,
    alpha: impl Fn(usize, usize) -> f32 + Sync,
) {
    exr::prelude::write_rgba_file(path, img.width as usize, img.height as usize, |x, y| {
        let p = img.get(x as u32, y as u32);
        (p.x, p.y, p.z, alpha(x, y))
    })
    .unwrap();
}

#[test]
fn rgba_read_backs_compare_with_the_rgb_original() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for out in ["a.exr", "a.png"] {
        let args = ["render", "--width", "48", "--height", "36", "-o", out];
        assert_eq!(run(p, &args).0, 0);
    }
    let img = brdfkit::image_io::read_exr(&p.join("a.exr")).unwrap();
    // Opaque RGBA copies of both: what a GPU read-back of the same frame writes.
    write_rgba_exr(&p.join("opaque.exr"), &img, |_, _| 1.0);
    let png = image::open(p.join("a.png")).unwrap().to_rgba8();
    png.save(p.join("opaque.png")).unwrap();
    // Half transparent (the left half alpha 0), colour unchanged.
    write_rgba_exr(
        &p.join("holes.exr"),
        &img,
        |x, _| if x < 24 { 0.0 } else { 1.0 },
    );
    // A seeded colour difference (every value x0.8) with alpha 1.
    let mut dim = img.clone();
    for px in &mut dim.pixels {
        *px *= 0.8;
    }
    write_rgba_exr(&p.join("dim.exr"), &dim, |_, _| 1.0);

    for (expected, actual, alpha, want) in [
        ("a.exr", "opaque.exr", "ignore", 0),
        ("a.exr", "opaque.exr", "compare", 0),
        ("opaque.exr", "a.exr", "compare", 0),
        ("a.png", "opaque.png", "ignore", 0),
        ("a.png", "opaque.png", "compare", 0),
        ("a.exr", "holes.exr", "ignore", 0),
        ("a.exr", "holes.exr", "compare", 1),
        ("a.exr", "dim.exr", "ignore", 1),
    ] {
        let (code, out, err) = run(
            p,
            &[
                "compare", expected, actual, "--alpha", alpha, "--diff", "r.png",
            ],
        );
        assert_eq!(
            code, want,
            "{expected} vs {actual}, alpha {alpha}: {out}{err}"
        );
    }
    let (_, out, _) = run(p, &["compare", "a.exr", "holes.exr", "--alpha", "compare"]);
    assert!(
        out.contains("alpha: max abs error 1.000000e0"),
        "the alpha difference is reported: {out}"
    );
    // Colour layouts still differ for EXR against PNG.
    let (code, _, err) = run(p, &["compare", "a.exr", "opaque.png"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn a_failure_stays_exit_1_when_the_diff_cannot_be_written() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    assert_eq!(
        run(
            p,
            &["render", "--width", "40", "--height", "30", "-o", "a.exr"]
        )
        .0,
        0
    );
    let img = brdfkit::image_io::read_exr(&p.join("a.exr")).unwrap();
    let mut dim = img.clone();
    for px in &mut dim.pixels {
        *px *= 0.8;
    }
    write_rgba_exr(&p.join("dim.exr"), &dim, |_, _| 1.0);
    for diff in ["no/such/dir/d.png", "a.exr/d.png"] {
        let (code, out, err) = run(p, &["compare", "a.exr", "dim.exr", "--diff", diff]);
        assert_eq!(code, 1, "--diff {diff}: {out}{err}");
        assert!(out.contains("FAIL"), "{out}");
        assert!(
            err.lines().count() == 1 && err.starts_with("warning") && err.contains(diff),
            "one warning line naming the diff path: {err}"
        );
        assert!(!err.contains("error:"), "{err}");
    }
    assert!(!p.join("no").exists());
    // The same comparison passes with the diff unwritable: nothing to write, no change.
    let (code, _, _) = run(p, &["compare", "a.exr", "a.exr", "--diff", "no/such/d.png"]);
    assert_eq!(code, 0);
}
