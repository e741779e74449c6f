//! What `brdfkit compare` measures and reports: statistics over the covered pixels (not the
//! background), non-finite pixels first, a FAIL line naming each failed bound, GPU-side
//! bounds files (golden/gpu-bounds.toml), and `--json` for scripts.
//!
//! (Past 400 lines because each test drives the one `compare` report end to end and they
//! share the render, scaling and report-parsing helpers at the top.)

use std::path::{Path, PathBuf};

use crate::common;

/// `brdfkit args` in `dir` (killed after 60 s): (exit code, stdout, stderr).
fn run(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let r = common::brdfkit(dir).timeout(60).run(args);
    (r.code.unwrap_or(-1), r.stdout, r.stderr)
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

/// Renders `args` to `dir/name` and reads it back.
fn render(dir: &Path, name: &str, args: &[&str]) -> brdfkit::image_io::Image {
    let mut all = vec!["render", "-o", name];
    all.extend_from_slice(args);
    let (code, out, err) = run(dir, &all);
    assert_eq!(code, 0, "{out}{err}");
    brdfkit::image_io::read_exr(&dir.join(name)).unwrap()
}

/// Writes `img` with every value scaled by `k`.
fn write_scaled(path: &Path, img: &brdfkit::image_io::Image, k: f32) {
    let mut out = img.clone();
    for p in &mut out.pixels {
        *p *= k;
    }
    brdfkit::image_io::write_exr(path, &out).unwrap();
}

/// `(covered, total, measured)` from the report's "covered pixels" line.
fn covered_line(out: &str) -> (u64, u64, u64) {
    let line = out
        .lines()
        .find(|l| l.trim_start().starts_with("covered pixels"))
        .unwrap_or_else(|| panic!("no covered pixels line: {out}"));
    let n: Vec<u64> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter(|w| !w.is_empty())
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(n.len(), 3, "{line}");
    (n[0], n[1], n[2])
}

/// The FAIL line of a report.
fn fail_line(out: &str) -> &str {
    out.lines()
        .find(|l| l.starts_with("FAIL"))
        .unwrap_or_else(|| panic!("no FAIL line: {out}"))
}

#[test]
fn the_default_frame_two_percent_brighter_fails_over_the_covered_pixels() {
    // The user report: the default frame against itself x1.02 passed (FLIP mean 0.0078 over
    // the whole frame, 83% of it background).
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let img = render(p, "a.exr", &[]);
    write_scaled(&p.join("b.exr"), &img, 1.02);
    // Over every pixel the mean stays under the default bound: the dilution the covered
    // pixels remove.
    let (e, a) = (
        brdfkit::compare::load(&p.join("a.exr")).unwrap(),
        brdfkit::compare::load(&p.join("b.exr")).unwrap(),
    );
    let th = brdfkit::compare::Thresholds::DEFAULT;
    let (all, _) = brdfkit::compare::compare(&e, &a, &th).unwrap();
    assert!(all.flip_mean < th.flip_mean, "{}", all.flip_mean);

    let (code, out, err) = run(p, &["compare", "a.exr", "b.exr"]);
    assert_eq!(code, 1, "a 2% brighter frame passed:\n{out}{err}");
    let (covered, total, measured) = covered_line(&out);
    assert_eq!(total, img.pixels.len() as u64);
    assert_eq!(measured, covered);
    let object = img
        .pixels
        .iter()
        .filter(|p| **p != glam::Vec3::ZERO)
        .count() as u64;
    assert_eq!(covered, object, "covered: the non-black pixels\n{out}");
    assert!(
        covered * 4 < total,
        "the default frame is mostly background: {out}"
    );
    let fail = fail_line(&out);
    assert!(
        fail.starts_with("FAIL: FLIP mean ")
            && fail.contains("> 0.01")
            && fail.ends_with("(covered pixels)"),
        "{fail}"
    );
    // The same frame against itself passes, over the same pixels.
    let (code, out, _) = run(p, &["compare", "a.exr", "a.exr"]);
    assert_eq!(code, 0, "{out}");
    assert_eq!(covered_line(&out).0, covered);
    assert!(out.contains("PSNR            inf (identical)"), "{out}");
}

#[test]
fn the_fail_line_names_each_failed_bound_with_value_and_limit() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let img = render(p, "a.exr", &["--width", "64", "--height", "48"]);
    write_scaled(&p.join("b.exr"), &img, 1.05);
    let cmp = |extra: &[&str]| {
        let mut args = vec!["compare", "a.exr", "b.exr", "--diff", "d.png"];
        args.extend_from_slice(extra);
        run(p, &args)
    };
    // Only the percentile bound is tight: only it is named.
    let (code, out, _) = cmp(&["--max-flip-mean", "0.9", "--max-flip-at-percentile", "1e-4"]);
    assert_eq!(code, 1, "{out}");
    let fail = fail_line(&out);
    assert!(
        fail.starts_with("FAIL: FLIP p99 ") && fail.contains(" > 0.0001"),
        "{fail}"
    );
    assert!(
        !fail.contains("FLIP mean"),
        "a bound that holds is named: {fail}"
    );
    // Both tight: both named, each with the measured value the report printed above.
    let (code, out, _) = cmp(&[
        "--max-flip-mean",
        "1e-4",
        "--max-flip-at-percentile",
        "1e-4",
    ]);
    assert_eq!(code, 1, "{out}");
    let fail = fail_line(&out);
    let value = |label: &str| -> f64 {
        let rest = &fail[fail
            .find(label)
            .unwrap_or_else(|| panic!("{label}: {fail}"))
            + label.len()..];
        rest.split_whitespace().next().unwrap().parse().unwrap()
    };
    let mean = value("FLIP mean ");
    let reported: f64 = out
        .lines()
        .find(|l| l.trim_start().starts_with("FLIP mean"))
        .and_then(|l| l.split_whitespace().nth(2))
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        (mean - reported).abs() < 1e-6 && mean > 1e-4,
        "{fail}\n{out}"
    );
    assert!(value("FLIP p99 ") > 1e-4, "{fail}");
    assert!(fail.contains(", FLIP p99 "), "{fail}");
    assert!(
        out.contains("expected | FLIP heatmap | actual written to d.png"),
        "{out}"
    );
}

