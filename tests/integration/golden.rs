//! Golden images: every entry of golden/manifest.toml re-renders within its tolerance, and
//! the check is able to fail (a perturbed reference is caught and leaves its report).
//!
//! (Past 400 lines because it is the golden oracle's own test: that every entry re-renders,
//! that each way it can fail is caught, and that the manifest, its README table and its
//! bounds agree; split, the perturbation helpers would have to be shared across files.)

use crate::shading_paths;

use brdfkit::aov::Aov;
use brdfkit::env::schema::SamplerKind;
use brdfkit::golden::{self, CheckOptions, CROSS_PLATFORM, KERNEL_DISPATCH};
use brdfkit::image_io;
use brdfkit::lanes::KernelPath;
use brdfkit::scene::{LightSpec, MaterialSpec, Precision, Scene, SceneFile};
use brdfkit::sh::Lookup;
use shading_paths::scalar_oracle;
use std::collections::BTreeSet;
use std::path::Path;

fn golden_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

/// A copy of golden/ in a temporary directory (probe paths `../assets/` made absolute),
/// with `edits` (file name, text to find, replacement) applied to its scene files.
pub(crate) fn golden_copy(edits: &[(&str, &str, &str)]) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/");
    for e in std::fs::read_dir(golden_dir()).unwrap() {
        let p = e.unwrap().path();
        let to = tmp.path().join(p.file_name().unwrap());
        if p.extension().is_some_and(|x| x == "toml") {
            let text = std::fs::read_to_string(&p).unwrap();
            std::fs::write(
                &to,
                text.replace("\"../assets/", &format!("\"{}", assets.display())),
            )
            .unwrap();
        } else {
            std::fs::copy(&p, &to).unwrap();
        }
    }
    for (file, from, to) in edits {
        let path = tmp.path().join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(from), "{file} has no {from:?}");
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    }
    tmp
}

#[test]
fn golden_set_matches_on_every_kernel_path() {
    // Every path this CPU runs (portable, avx2, avx512): identical bits on the path that
    // blessed an entry, the entry's tolerance on the others; and since the kernel paths are
    // built to give the same bits (fused multiply-add on all, one lane-sum order, 16 lanes
    // only for per-light and per-pixel values), no pixel may differ on any path of the
    // blessing platform.
    let report = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/golden-failures");
    let paths = crate::common::kernel_paths("golden: every kernel path gives the blessed bits");
    assert!(paths.contains(&KernelPath::Portable));
    let manifest = golden::load_manifest(&golden_dir()).unwrap();
    if !manifest.entries.iter().any(golden::blessed_here) {
        crate::common::cannot_run(
            "golden: identical bits on the blessing platform",
            &format!("no entry was blessed on {}", golden::platform()),
        );
    }
    for kernel in paths {
        let opts = CheckOptions { kernel };
        let outcomes =
            golden::check(&golden_dir(), &report, &[], &opts).expect("golden check runs");
        assert!(!outcomes.is_empty());
        let failed: Vec<String> = outcomes
            .iter()
            .filter(|o| !o.passed)
            .map(|o| format!("{}: {}", o.name, o.message))
            .collect();
        assert!(
            failed.is_empty(),
            "golden failures on the {} path (see {}):\n{}",
            kernel.name(),
            report.display(),
            failed.join("\n")
        );
        let manifest = golden::load_manifest(&golden_dir()).unwrap();
        for (o, e) in outcomes.iter().zip(&manifest.entries) {
            assert_eq!(o.name, e.name);
            eprintln!("{} [{}]: {}", o.name, kernel.name(), o.message);
            if golden::blessed_here(e) {
                assert_eq!(
                    o.pixels_differing,
                    0,
                    "{} on the {} path: {}",
                    o.name,
                    kernel.name(),
                    o.message
                );
            }
        }
    }
}

#[test]
fn a_perturbed_reference_is_caught() {
    let tmp = golden_copy(&[]);
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
    let outcomes = golden::check(
        tmp.path(),
        &report,
        std::slice::from_ref(&entry.name),
        &CheckOptions::default(),
    )
    .unwrap();
    assert_eq!(outcomes.len(), 1);
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
    let reports = tempfile::tempdir().unwrap();
    let _ = golden::check(&golden_dir(), reports.path(), &[], &CheckOptions::default());
    for (p, t) in before {
        assert_eq!(
            std::fs::metadata(&p).unwrap().modified().unwrap(),
            t,
            "{} was modified by a check",
            p.display()
        );
    }
}

