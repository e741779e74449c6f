//! `[env] method = "transfer"` end to end: a Lambert sphere against the converged reference
//! (`RenderOptions::converged_reference()` on `sampler = "full"`: f64, every texel a light)
//! under the shipped probes, and the scene errors of the method.

use crate::env_table_common::{against_reference, scene};
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::Environment;
use std::path::Path;

const LAMBERT: &str = "kind = \"lambert\"\nalbedo = [0.8, 0.6, 0.4]";

/// Lambert through the irradiance table (64 x 33 nodes, 16 exact lights) against the
/// converged reference: relative RMSE below 0.5% under city and studio (measured 0.052%
/// and 0.38%: studio's many bright lights cross horizons between nodes); without the table (a scene of the 16 exact lights alone) the
/// error is far above the bound, so the check sees the table.
#[test]
fn lambert_transfer_matches_the_converged_reference() {
    let grid =
        "method = \"transfer\"\ntransfer_azimuth = 64\ntransfer_polar = 33\nexact_lights = 16";
    for probe in ["city", "studio"] {
        let run = against_reference(probe, LAMBERT, grid, 16);
        let (e, e0) = (run.error, run.error_without_table);
        eprintln!("{probe}: Lambert transfer rel RMSE {e:.5}");
        assert!(e < 0.005, "{probe}: rel RMSE {e}");
        assert!(e0 > 0.05, "{probe}: the table adds too little ({e0})");
    }
}

#[test]
fn transfer_refuses_other_materials_and_bad_grids() {
    let phong = "kind = \"blinn-phong\"";
    let e = scene("city", phong, "method = \"transfer\"").err().unwrap();
    assert!(e.to_string().contains("env.method"), "{e}");
    let e = scene(
        "city",
        LAMBERT,
        "method = \"transfer\"\ntransfer_azimuth = 100",
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("env.transfer_azimuth"), "{e}");
}

use crate::common;

/// `render --reference` of a transfer scene is the converged reference (every texel a light,
/// no table): the same bits as the same scene with `method = "lights"`. Before, `--reference`
/// set only `sampler = "full"`, so a transfer scene got its table term added on top of the
/// full probe's lights (the probe counted twice).
#[test]
fn reference_of_a_transfer_scene_is_the_full_probe() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let probe = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/studio.exr");
    for (name, method) in [("t", "transfer"), ("l", "lights")] {
        // The table's grid is a field of `transfer` alone (another method's is an error).
        let grid = match method {
            "transfer" => "transfer_azimuth = 64\ntransfer_polar = 33\n",
            _ => "",
        };
        let text = format!(
            "[mesh]\nsource = \"sphere\"\n[material]\n{LAMBERT}\n[env]\nfile = {:?}\n\
             method = \"{method}\"\n{grid}",
            probe.to_str().unwrap()
        );
        std::fs::write(d.join(format!("{name}.toml")), text).unwrap();
        let r = common::brdfkit(d).run(&[
            "render",
            &format!("{name}.toml"),
            "--reference",
            "--width",
            "12",
            "--height",
            "12",
            "-o",
            &format!("{name}.exr"),
        ]);
        assert!(r.success(), "{method}: {}", r.stderr);
    }
    let t = brdfkit::image_io::read_exr(&d.join("t.exr")).unwrap();
    let l = brdfkit::image_io::read_exr(&d.join("l.exr")).unwrap();
    assert!(
        t.pixels == l.pixels,
        "--reference of a transfer scene differs"
    );
}

/// The largest per-pixel, per-channel difference of `a` from `oracle` relative to the pixel
/// (or to 1% of the image's peak where SH terms cancel), as tests/integration/kernel.rs measures the
/// lights' kernels against the scalar oracle.
fn worst_relative(a: &brdfkit::image_io::Image, oracle: &brdfkit::image_io::Image) -> f32 {
    let peak = oracle
        .pixels
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0f32, f32::max);
    let mut worst = 0.0f32;
    for (p, q) in a.pixels.iter().zip(&oracle.pixels) {
        let d = (*p - *q).abs().max_element();
        let scale = q.abs().max_element().max(1e-2 * peak);
        // A NaN difference counts as infinitely far.
        worst = worst.max(if d.is_nan() { f32::INFINITY } else { d / scale });
    }
    worst
}