#[test]
fn a_non_finite_pixel_is_reported_first_and_fails() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let img = render(p, "a.exr", &["--width", "48", "--height", "36"]);
    let mut bad = img.clone();
    let w = img.width as usize;
    bad.pixels[7 * w + 5] = glam::Vec3::new(f32::NAN, 0.2, 0.2);
    bad.pixels[7 * w + 6] = glam::Vec3::splat(f32::INFINITY);
    brdfkit::image_io::write_exr(&p.join("nan.exr"), &bad).unwrap();
    let (code, out, err) = run(p, &["compare", "a.exr", "nan.exr"]);
    assert_eq!(code, 1, "non-finite pixels passed:\n{out}{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[1].trim_start().starts_with("non-finite")
            && lines[1].contains("2 pixels")
            && lines[1].contains("(5, 7), (6, 7)"),
        "the non-finite pixels come first, with their coordinates:\n{out}"
    );
    for not_a_measure in ["RMSE", "PSNR", "max abs error", "FLIP mean  "] {
        assert!(
            !out.contains(not_a_measure),
            "{not_a_measure} printed:\n{out}"
        );
    }
    let fail = fail_line(&out);
    assert_eq!(fail, "FAIL: non-finite pixels 2 > 0", "{out}");
    let (covered, _, measured) = covered_line(&out);
    assert_eq!(covered - measured, 2, "{out}");

    let (code, json, _) = run(p, &["compare", "a.exr", "nan.exr", "--json"]);
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["verdict"], "fail");
    assert!(v["measures"].is_null(), "{json}");
    assert_eq!(v["failed"], serde_json::json!(["non_finite"]), "{json}");
    assert_eq!(
        v["pixels"]["non_finite_at"],
        serde_json::json!([[5, 7], [6, 7]])
    );
    let flip_bound = v["bounds"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["measure"] == "flip_mean")
        .unwrap();
    assert!(
        flip_bound["passed"].is_null() && flip_bound["value"].is_null(),
        "{json}"
    );
}