#[test]
fn scene_perturbations_of_shaded_entries_are_caught() {
    // Faults a port could make, seeded into the scene files of two entries at their
    // shipped tolerance (kernel-dispatch): the coefficient table filtered bilinearly instead
    // of GL_NEAREST (a texel-filtering fault, like the half-texel shift of
    // tests/integration/perturbation.rs), and the probe turned by 2 degrees about +y (a probe
    // orientation fault).
    let silk = "fig3-10-blue-silk-nearest";
    let city = "fig3-8-median-cut-city";
    let tmp = golden_copy(&[
        (
            "fig3-10-blue-silk-nearest.toml",
            "lookup = \"nearest\"",
            "lookup = \"bilinear\"",
        ),
        (
            "fig3-8-median-cut-city.toml",
            "seed = 1",
            "seed = 1\nrotation = 2.0",
        ),
    ]);
    let report = tmp.path().join("report");
    let names = [silk.to_string(), city.to_string()];
    let outcomes = golden::check(tmp.path(), &report, &names, &CheckOptions::default()).unwrap();
    assert_eq!(outcomes.len(), 2);
    for o in &outcomes {
        eprintln!("{}: {}", o.name, o.message);
        assert!(
            !o.passed,
            "{}: a seeded fault passed: {}",
            o.name, o.message
        );
        assert!(o.pixels_over_tolerance > 0, "{}: {}", o.name, o.message);
        assert!(report.join(format!("{}.png", o.name)).exists());
    }
}

#[test]
fn every_entry_is_blessed_and_states_its_fast_vs_reference_bound() {
    let manifest = golden::load_manifest(&golden_dir()).unwrap();
    for e in &manifest.entries {
        assert!(e.hash.starts_with("xxh3-64:"), "{}: not blessed", e.name);
        assert!(!e.config.is_empty(), "{}: no configuration summary", e.name);
        assert!(!e.shows.is_empty(), "{}: no description", e.name);
        assert!(
            e.blessed_on.contains('-'),
            "{}: no blessed_on (platform and kernel path)",
            e.name
        );
        assert_eq!(
            e.aov.is_none(),
            e.fast_vs_reference_small.is_some(),
            "{}: a shaded entry (only) has a small bound",
            e.name
        );
        match (e.aov, e.fast_vs_reference) {
            (None, Some(b)) => assert!(
                b.max_abs.is_finite() && b.rel_rmse.is_finite() && b.flip_mean.is_finite(),
                "{}: {b:?}",
                e.name
            ),
            (None, None) => panic!("{}: shaded entry without a measured bound", e.name),
            (Some(_), b) => assert!(b.is_none(), "{}: a debug output has no reference", e.name),
        }
        assert!(
            golden_dir().join(format!("{}.png", e.name)).exists(),
            "{}: no PNG preview",
            e.name
        );
    }
}

#[test]
fn readme_table_matches_the_manifest() {
    let manifest = golden::load_manifest(&golden_dir()).unwrap();
    let readme = std::fs::read_to_string(golden_dir().join("README.md")).unwrap();
    let regenerated = golden::with_readme_table(&readme, &manifest)
        .expect("golden/README.md has the table markers");
    assert!(
        regenerated == readme,
        "golden/README.md's table differs from manifest.toml: run `brdfkit golden bless`"
    );
}

