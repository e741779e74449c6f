//! Turning the environment (`render --turntable N --turntable-env`): frame `k` of `N` is
//! the static render of the scene file whose `[env] rotation` is `360 k / N` degrees, for
//! every `[env] method` (`lights`, `transfer`, `lightcuts`, `reflection`, `auto`) and every material
//! class of the sweep (diffuse: Lambert; sh-glossy: the library's teal-paint SH data set;
//! glossy: Blinn-Phong 200) plus a D-BRDF (the library's lindt-paper). Every method builds
//! the environment again at the frame's rotation, so the tolerance is zero: the same bits.
//! The seeded fault "nothing turns" ([`TurnFault::NothingTurns`]) must fail every case, and
//! the command line's frames must equal its static renders (the README's turntable). Each
//! case renders 24 x 24 pixels under the city probe box-downsampled to 128 x 64
//! ([`common::small_city_probe`]): turning is the same code at any probe size, and on the
//! 512 x 256 file the SH data set's reflection bake (its error measurement evaluates the
//! SH series against every texel) took 80 of the test's 100 seconds.

use crate::common;
use brdfkit::env::lightset::prepare::CacheDir;
use brdfkit::image_io::Image;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::turntable::{frame_scene_seeded, Motion, TurnFault};
use std::path::Path;

const SIDE: u32 = 24;
/// Frame `K` of `N`: 135 degrees.
const K: usize = 3;
const N: usize = 8;

const CLASSES: [(&str, &str); 4] = [
    ("diffuse", "kind = \"lambert\"\nalbedo = [0.8, 0.8, 0.8]"),
    ("sh-glossy", "kind = \"library\"\nname = \"teal-paint\""),
    (
        "glossy",
        "kind = \"blinn-phong\"\nkd = [0.05, 0.05, 0.05]\nks = [0.9, 0.9, 0.9]\nexponent = 200.0",
    ),
    ("dbrdf", "kind = \"library\"\nname = \"lindt-paper\""),
];

/// Small tables and sets: the check is of turning, not of accuracy.
const METHODS: [(&str, &str); 5] = [
    (
        "lights",
        "method = \"lights\"\nsampler = \"median-cut\"\ncount = 32",
    ),
    (
        "transfer",
        "method = \"transfer\"\ntransfer_azimuth = 32\ntransfer_polar = 17\nexact_lights = 8",
    ),
    ("lightcuts", "method = \"lightcuts\"\ncut_error = 0.02"),
    (
        "reflection",
        "method = \"reflection\"\nreflection_grid = 8\nreflection_slices = 3\nreflection_residual = 32",
    ),
    (
        "auto",
        "transfer_azimuth = 32\ntransfer_polar = 17\nexact_lights = 8\ncut_error = 0.02\n\
         reflection_grid = 8\nreflection_slices = 3\nreflection_residual = 32",
    ),
];

/// The pairs a method cannot shade (a transfer table: SH data sets and Lambert only;
/// light cuts: no cone bound for an SH data set). `reflection` shades lindt-paper
/// (anisotropic) by filtered importance sampling, built again at each rotation.
const REFUSED: [(&str, &str); 3] = [
    ("transfer", "glossy"),
    ("transfer", "dbrdf"),
    ("lightcuts", "sh-glossy"),
];

fn text(probe: &str, material: &str, env: &str, rotation: f64) -> String {
    format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 24\n[material]\n{material}\n\
         [env]\nfile = {probe:?}\nrotation = {rotation:?}\n{env}\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\n"
    )
}

fn resolve(text: &str) -> brdfkit::error::Result<Scene> {
    Scene::resolve(
        &SceneFile::parse(text).unwrap(),
        Path::new(env!("CARGO_MANIFEST_DIR")),
    )
}

fn image(s: &Scene) -> Image {
    render(s, &RenderOptions::default()).image
}

/// Largest per-pixel channel difference over the image's peak.
fn relative_max(a: &Image, b: &Image) -> f32 {
    let peak = b
        .pixels
        .iter()
        .map(|p| p.max_element())
        .fold(0.0f32, f32::max);
    let worst = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0f32, f32::max);
    worst / peak.max(f32::MIN_POSITIVE)
}

/// What one case measured: whether frame `K` of `N` has the bits of the static render at
/// its rotation, and the largest difference from that render (relative to its peak) of the
/// frame, of the frame turned with the seeded fault "nothing turns", and of the unturned
/// scene.
struct Turned {
    same: bool,
    diff: f32,
    fault_same: bool,
    fault_diff: f32,
    unturned: f32,
}