#[test]
fn gpu_bounds_toml_gives_the_bounds_the_gpu_check_applies() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let golden = golden_dir();
    let bounds = golden.join("gpu-bounds.toml");
    let manifest = golden.join("manifest.toml");
    let (b, m) = (bounds.to_str().unwrap(), manifest.to_str().unwrap());
    let image = |name: &str| {
        golden
            .join(format!("{name}.exr"))
            .to_str()
            .unwrap()
            .to_string()
    };
    // An entry gpu-bounds.toml lists: its own, tighter bounds.
    let listed = "fig3-9-blue-synthetic-fabric-median-cut";
    let (e, a) = (image(listed), image(listed));
    let (code, out, err) = run(p, &["compare", &e, &a, "--bounds", b, "--entry", listed]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains(&format!(
            "thresholds of {b} entry '{listed}': FLIP mean <= 0.004, p99 <= 0.04"
        )) && out.contains("(max 0.004)")
            && out.contains("(max 0.04)"),
        "{out}"
    );
    // Its radiometric bounds come along (the file lists every entry with them), as the
    // file states them.
    let file: toml::Table = toml::from_str(&std::fs::read_to_string(&bounds).unwrap()).unwrap();
    let t = &file[listed];
    let rmse = t["rel_rmse"].as_float().unwrap();
    assert!(
        out.contains(&format!(
            ", mean error <= {}, relative RMSE <= {rmse}, relative error p99 <= {}, coverage mismatch <= {}",
            t["mean_error"].as_float().unwrap(),
            t["rel_error"].as_float().unwrap(),
            t["coverage_mismatch"].as_float().unwrap(),
        )) && out.contains(&format!("relative RMSE   0.000e0  (max {rmse})")),
        "{out}"
    );
    // An entry a bounds file does not list: the manifest's bounds beside it, as the GPU
    // check does (a copy of the manifest beside a file that lists one entry).
    let other = "fig3-13-teal-paint";
    let (e, a) = (image(other), image(other));
    let sub = p.join("sub");
    std::fs::create_dir(&sub).unwrap();
    std::fs::copy(&manifest, sub.join("manifest.toml")).unwrap();
    std::fs::write(
        sub.join("gpu-bounds.toml"),
        format!("[{listed}]\nmean = 0.004\nwhy = \"x\"\n"),
    )
    .unwrap();
    let (sb, sm) = (
        sub.join("gpu-bounds.toml").to_str().unwrap().to_string(),
        sub.join("manifest.toml").to_str().unwrap().to_string(),
    );
    let (code, out, err) = run(p, &["compare", &e, &a, "--bounds", &sb, "--entry", other]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains(&format!(
            "thresholds of {sm} entry '{other}' (not in {sb}): FLIP mean <= 0.01, p99 <= 0.1\n"
        )),
        "{out}"
    );
    // The manifest itself, through --bounds and through --manifest.
    for flag in ["--bounds", "--manifest"] {
        let (code, out, err) = run(p, &["compare", &e, &a, flag, m, "--entry", other]);
        assert_eq!(code, 0, "{flag}: {out}{err}");
        assert!(
            out.contains(&format!(
                "thresholds of {m} entry '{other}': FLIP mean <= 0.01"
            )),
            "{out}"
        );
    }
    // JSON names where the bounds came from.
    let (_, json, _) = run(
        p,
        &[
            "compare", &e, &a, "--bounds", b, "--entry", listed, "--json",
        ],
    );
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["thresholds"]["flip_mean"], 0.004, "{json}");
    assert_eq!(v["thresholds"]["from"], b, "{json}");

    // Errors: one line naming the file and the problem.
    std::fs::copy(&manifest, p.join("manifest.toml")).unwrap();
    // `compare --bounds gpu-bounds.toml --entry LISTED` with `text` as the bounds file.
    let with_bounds = |text: &str| {
        std::fs::write(p.join("gpu-bounds.toml"), text).unwrap();
        run(
            p,
            &[
                "compare",
                &e,
                &a,
                "--bounds",
                "gpu-bounds.toml",
                "--entry",
                listed,
            ],
        )
    };
    let (code, _, err) = with_bounds(&format!(
        "[{listed}]\nmean = 0.004\npercentile = 0.99\nat_percentil = 0.04\nwhy = \"x\"\n"
    ));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.lines().count() == 1 && err.contains("gpu-bounds.toml") && err.contains("at_percentil"),
        "{err}"
    );
    let (code, _, err) = with_bounds(
        "[no-such-entry]\nmean = 0.004\npercentile = 0.99\nat_percentile = 0.04\nwhy = \"x\"\n",
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("gpu-bounds.toml") && err.contains("[no-such-entry]: no such golden entry"),
        "{err}"
    );
    let (code, _, err) = run(p, &["compare", &e, &a, "--bounds", b, "--entry", "nope"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("manifest.toml") && err.contains("no entry named 'nope'"),
        "{err}"
    );
}