#[test]
fn the_set_covers_every_configuration() {
    let dir = golden_dir();
    let manifest = golden::load_manifest(&dir).unwrap();
    let mut seen = BTreeSet::new();
    for e in &manifest.entries {
        let f = SceneFile::load(&dir.join(&e.scene)).unwrap();
        if let Some(a) = e.aov {
            seen.insert(format!("aov {a:?}"));
            continue;
        }
        seen.insert(format!("precision {:?}", f.render.precision));
        let (kind, lookup) = match &f.material {
            MaterialSpec::Lambert { .. } => ("lambert", None),
            MaterialSpec::BlinnPhong { .. } => ("blinn-phong", None),
            MaterialSpec::Library { name, lookup } => {
                let sh = brdfkit::library::find(name).unwrap().representation
                    != brdfkit::library::Representation::Dbrdf;
                if sh {
                    ("library SH", Some(lookup.unwrap_or(Lookup::Bilinear)))
                } else {
                    ("library D-BRDF", None)
                }
            }
            MaterialSpec::ShFile { lookup, .. } => {
                ("sh-file", Some(lookup.unwrap_or(Lookup::Nearest)))
            }
            MaterialSpec::DbrdfFile { .. } => ("dbrdf-file", None),
            // Not required below: a MERL table is 35 MB (tests/integration/material_files.rs
            // renders one).
            MaterialSpec::MerlFile { .. } => ("merl-file", None),
            // Not required below either: tests/integration/material_files.rs renders RGL
            // files written by the tests.
            MaterialSpec::RglFile { .. } => ("rgl-file", None),
        };
        seen.insert(format!("material {kind}"));
        if let Some(l) = lookup {
            seen.insert(format!("lookup {l:?}"));
        }
        for l in f.lights.iter().flatten() {
            seen.insert(match l {
                LightSpec::Point { .. } => "light point".into(),
                LightSpec::Directional { .. } => "light directional".into(),
            });
        }
        if let Some(env) = &f.env {
            seen.insert("light environment".into());
            seen.insert(format!("sampler {:?}", env.sampler));
        }
    }
    let mut want: Vec<String> = [
        "material lambert",
        "material blinn-phong",
        "material library SH",
        "material library D-BRDF",
        "material sh-file",
        "material dbrdf-file",
        "light point",
        "light directional",
        "light environment",
        "lookup Nearest",
        "lookup Bilinear",
    ]
    .map(String::from)
    .to_vec();
    want.extend([Precision::F32, Precision::F64].map(|p| format!("precision {p:?}")));
    want.extend(
        [
            SamplerKind::Uniform,
            SamplerKind::Importance,
            SamplerKind::Stratified,
            SamplerKind::MedianCut,
            SamplerKind::Lloyd,
            SamplerKind::Full,
        ]
        .map(|s| format!("sampler {s:?}")),
    );
    want.extend(
        [
            Aov::Normal,
            Aov::Depth,
            Aov::Coverage,
            Aov::ViewPolar,
            Aov::ViewAzimuth,
            Aov::LightPolar,
            Aov::LightAzimuth,
        ]
        .map(|a| format!("aov {a:?}")),
    );
    let missing: Vec<&String> = want.iter().filter(|w| !seen.contains(*w)).collect();
    assert!(missing.is_empty(), "the golden set lacks {missing:?}");
}

#[test]
fn kernel_dispatch_tolerance_is_relative_to_a_floor_of_the_peak() {
    // Peak 1.0: a near-zero pixel (SH cancellation) may move by 1e-3 x 1% of the peak...
    let a = image_io::Image {
        width: 2,
        height: 1,
        pixels: vec![glam::Vec3::splat(1.0), glam::Vec3::splat(1e-4)],
    };
    let mut b = a.clone();
    b.pixels[1] = glam::Vec3::splat(1e-4 + 9e-6);
    assert_eq!(golden::compare(&a, &b, KERNEL_DISPATCH).unwrap().1, 0);
    assert_eq!(
        golden::compare(&a, &b, CROSS_PLATFORM).unwrap().1,
        0,
        "9e-6 is inside cross-platform's absolute 1e-5"
    );
    // ...but not by 2e-5, and a bright pixel not by 1%.
    b.pixels[1] = glam::Vec3::splat(1e-4 + 2e-5);
    assert_eq!(golden::compare(&a, &b, KERNEL_DISPATCH).unwrap().1, 1);
    b.pixels[1] = a.pixels[1];
    b.pixels[0] = glam::Vec3::splat(1.01);
    assert_eq!(golden::compare(&a, &b, KERNEL_DISPATCH).unwrap().1, 1);
    b.pixels[0] = glam::Vec3::splat(1.0009);
    assert_eq!(golden::compare(&a, &b, KERNEL_DISPATCH).unwrap().1, 0);
}