/// Frame `K` of `N` of every method and class against the static render at `360 K / N`
/// degrees; `None` where the method refuses the material.
fn cases() -> Vec<(&'static str, &'static str, Option<Turned>)> {
    let degrees = 360.0 * K as f64 / N as f64;
    let dir = tempfile::tempdir().unwrap();
    let probe = common::small_city_probe(dir.path());
    let mut out = Vec::new();
    for (class, material) in CLASSES {
        for (method, env) in METHODS {
            let base = match resolve(&text(&probe, material, env, 0.0)) {
                Ok(s) => s,
                Err(e) => {
                    assert!(REFUSED.contains(&(method, class)), "{method} {class}: {e}");
                    assert!(e.to_string().contains("env.method"), "{e}");
                    out.push((class, method, None));
                    continue;
                }
            };
            assert!(!REFUSED.contains(&(method, class)), "{method} {class}");
            let frame = |fault| {
                let s =
                    frame_scene_seeded(&base, Motion::Environment, K, N, &CacheDir::None, fault);
                image(&s.unwrap())
            };
            let (f, faulty) = (frame(TurnFault::None), frame(TurnFault::NothingTurns));
            let t = image(&resolve(&text(&probe, material, env, degrees)).unwrap());
            out.push((
                class,
                method,
                Some(Turned {
                    same: f.pixels == t.pixels,
                    diff: relative_max(&f, &t),
                    fault_same: faulty.pixels == t.pixels,
                    fault_diff: relative_max(&faulty, &t),
                    unturned: relative_max(&image(&base), &t),
                }),
            ));
        }
    }
    out
}

/// Every method and class: the frame has the bits of the static render; the seeded fault
/// "nothing turns" fails every case (its frame is as far from the static render as the
/// unturned scene, over a quarter of the peak here).
#[test]
fn a_turntable_env_frame_is_the_static_render_at_its_rotation_for_every_method() {
    for (class, method, r) in cases() {
        let Some(r) = r else {
            eprintln!("{class:>9} {method:>9}: refused (not a method of this material)");
            continue;
        };
        eprintln!(
            "{class:>9} {method:>9}: frame {K}/{N} vs rotation {}: same bits {}, max diff \
             {:.2e} of peak; nothing turns (seeded): same bits {}, max diff {:.2e}",
            360 * K / N,
            r.same,
            r.diff,
            r.fault_same,
            r.fault_diff
        );
        assert!(
            r.same,
            "{class} {method}: frame {K} of {N} is not the static render"
        );
        // The case can fail: turning changes the image, and the fault is caught.
        assert!(
            r.unturned > 1e-3,
            "{class} {method}: turning changes nothing"
        );
        assert!(
            !r.fault_same && r.fault_diff > 1e-3,
            "{class} {method}: the seeded fault passed"
        );
    }
}

/// The command line: frame 2 of a 4-frame `--turntable-env` against `render` of the scene
/// at `rotation = 180`, under `auto` (light cuts for a D-BRDF and the transfer table for
/// Lambert: the two methods whose frames once did not turn) and under `reflection`
/// (Blinn-Phong).
#[test]
fn the_command_line_frames_turn_as_the_scene_file_rotation_does() {
    let dir = tempfile::tempdir().unwrap();
    let probe = common::small_city_probe(dir.path());
    for (name, material, env) in [
        ("cuts", CLASSES[3].1, "cut_error = 0.02"),
        (
            "reflection",
            CLASSES[2].1,
            "method = \"reflection\"\nreflection_grid = 8\nreflection_slices = 3\nreflection_residual = 64",
        ),
        (
            "table",
            CLASSES[0].1,
            "transfer_azimuth = 32\ntransfer_polar = 17",
        ),
    ] {
        let scene =
            |rotation: f64| text(&probe, material, env, rotation);
        let turning = dir.path().join(format!("{name}.toml"));
        std::fs::write(&turning, scene(0.0)).unwrap();
        let fixed = dir.path().join(format!("{name}-180.toml"));
        std::fs::write(&fixed, scene(180.0)).unwrap();
        let out = dir.path().join(format!("{name}.png"));
        let r = common::brdfkit(dir.path()).run(&[
            "render",
            turning.to_str().unwrap(),
            "--turntable",
            "4",
            "--turntable-env",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(r.success(), "{}", r.stderr);
        let still = dir.path().join(format!("{name}-180.png"));
        let r = common::brdfkit(dir.path()).run(&[
            "render",
            fixed.to_str().unwrap(),
            "-o",
            still.to_str().unwrap(),
        ]);
        assert!(r.success(), "{}", r.stderr);
        let pixels = |p: &Path| image::open(p).unwrap().to_rgb8().into_raw();
        let frame = |k: usize| pixels(&dir.path().join(format!("{name}_000{k}.png")));
        assert_eq!(
            frame(2),
            pixels(&still),
            "{name}: frame 2 of 4 is not rotation 180"
        );
        assert_ne!(frame(2), frame(0), "{name}: nothing turned");
    }
}