#[test]
fn json_output_parses_and_carries_the_verdict_measures_and_bounds() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let img = render(p, "a.exr", &["--width", "64", "--height", "48"]);
    write_scaled(&p.join("b.exr"), &img, 1.05);
    let (code, json, err) = run(p, &["compare", "a.exr", "a.exr", "--json"]);
    assert_eq!(code, 0, "{json}{err}");
    let v: serde_json::Value = serde_json::from_str(&json).expect("stdout is one JSON document");
    assert_eq!(v["verdict"], "pass");
    assert_eq!(v["failed"], serde_json::json!([]));
    assert_eq!(v["measures"]["max_abs"], 0.0);
    assert!(
        v["measures"]["psnr_db"].is_null(),
        "identical: infinite PSNR is null"
    );
    assert_eq!(v["pixels"]["over"], "covered");
    let covered = v["pixels"]["covered"].as_u64().unwrap();
    assert!(covered > 0 && covered < 64 * 48, "{json}");

    let (code, json, _) = run(
        p,
        &["compare", "a.exr", "b.exr", "--json", "--diff", "d.png"],
    );
    assert_eq!(code, 1, "{json}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["verdict"], "fail");
    let failed: Vec<&str> = v["failed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert!(failed.contains(&"flip_mean"), "{json}");
    let bounds = v["bounds"].as_array().unwrap();
    let names: Vec<&str> = bounds
        .iter()
        .map(|b| b["measure"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["non_finite", "flip_mean", "flip_at_percentile"],
        "{json}"
    );
    for b in bounds {
        let passed = b["passed"].as_bool().unwrap();
        let (value, limit) = (b["value"].as_f64().unwrap(), b["limit"].as_f64().unwrap());
        assert_eq!(passed, value <= limit, "{b}");
        assert_eq!(
            !passed,
            failed.contains(&b["measure"].as_str().unwrap()),
            "{b}"
        );
    }
    assert_eq!(bounds[1]["limit"], 0.01);
    assert_eq!(bounds[1]["value"], v["measures"]["flip_mean"], "{json}");
    assert_eq!(v["diff"], "d.png");
    assert!(p.join("d.png").exists());

    // Unusable input: exit 2, nothing on stdout, one error line.
    let (code, out, err) = run(p, &["compare", "a.exr", "missing.exr", "--json"]);
    assert_eq!(code, 2);
    assert!(out.is_empty(), "{out}");
    assert!(
        err.lines().count() == 1 && err.contains("missing.exr"),
        "{err}"
    );
}

#[test]
fn radiometric_bounds_catch_a_half_percent_gain() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let img = render(p, "a.exr", &["--width", "64", "--height", "48"]);
    write_scaled(&p.join("gain.exr"), &img, 1.005);
    // FLIP opened wide (each radiometric bound alone decides below).
    let open = ["--max-flip-mean", "1", "--max-flip-at-percentile", "1"];
    let with_open = |extra: &[&str]| {
        let mut args = vec!["compare", "a.exr", "gain.exr"];
        args.extend(open);
        args.extend(extra);
        run(p, &args)
    };
    let (code, out, _) = with_open(&[]);
    assert_eq!(code, 0, "{out}");
    let ratio_line = out
        .lines()
        .find(|l| l.trim_start().starts_with("mean ratio"))
        .unwrap_or_else(|| panic!("no mean ratio line: {out}"));
    assert!(
        ratio_line.contains("R 1.005000 G 1.005000 B 1.005000"),
        "{ratio_line}"
    );
    // The mean bound fails it and names itself on the FAIL line; each other bound too.
    for (flag, limit, label) in [
        ("--max-mean-error", "0.001", "mean error"),
        ("--max-rel-rmse", "0.001", "relative RMSE"),
        ("--max-rel-error", "0.001", "relative error p99"),
    ] {
        let (code, out, _) = with_open(&[flag, limit]);
        assert_eq!(code, 1, "{flag}: {out}");
        let fail = fail_line(&out);
        assert!(
            fail.starts_with(&format!("FAIL: {label} 0.00"))
                && fail.contains(&format!("> {limit}")),
            "{flag}: {fail}"
        );
        // At 0.01 it passes.
        let (code, out, _) = with_open(&[flag, "0.01"]);
        assert_eq!(code, 0, "{flag}: {out}");
    }
    // A silhouette pixel lit in one image only is counted, not averaged into the measures:
    // one covered pixel blacked out leaves the means exact and the mismatch at 1 pixel.
    let mut holed = img.clone();
    let i = img
        .pixels
        .iter()
        .position(|p| *p != glam::Vec3::ZERO)
        .unwrap();
    holed.pixels[i] = glam::Vec3::ZERO;
    brdfkit::image_io::write_exr(&p.join("holed.exr"), &holed).unwrap();
    let (code, out, _) = run(
        p,
        &[
            "compare",
            "holed.exr",
            "a.exr",
            "--json",
            "--max-mean-error",
            "0",
            "--max-coverage-mismatch",
            "0",
        ],
    );
    assert_eq!(code, 1, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["measures"]["mean_error"], 0.0, "{out}");
    assert_eq!(v["measures"]["coverage_mismatch"], 1, "{out}");
    assert_eq!(
        v["failed"],
        serde_json::json!(["coverage_mismatch"]),
        "{out}"
    );
    // A bound out of range is a one-line error naming the flag.
    let (code, _, err) = run(p, &["compare", "a.exr", "gain.exr", "--max-rel-rmse=-1"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.lines().count() == 1 && err.contains("--max-rel-rmse"),
        "{err}"
    );
}