#[test]
fn manifest_errors_name_the_file_entry_and_field() {
    let ok = "[[entry]]\nname = \"a\"\nscene = \"a.toml\"\ntolerance = \"cross-platform\"\n";
    assert!(golden::parse_manifest(ok).is_ok());
    for (text, want) in [
        (
            ok.replace("cross-platform", "close"),
            "entry[0] ('a').tolerance: unknown tolerance 'close'",
        ),
        (ok.replace("\"a\"", "\"../a\""), "entry[0] ('../a').name"),
        (format!("{ok}\n{ok}"), "entry[1] ('a').name: duplicate"),
        (
            ok.replace("scene = \"a.toml\"", "scene = \"\""),
            "entry[0] ('a').scene",
        ),
        (
            format!("{ok}flip = {{ mean = 0.01, percentile = 1.5, at_percentile = 0.1 }}\n"),
            "entry[0] ('a').flip",
        ),
        (
            format!("{ok}colour = 1\n"),
            "line 5: entry[0].colour: unknown field `colour`",
        ),
        (
            ok.replace("tolerance = \"cross-platform\"\n", ""),
            "missing field `tolerance`",
        ),
    ] {
        let e = golden::parse_manifest(&text).unwrap_err();
        assert!(e.contains(want), "{e:?} lacks {want:?}");
    }
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("manifest.toml"),
        ok.replace("cross-platform", "close"),
    )
    .unwrap();
    let e = golden::load_manifest(d.path()).unwrap_err().to_string();
    assert!(
        e.contains("manifest.toml") && e.contains(".tolerance"),
        "{e}"
    );
}

#[test]
fn scene_precision_and_lookup_fields() {
    // precision = "f64" renders through the f64 path with no skips, bit for bit.
    let mut f = SceneFile::parse(
        "[mesh]\nsegments = 4\n[material]\nkind = \"library\"\nname = \"magenta-plastic\"\n\
         lookup = \"nearest\"\n[render]\nwidth = 24\nheight = 18\nprecision = \"f64\"\n",
    )
    .unwrap();
    let s = Scene::resolve(&f, Path::new(".")).unwrap();
    assert_eq!(s.material.as_sh().unwrap().coeff_lookup, Lookup::Nearest);
    let f64_img = brdfkit::render::render(&s, &Default::default()).image;
    let f64_path = brdfkit::render::RenderOptions::default()
        .with_path(brdfkit::shade::ShadingPath::F64NoSkips);
    assert_eq!(f64_img, brdfkit::render::render(&s, &f64_path).image);
    f.render.precision = Precision::F32;
    let s32 = Scene::resolve(&f, Path::new(".")).unwrap();
    assert_ne!(
        brdfkit::render::render(&s32, &Default::default()).image,
        f64_img
    );
    // Without a lookup the library's own (bilinear) stays.
    f.material = MaterialSpec::Library {
        name: "magenta-plastic".into(),
        lookup: None,
    };
    let s = Scene::resolve(&f, Path::new(".")).unwrap();
    assert_eq!(s.material.as_sh().unwrap().coeff_lookup, Lookup::Bilinear);
    // A D-BRDF has no coefficient table: the error names the field.
    f.material = MaterialSpec::Library {
        name: "lindt-paper".into(),
        lookup: Some(Lookup::Nearest),
    };
    let e = Scene::resolve(&f, Path::new("."))
        .err()
        .unwrap()
        .to_string();
    assert!(e.starts_with("material.lookup:"), "{e}");
    let e = SceneFile::parse("[render]\nprecision = \"f16\"\n").unwrap_err();
    assert!(e.contains("line 2") && e.contains("f16"), "{e}");
}

#[test]
fn a_stale_manifest_is_caught() {
    // The stored image edited outside bless (hash), and a manifest whose configuration
    // summary no longer describes the scene.
    let tmp = golden_copy(&[]);
    let manifest = golden::load_manifest(tmp.path()).unwrap();
    let e = manifest
        .entries
        .iter()
        .find(|e| e.name == "debug-depth")
        .unwrap();
    let text = std::fs::read_to_string(tmp.path().join("manifest.toml")).unwrap();
    let stale = text.replacen(&e.config, "teapot/8 80x60, lambert", 1);
    std::fs::write(tmp.path().join("manifest.toml"), &stale).unwrap();
    let names = [e.name.clone()];
    let o = &golden::check(
        tmp.path(),
        &tmp.path().join("r"),
        &names,
        &CheckOptions::default(),
    )
    .unwrap()[0];
    assert!(
        !o.passed && o.message.contains("config is stale"),
        "{}",
        o.message
    );
    let rehashed = text.replacen(&e.hash, "xxh3-64:0000000000000000", 1);
    std::fs::write(tmp.path().join("manifest.toml"), &rehashed).unwrap();
    let o = &golden::check(
        tmp.path(),
        &tmp.path().join("r"),
        &names,
        &CheckOptions::default(),
    )
    .unwrap()[0];
    assert!(
        !o.passed && o.message.contains("manifest hash"),
        "{}",
        o.message
    );
    // An unknown name is an error naming the manifest.
    let err = golden::check(
        tmp.path(),
        &tmp.path().join("r"),
        &["nope".into()],
        &CheckOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("manifest.toml") && err.contains("'nope'"),
        "{err}"
    );
}

