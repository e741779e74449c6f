//! The GPU golden check end to end (cargo feature `gpu`; needs a Vulkan adapter, e.g. Mesa's
//! lavapipe, which .ci/run installs): `brdfkit golden check --device gpu` passes for the
//! correct wgpu renderer, and fails for each seeded GPU fault (half-texel offset, missing
//! cosine, mirrored azimuth, sRGB applied twice, the transfer table read at the mirrored
//! probe azimuth, the reflection table read at `-psi`) injected through the hidden
//! `--gpu-fault`.
//! Every entry the GPU does not render must be listed as skipped with its reason.
#![cfg(feature = "gpu")]

use crate::common;

use std::path::{Path, PathBuf};

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

fn check(extra: &[&str]) -> common::Run {
    let tmp = tempfile::tempdir().unwrap();
    let dir = golden_dir();
    let mut args = vec![
        "golden",
        "check",
        "--device",
        "gpu",
        "--dir",
        dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    // XDG_RUNTIME_DIR for the child only: Mesa's Vulkan drivers print a line when it is unset.
    common::brdfkit(tmp.path())
        .env("XDG_RUNTIME_DIR", tmp.path())
        .timeout(600)
        .run(&args)
}

/// Entry lines of a check's output: (name, status, rest).
fn entries(stdout: &str) -> Vec<(String, String, String)> {
    stdout
        .lines()
        .filter_map(|l| {
            let mut it = l.split_whitespace();
            let name = it.next()?.to_string();
            let status = it.next()?.to_string();
            ["pass", "FAIL", "skip"]
                .contains(&status.as_str())
                .then(|| (name, status, it.collect::<Vec<_>>().join(" ")))
        })
        .collect()
}

/// Runs the check with `--gpu-fault fault` on `must_fail` and `must_pass` and asserts that
/// it exits 1 and that the entries it fails are exactly `must_fail` (in any order);
/// returns them sorted, for the log.
fn assert_fails_exactly(fault: &str, must_fail: &[&str], must_pass: &[&str]) -> Vec<String> {
    let mut args = vec!["--gpu-fault", fault];
    args.extend(must_fail.iter().chain(must_pass));
    let r = check(&args);
    assert_eq!(
        r.code,
        Some(1),
        "seeded fault {fault} did not fail the check:\n{}{}",
        r.stdout,
        r.stderr
    );
    let mut failed: Vec<String> = entries(&r.stdout)
        .into_iter()
        .filter(|l| l.1 == "FAIL")
        .map(|l| l.0)
        .collect();
    let mut want: Vec<String> = must_fail.iter().map(|n| n.to_string()).collect();
    failed.sort();
    want.sort();
    assert_eq!(
        failed, want,
        "{fault} must fail exactly these:\n{}",
        r.stdout
    );
    eprintln!("{fault}: fails {}", want.join(", "));
    want
}

#[test]
fn the_correct_gpu_build_passes_and_every_seeded_fault_fails() {
    let ok = check(&[]);
    assert!(
        ok.success(),
        "correct build failed:\n{}{}",
        ok.stdout,
        ok.stderr
    );
    let lines = entries(&ok.stdout);
    let manifest = std::fs::read_to_string(golden_dir().join("manifest.toml")).unwrap();
    let n_entries = manifest.matches("[[entry]]").count();
    assert_eq!(lines.len(), n_entries, "one line per entry:\n{}", ok.stdout);
    // Every entry is rendered on the GPU and passes but the coverage debug output, which is
    // skipped with its reason.
    for (name, status, rest) in &lines {
        if name == "debug-coverage" {
            assert_eq!(status, "skip", "{rest}");
            assert!(
                rest.starts_with("skipped: debug output 'coverage'"),
                "{rest}"
            );
        } else {
            assert_eq!(status, "pass", "{name}: {rest}");
        }
    }

    // Each fault runs on entries it must fail (from the table of every fault over every
    // entry in docs/gpu.md: its smallest and largest margins) and, where named, entries it
    // must pass; the failures must be exactly the first set. A full pass per fault cost
    // CI about a minute of lavapipe for no more evidence: the correct run above and the
    // gain run below cover every entry. The transfer table's fault runs on every transfer
    // entry (it must fail all of them) and two entries without a table (it must pass them).
    let names: Vec<&str> = manifest
        .lines()
        .filter_map(|l| l.strip_prefix("name = \""))
        .map(|l| l.trim_end_matches('"'))
        .collect();
    let transfer: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| n.starts_with("env-transfer-"))
        .collect();
    assert!(transfer.len() >= 2, "{transfer:?}");
    for (fault, must_fail, must_pass) in [
        (
            "half-texel",
            &[
                "fig3-12-gold-dust-paint-median-cut",
                "fig3-10-blue-silk-bilinear",
            ][..],
            &[][..],
        ),
        (
            "no-cosine",
            &["fig3-11-lindt-paper", "fig3-6-importance-city"],
            &[],
        ),
        (
            "mirrored-azimuth",
            &[
                "env-transfer-teal-paint-city",
                "fig3-2-directional-light-azimuth",
            ],
            &[],
        ),
        (
            "srgb-twice",
            &["fig3-8-lloyd-studio", "fig3-13-teal-paint-f64"],
            &[],
        ),
        (
            "transfer-mirrored-azimuth",
            &transfer[..],
            &["default-160x120", "fig3-8-lloyd-studio"],
        ),
    ] {
        for n in must_fail.iter().chain(must_pass) {
            assert!(names.contains(n), "{fault}: no entry {n} in the manifest");
        }
        assert_fails_exactly(fault, must_fail, must_pass);
    }

    let reflection: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| n.starts_with("env-reflection-"))
        .collect();
    assert!(reflection.len() >= 2, "{reflection:?}");

    // The reflection table's own fault fails every entry that has one, and no other: run on
    // those and on a transfer-table entry and a delta-light entry, which must pass.
    assert_fails_exactly(
        "reflection-psi-sign",
        &reflection,
        &["env-transfer-lambert-studio", "default-160x120"],
    );
}