/// The fast path folds the transfer term into its tile loop (one surface per pixel, SIMD
/// lookup and dot, polynomial angles, the data set's effective bands); the scalar oracle
/// adds it in a plain second pass (`std` angles, every band). Held within
/// `FAST_PATH_TOLERANCE` of each other on an 8-band SH material (city, 4 exact lights) and
/// on Lambert (studio); both instruction-set paths give the same bits, and so do 1 and 2
/// threads. The seeded fault (the fast path's lookup one azimuth node over) must exceed
/// the tolerance.
#[test]
fn fast_path_matches_the_scalar_oracle_within_the_tolerance() {
    use brdfkit::env::transfer::FAST_PATH_TOLERANCE;
    use brdfkit::shade::{KernelFault, ShadeOptions, ShadingPath};
    let grid =
        "method = \"transfer\"\ntransfer_azimuth = 32\ntransfer_polar = 17\nexact_lights = 4";
    for (probe, material) in [
        ("city", "kind = \"library\"\nname = \"teal-paint\""),
        ("studio", LAMBERT),
    ] {
        let mut s = scene(probe, material, grid).unwrap();
        s.render.width = 40;
        s.render.height = 40;
        let shade = |opts: ShadeOptions| {
            let vis = brdfkit::render::rasterize(&s, false);
            brdfkit::shade::shade(&s, &vis, &opts).image
        };
        let oracle = shade(ShadeOptions::default().with_path(ShadingPath::ScalarOracle));
        let mut fast_images = Vec::new();
        for kernel in crate::common::kernel_paths("transfer_scene") {
            let opts = ShadeOptions {
                kernel: Some(kernel),
                ..ShadeOptions::default()
            };
            fast_images.push(shade(opts));
        }
        let fast = &fast_images[0];
        for other in &fast_images[1..] {
            assert!(other.pixels == fast.pixels, "{probe}: paths differ in bits");
        }
        let worst = worst_relative(fast, &oracle);
        eprintln!("{probe}: fast vs oracle worst relative difference {worst:.2e}");
        assert!(worst <= FAST_PATH_TOLERANCE, "{probe}: {worst:.2e}");
        // The check sees the term: without it the fast image is far off.
        let mut bare = s.clone();
        bare.environment = Environment::Lights(s.environment.delta_lights().to_vec());
        let vis = brdfkit::render::rasterize(&bare, false);
        let no_term = brdfkit::shade::shade(&bare, &vis, &ShadeOptions::default()).image;
        assert!(worst_relative(&no_term, &oracle) > 100.0 * FAST_PATH_TOLERANCE);
        let faulty = shade(ShadeOptions {
            fault: Some(KernelFault::TransferAzimuthShift),
            ..ShadeOptions::default()
        });
        let w = worst_relative(&faulty, &oracle);
        eprintln!("{probe}: seeded azimuth shift {w:.2e}");
        assert!(
            w > FAST_PATH_TOLERANCE,
            "{probe}: the fault passed ({w:.2e})"
        );
        // Same bits for 1 and 2 threads (render on dedicated pools).
        let threads = |n| {
            let opts = RenderOptions {
                threads: Some(n),
                ..RenderOptions::default()
            };
            render(&s, &opts).image
        };
        assert!(
            threads(1).pixels == threads(2).pixels,
            "{probe}: thread counts differ"
        );
    }
}

/// `render --env-method transfer` overrides a scene's `[env] method = "lights"`: the table
/// is built once and written to the run's cache (`transfer-KEY.bin`), read back by the
/// next run (`(cached)`, the same bits), listed and cleaned by `brdfkit cache`; a damaged
/// entry is refused, rebuilt and rewritten (the same bits again). `--env-method lights`
/// renders another image; without an environment the flag is a clear error.
#[test]
fn env_method_flag_and_table_cache() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let probe = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr");
    let text = format!(
        "[mesh]\nsource = \"sphere\"\n[material]\n{LAMBERT}\n[env]\nfile = {:?}\n\
         method = \"auto\"\ntransfer_azimuth = 32\ntransfer_polar = 17\n",
        probe.to_str().unwrap()
    );
    std::fs::write(d.join("s.toml"), text).unwrap();
    let cli = common::brdfkit(d);
    let render = |method: &str, out: &str| {
        let r = cli.run(&[
            "render",
            "s.toml",
            "--env-method",
            method,
            "--width",
            "16",
            "--height",
            "16",
            "-o",
            out,
        ]);
        assert!(r.success(), "{method}: {}", r.stderr);
        (
            r.stderr,
            brdfkit::image_io::read_exr(&d.join(out)).unwrap().pixels,
        )
    };
    let entries = || -> Vec<std::path::PathBuf> {
        std::fs::read_dir(d.join("cache"))
            .map(|rd| {
                rd.map(|e| e.unwrap().path())
                    .filter(|p| p.to_string_lossy().contains("transfer-"))
                    .collect()
            })
            .unwrap_or_default()
    };
    let (err1, first) = render("transfer", "a.exr");
    assert!(
        err1.contains("transfer table") && !err1.contains("(cached)"),
        "{err1}"
    );
    let files = entries();
    assert_eq!(files.len(), 1, "{files:?}");
    let entry = std::fs::read(&files[0]).unwrap();
    let (err2, second) = render("transfer", "b.exr");
    assert!(err2.contains("(cached)"), "{err2}");
    assert!(first == second, "a cached table renders other bits");
    // Damage the last value: refused with a warning, rebuilt, rewritten as before.
    let mut bad = entry.clone();
    *bad.last_mut().unwrap() ^= 0x40;
    std::fs::write(&files[0], &bad).unwrap();
    let (err3, third) = render("transfer", "c.exr");
    assert!(
        err3.contains("checksum") && !err3.contains("(cached)"),
        "{err3}"
    );
    assert!(first == third);
    assert_eq!(std::fs::read(&files[0]).unwrap(), entry);
    // The flag does take effect: `--env-method lights` renders another image.
    let (_, lights) = render("lights", "d.exr");
    assert!(lights != first);
    let show = cli.run(&["cache"]);
    assert!(
        show.stdout.contains("transfer and reflection tables"),
        "{}",
        show.stdout
    );
    let clean = cli.run(&["cache", "clean"]);
    assert!(clean.success(), "{}", clean.stderr);
    assert!(entries().is_empty());
    // No environment: a clear error naming the flag.
    let r = cli.run(&["render", "--env-method", "transfer", "-o", "x.png"]);
    assert!(!r.success());
    assert!(
        r.stderr.contains("--env-method") && r.stderr.contains("[env]"),
        "{}",
        r.stderr
    );
}