#[test]
fn the_scalar_oracle_passes_every_shaded_f32_entry() {
    // Another dispatch path must pass the check: the scalar oracle (`ShadingPath::ScalarOracle`, the
    // per-light `Brdf::eval` loop, no SIMD, no culling, another summation order) is held
    // against each stored fast render at the entry's own tolerance.
    let dir = golden_dir();
    let manifest = golden::load_manifest(&dir).unwrap();
    let mut checked = 0;
    for e in manifest.entries.iter().filter(|e| e.aov.is_none()) {
        let f = SceneFile::load(&dir.join(&e.scene)).unwrap();
        if f.render.precision != Precision::F32 {
            continue;
        }
        let scene = Scene::resolve(&f, &dir).unwrap();
        let vis = brdfkit::render::rasterize(&scene, false);
        let oracle = scalar_oracle(&scene, &vis);
        let stored = image_io::read_exr(&dir.join(format!("{}.exr", e.name))).unwrap();
        let tol = golden::tolerance_named(&e.tolerance).unwrap();
        let (max_abs, over) = golden::compare(&stored, &oracle, tol).unwrap();
        // The largest share of the tolerance used by any channel.
        let peak = stored
            .pixels
            .iter()
            .map(|p| p.max_element())
            .fold(0.0f32, f32::max);
        let used = stored
            .pixels
            .iter()
            .zip(&oracle.pixels)
            .flat_map(|(s, o)| {
                let lim = glam::Vec3::splat(tol.abs)
                    + s.abs().max(glam::Vec3::splat(tol.peak_floor * peak)) * tol.rel;
                ((*o - *s).abs() / lim).to_array()
            })
            .fold(0.0f32, f32::max);
        eprintln!(
            "{}: scalar oracle max abs {max_abs:.3e}, {:.1}% of the tolerance",
            e.name,
            100.0 * used
        );
        assert_eq!(
            over, 0,
            "{}: the scalar oracle fails '{}'",
            e.name, e.tolerance
        );
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} shaded f32 entries");
}

/// The kernel path that blessed `name`, if this machine is its platform and runs that
/// path (whatever `auto` picks here); the exact-bits faults below are only meaningful there.
/// The kernel path to check entry `name` on where the check is exact for it: the path that
/// blessed it when this CPU runs it, else any (every path gives the same bits, which
/// `golden_set_matches_on_every_kernel_path` checks); `None` off the
/// entry's platform.
fn blessing_kernel(name: &str) -> Option<KernelPath> {
    let manifest = golden::load_manifest(&golden_dir()).unwrap();
    let e = manifest.entries.iter().find(|e| e.name == name).unwrap();
    if !golden::blessed_here(e) {
        return None;
    }
    let available = KernelPath::available();
    let blessed = available
        .iter()
        .copied()
        .find(|p| e.blessed_on == format!("{}/{}", golden::platform(), p.name()));
    Some(blessed.unwrap_or(available[0]))
}