/// The faults a GPU porter would recognise beyond the five above, caught by the radiometric
/// bounds of golden/gpu-bounds.toml (FLIP lets most of them pass). A 0.5% gain must fail
/// every entry that renders radiance (all but the debug and angle outputs); each other fault
/// is run on entries it must fail (a subset, for CI's time; docs/gpu.md has every entry's
/// margin).
#[test]
fn the_radiometric_bounds_catch_a_gain_and_the_porting_faults() {
    let manifest = std::fs::read_to_string(golden_dir().join("manifest.toml")).unwrap();
    let table: toml::Table = toml::from_str(&manifest).unwrap();
    let manifest_entries = table["entry"].as_array().unwrap();
    let name = |e: &toml::Value| e["name"].as_str().unwrap().to_string();
    let lit: Vec<String> = manifest_entries
        .iter()
        .filter(|e| e.get("aov").is_none() && name(e) != "fig3-8-full-studio")
        .map(name)
        .collect();
    let aov: Vec<String> = manifest_entries
        .iter()
        .filter(|e| e.get("aov").is_some() && name(e) != "debug-coverage")
        .map(name)
        .collect();
    assert!(lit.len() >= 15 && aov.len() >= 4, "{lit:?} {aov:?}");
    // A 0.5% gain must fail every lit entry and no angle or debug output.
    let lit: Vec<&str> = lit.iter().map(String::as_str).collect();
    let aov: Vec<&str> = aov.iter().map(String::as_str).collect();
    assert_fails_exactly("gain", &lit, &aov);

    for (fault, must_fail) in [
        (
            "nearest-azimuth",
            &["fig3-10-blue-silk-bilinear", "fig3-11-lindt-paper"][..],
        ),
        (
            "diffuse-no-inv-pi",
            &["fig3-1-point-light-lambert", "env-transfer-lambert-studio"],
        ),
        (
            "sh-sign",
            &["fig3-10-blue-silk-bilinear", "fig3-13-teal-paint"],
        ),
        (
            "f16-tables",
            &[
                "fig3-12-gold-dust-paint-median-cut",
                "fig3-10-blue-silk-nearest",
            ],
        ),
        (
            "last-light-dropped",
            &["default-160x120", "fig3-8-median-cut-city"],
        ),
        (
            "rotation-sign",
            &[
                "env-transfer-lambert-studio",
                "env-reflection-blinn-phong-studio",
            ],
        ),
    ] {
        assert_fails_exactly(fault, must_fail, &[]);
    }
}

#[test]
fn an_unknown_fault_or_a_fault_on_the_cpu_is_a_one_line_error() {
    let r = check(&["--gpu-fault", "nonsense"]);
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert_eq!(r.stderr.trim().lines().count(), 1, "{}", r.stderr);
    assert!(r.stderr.contains("--gpu-fault"), "{}", r.stderr);
    let tmp = tempfile::tempdir().unwrap();
    let dir = golden_dir();
    let r = common::brdfkit(tmp.path()).run(&[
        "golden",
        "check",
        "--dir",
        dir.to_str().unwrap(),
        "--gpu-fault",
        "no-cosine",
    ]);
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(r.stderr.contains("needs --device gpu"), "{}", r.stderr);
}
