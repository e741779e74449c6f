//! Golden images: every entry of golden/manifest.toml re-renders within its tolerance, and
//! the check is able to fail (a perturbed reference is caught and leaves its report).

use brdfkit::golden::{self, CROSS_PLATFORM};
use brdfkit::image_io;
use std::path::Path;

fn golden_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

#[test]
fn golden_set_matches() {
    let report = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/golden-failures");
    let outcomes = golden::check(&golden_dir(), &report).expect("golden check runs");
    assert!(!outcomes.is_empty());
    let failed: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.passed)
        .map(|o| format!("{}: {}", o.name, o.message))
        .collect();
    assert!(
        failed.is_empty(),
        "golden failures (see {}):\n{}",
        report.display(),
        failed.join("\n")
    );
}

#[test]
fn a_perturbed_reference_is_caught() {
    let tmp = tempfile::tempdir().unwrap();
    for e in std::fs::read_dir(golden_dir()).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, tmp.path().join(p.file_name().unwrap())).unwrap();
    }
    let manifest = golden::load_manifest(tmp.path()).unwrap();
    let entry = &manifest.entries[0];
    let exr = tmp.path().join(format!("{}.exr", entry.name));
    let mut img = image_io::read_exr(&exr).unwrap();
    // One covered pixel off by 1%: a shading change far smaller than any real bug.
    let i = img
        .pixels
        .iter()
        .position(|p| p.max_element() > 0.1)
        .unwrap();
    img.pixels[i] *= 1.01;
    image_io::write_exr(&exr, &img).unwrap();
    // Keep the manifest hash consistent, so only the pixel comparison can catch it.
    let text = std::fs::read_to_string(tmp.path().join("manifest.toml")).unwrap();
    let text = text.replace(&entry.hash, &golden::content_hash(&img));
    std::fs::write(tmp.path().join("manifest.toml"), text).unwrap();
    let report = tmp.path().join("report");
    let outcomes = golden::check(tmp.path(), &report).unwrap();
    assert!(
        !outcomes[0].passed,
        "a 1% change of one pixel passed the check"
    );
    assert_eq!(outcomes[0].pixels_over_tolerance, 1);
    assert!(
        report.join(format!("{}.png", entry.name)).exists(),
        "no expected|difference|actual image"
    );
    assert!(
        report.join(format!("{}.json", entry.name)).exists(),
        "no JSON report"
    );
}

#[test]
fn tolerance_admits_ulps_but_not_changes() {
    let a = image_io::Image {
        width: 2,
        height: 1,
        pixels: vec![glam::Vec3::splat(0.5), glam::Vec3::ZERO],
    };
    let mut b = a.clone();
    b.pixels[0] = glam::Vec3::splat(f32::from_bits(0.5f32.to_bits() + 4));
    assert_eq!(
        golden::compare(&a, &b, CROSS_PLATFORM),
        Some((b.pixels[0].x - 0.5, 0))
    );
    b.pixels[1] = glam::Vec3::new(0.0, 1e-3, 0.0);
    assert_eq!(golden::compare(&a, &b, CROSS_PLATFORM).unwrap().1, 1);
    b.pixels[1] = glam::Vec3::new(f32::NAN, 0.0, 0.0);
    assert_eq!(
        golden::compare(&a, &b, CROSS_PLATFORM).unwrap().1,
        1,
        "NaN must fail"
    );
}

#[test]
fn a_test_run_never_writes_golden_files() {
    let before: Vec<(std::path::PathBuf, std::time::SystemTime)> = std::fs::read_dir(golden_dir())
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (e.path(), e.metadata().unwrap().modified().unwrap())
        })
        .collect();
    let _ = golden::check(
        &golden_dir(),
        &std::env::temp_dir().join("brdfkit-golden-probe"),
    );
    for (p, t) in before {
        assert_eq!(
            std::fs::metadata(&p).unwrap().modified().unwrap(),
            t,
            "{} was modified by a check",
            p.display()
        );
    }
}