#[test]
fn regressions_within_the_tolerance_fail_on_the_blessing_path() {
    // Three faults that move pixels by far less than the kernel-dispatch tolerance (1e-3 of
    // the pixel), each of which the old tolerance-only check passed: the environment's
    // radiance 0.05% too bright, the dimmest lights of the full studio probe dropped, and
    // one texel on the probe's u = 0 seam lost. On the path that blessed the entries every
    // bit must agree, so each fails there.
    let city = "fig3-8-median-cut-city";
    let full = "fig3-8-full-studio";
    let (Some(kernel), Some(_)) = (blessing_kernel(city), blessing_kernel(full)) else {
        crate::common::cannot_run(
            "golden: regressions within the tolerance fail on the blessing platform",
            &format!(
                "this platform ({}) is not the one that blessed {city} and {full}",
                golden::platform()
            ),
        );
        return;
    };
    let report = tempfile::tempdir().unwrap();
    type Edits<'a> = Vec<(&'a str, &'a str, &'a str)>;
    let faults: [(&str, &str, Edits); 3] = [
        (
            "0.05% constant",
            city,
            vec![(
                "fig3-8-median-cut-city.toml",
                "seed = 1",
                "seed = 1\nintensity = 1.0005",
            )],
        ),
        (
            "dimmest lights dropped",
            full,
            vec![(
                "fig3-8-full-studio.toml",
                "drop_lights = 0.0",
                "drop_lights = 0.00001",
            )],
        ),
        (
            "one seam texel lost",
            full,
            vec![(
                "fig3-8-full-studio.toml",
                "assets/probes/studio.exr\"",
                "SEAM\"",
            )],
        ),
    ];
    for (what, name, edits) in faults {
        let tmp = golden_copy(&edits);
        // The seam fault's probe: studio.exr with texel (0, h/2) black.
        let toml = tmp.path().join("fig3-8-full-studio.toml");
        let text = std::fs::read_to_string(&toml).unwrap();
        if text.contains("SEAM\"") {
            let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/studio.exr");
            let mut probe = image_io::read_exr(&src).unwrap();
            let (w, h) = (probe.width, probe.height);
            assert!(probe.get(0, h / 2).max_element() > 0.0);
            probe.pixels[(h / 2 * w) as usize] = glam::Vec3::ZERO;
            let seam = tmp.path().join("studio-seam.exr");
            image_io::write_exr(&seam, &probe).unwrap();
            let start = text.find("file = \"").unwrap() + "file = \"".len();
            let end = text.find("SEAM\"").unwrap() + "SEAM".len();
            let fixed = format!("{}{}{}", &text[..start], seam.display(), &text[end..]);
            std::fs::write(&toml, fixed).unwrap();
        }
        let o = golden::check(
            tmp.path(),
            report.path(),
            &[name.to_string()],
            &CheckOptions { kernel },
        )
        .unwrap()
        .remove(0);
        eprintln!(
            "{what} ({name}): {} pixels differ, {} over the tolerance, max abs {:.3e}: {}",
            o.pixels_differing, o.pixels_over_tolerance, o.max_abs_error, o.message
        );
        assert!(!o.passed, "{what}: passed the check");
        assert!(o.pixels_differing > 0, "{what}: changed no bit");
        assert_eq!(
            o.pixels_over_tolerance, 0,
            "{what}: the tolerance alone catches it; pick a smaller fault"
        );
    }
}

#[test]
fn fast_vs_reference_bounds_hold_for_every_shaded_entry() {
    // Re-measures each shaded entry's fast-vs-reference bound at 1/4 of its size (the f64
    // reference with every probe texel a light) and holds it to the stored one.
    let out = golden::check_bounds(&golden_dir(), &[]).expect("bounds measured");
    let manifest = golden::load_manifest(&golden_dir()).unwrap();
    let shaded = manifest.entries.iter().filter(|e| e.aov.is_none()).count();
    assert_eq!(out.len(), shaded);
    for b in &out {
        eprintln!(
            "{}: measured {:?}, stored {:?}",
            b.name, b.measured, b.stored
        );
    }
    let failed: Vec<&str> = out
        .iter()
        .filter(|b| !b.passed)
        .map(|b| b.name.as_str())
        .collect();
    assert!(failed.is_empty(), "bounds exceeded: {failed:?}");
}

#[test]
fn a_sampler_that_drifts_from_the_reference_fails_the_bound_check() {
    // The same entry with a quarter of its lights: its error against the converged
    // reference grows past the stored bound.
    let name = "fig3-8-lloyd-studio";
    let tmp = golden_copy(&[("fig3-8-lloyd-studio.toml", "count = 64", "count = 16")]);
    let out = golden::check_bounds(tmp.path(), &[name.to_string()]).unwrap();
    eprintln!(
        "{name} with 16 lights: {:?} vs stored {:?}",
        out[0].measured, out[0].stored
    );
    assert!(!out[0].passed);
}

#[test]
fn an_f64_entry_is_measured_against_the_fast_path_not_itself() {
    let manifest = golden::load_manifest(&golden_dir()).unwrap();
    let e = manifest
        .entries
        .iter()
        .find(|e| e.name == "fig3-13-teal-paint-f64")
        .unwrap();
    let b = golden::measure(&golden_dir(), e, golden::BOUND_CHECK_SCALE)
        .unwrap()
        .unwrap();
    eprintln!("{}: f32 fast path vs f64 reference at 1/4: {b:?}", e.name);
    assert!(b.max_abs > 0.0, "the fast side is the reference itself");
}
