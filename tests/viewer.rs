//! `brdfkit view` driven as a person would, under Xvfb: a script orbits the camera, changes
//! the material and the probe; the screenshot it writes at the end must equal, pixel for
//! pixel, `brdfkit render` of the scene file it writes beside it (an independent process
//! rendering headless), and that scene file must hold the changes the script made. Where
//! Xvfb is not installed a test says it did not run; under `CI=true` it fails instead
//! ([`common::cannot_run`]).
//!
//! Also: without a display, `view` fails with one line and a non-zero exit, no panic.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_brdfkit");

/// A running Xvfb server, killed on drop. One at a time in this process: the tests run on
/// threads, and two of them starting a server on the same free display number at once
/// would both see its socket appear and share one server, which the first to finish kills.
struct Xvfb {
    child: Child,
    display: String,
    _one_at_a_time: std::sync::MutexGuard<'static, ()>,
}

static ONE_SERVER: std::sync::Mutex<()> = std::sync::Mutex::new(());

impl Drop for Xvfb {
    /// SIGTERM, so the server removes its socket and lock file (SIGKILL would leave them,
    /// and later runs would skip that display number).
    fn drop(&mut self) {
        // SAFETY: signals the child this struct started and still owns (not yet waited for).
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        let _ = self.child.wait();
    }
}

/// The Xvfb executable on PATH, if any.
fn xvfb_path() -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|d| d.join("Xvfb"))
            .find(|p| p.is_file())
    })
}

/// Starts Xvfb on the first display number in 90..400 whose socket and lock are free.
fn start_xvfb(exe: &Path) -> Xvfb {
    let guard = ONE_SERVER.lock().unwrap_or_else(|e| e.into_inner());
    for n in 90..400 {
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        let lock = PathBuf::from(format!("/tmp/.X{n}-lock"));
        if socket.exists() || lock.exists() {
            continue;
        }
        let mut child = Command::new(exe)
            .args([
                &format!(":{n}"),
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb");
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(10) {
            if socket.exists() {
                return Xvfb {
                    child,
                    display: format!(":{n}"),
                    _one_at_a_time: guard,
                };
            }
            if let Ok(Some(_)) = child.try_wait() {
                break; // lost a race for this display; try the next
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = child.kill();
        let _ = child.wait();
    }
    panic!("no free X display for Xvfb in :90..:400");
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// `brdfkit render SCENE -o OUT` with the test's own light-set cache; OUT's pixels.
fn render(scene: &Path, out: &Path, cache: &Path) -> image::RgbImage {
    let o = Command::new(BIN)
        .args([
            "render".as_ref(),
            scene.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ])
        .env("BRDFKIT_CACHE_DIR", cache)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    rgb(out)
}

#[test]
fn scripted_orbit_material_and_probe_change_give_the_pixels_render_gives() {
    let Some(exe) = xvfb_path() else {
        common::cannot_run(
            "tests/viewer.rs: the viewer test",
            "Xvfb is not installed (Debian package xvfb)",
        );
        return;
    };
    let x = start_xvfb(&exe);
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let script = tmp.path().join("script.txt");
    // Orbit right and up, next material (after blue-silk: lindt-paper), next probe (after
    // sky: city), orbit back a little, zoom in one notch.
    std::fs::write(
        &script,
        "0 drag 60 20\n50 key m\n100 key p\n150 drag -25 0\n200 wheel 1\n",
    )
    .unwrap();
    let shot = tmp.path().join("shot.png");
    let scene = tmp.path().join("shot.toml");
    let repo = env!("CARGO_MANIFEST_DIR");
    let o = Command::new(BIN)
        .current_dir(repo)
        .args(["view", "--width", "160", "--height", "120"])
        .args(["--env", "assets/probes/sky.exr", "--sampler", "median-cut"])
        .args(["--lights", "32", "--material", "blue-silk"])
        .args(["--script".as_ref(), script.as_os_str()])
        .args(["--screenshot".as_ref(), shot.as_os_str()])
        .args(["--write-scene".as_ref(), scene.as_os_str()])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("BRDFKIT_CACHE_DIR", &cache)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "view failed: {err}");
    assert!(!err.contains("warning"), "{err}");

    // The scene file holds what the script did.
    let text = std::fs::read_to_string(&scene).unwrap();
    let file = brdfkit::scene::SceneFile::parse(&text).unwrap();
    match &file.material {
        brdfkit::scene::MaterialSpec::Library { name, .. } => assert_eq!(name, "lindt-paper"),
        m => panic!("material {m:?}"),
    }
    let env = file.env.as_ref().expect("an [env]");
    assert!(env.file.ends_with("city.exr"), "{}", env.file.display());
    assert_eq!(
        (env.count, env.sampler),
        (32, brdfkit::env::schema::SamplerKind::MedianCut)
    );
    let cam = file.camera.as_ref().expect("the orbit placed the camera");
    let (p, t) = (cam.position.unwrap(), cam.target.unwrap());
    // Net drag: 35 px right (yaw -35/200 rad from the auto-framed view, which looks from
    // +x of the target: the camera's x offset shrinks) and 20 px down (pitch up).
    let auto_from = glam::Vec3::new(0.35, 0.45, 1.0).normalize();
    let rel = (glam::Vec3::from(p) - glam::Vec3::from(t)).normalize();
    let yaw = |v: glam::Vec3| v.x.atan2(v.z) as f64;
    let pitch = |v: glam::Vec3| v.y.asin() as f64;
    assert!(
        (yaw(auto_from) - yaw(rel) - 35.0 / 200.0).abs() < 1e-4,
        "{rel:?}"
    );
    assert!(
        (pitch(rel) - pitch(auto_from) - 20.0 / 200.0).abs() < 1e-4,
        "{rel:?}"
    );

    // The screenshot equals `render` of that file, pixel for pixel.
    let viewed = rgb(&shot);
    assert_eq!(viewed.dimensions(), (160, 120));
    let rendered = render(&scene, &tmp.path().join("render.png"), &cache);
    let differing = viewed
        .pixels()
        .zip(rendered.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differing, 0, "pixels differing from `brdfkit render`");
    // Not a blank frame: the object covers part of it, the probe lights it.
    let lit = viewed
        .pixels()
        .filter(|p| p.0.iter().any(|&c| c > 8))
        .count();
    assert!(lit > 1000 && lit < 160 * 120, "{lit} lit pixels");

    // Seeded fault: had the probe change not reached the frame (sky instead of city), the
    // comparison fails.
    let faulty = tmp.path().join("faulty.toml");
    std::fs::write(&faulty, text.replace("city.exr", "sky.exr")).unwrap();
    let wrong = render(&faulty, &tmp.path().join("faulty.png"), &cache);
    let differing = viewed
        .pixels()
        .zip(wrong.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differing > 100,
        "the wrong probe changed only {differing} pixels"
    );
}

#[test]
fn a_still_view_refines_to_the_frame_render_gives_for_its_last_step() {
    let Some(exe) = xvfb_path() else {
        common::cannot_run(
            "tests/viewer.rs: the refinement test",
            "Xvfb is not installed (Debian package xvfb)",
        );
        return;
    };
    let x = start_xvfb(&exe);
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let script = tmp.path().join("script.txt");
    std::fs::write(&script, "0 drag 20 0\n100 await-refined\n").unwrap();
    let (shot, scene) = (tmp.path().join("shot.png"), tmp.path().join("shot.toml"));
    let o = Command::new(BIN)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "view",
            "--width",
            "128",
            "--height",
            "96",
            "--refine-steps",
            "1",
        ])
        .args(["--env", "assets/probes/city.exr", "--sampler", "median-cut"])
        .args(["--lights", "32", "--material", "blue-silk"])
        .args(["--script".as_ref(), script.as_os_str()])
        .args(["--screenshot".as_ref(), shot.as_os_str()])
        .args(["--write-scene".as_ref(), scene.as_os_str()])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("BRDFKIT_CACHE_DIR", &cache)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "view failed: {err}");
    // The last step (refine.rs): 4x the lights, nothing dropped, every SH band.
    let text = std::fs::read_to_string(&scene).unwrap();
    let file = brdfkit::scene::SceneFile::parse(&text).unwrap();
    assert_eq!(file.env.as_ref().unwrap().count, 128);
    assert_eq!(file.render.drop_lights, 0.0);
    assert!(!file.render.band_skip);
    let viewed = rgb(&shot);
    let rendered = render(&scene, &tmp.path().join("render.png"), &cache);
    assert!(
        viewed == rendered,
        "the refined frame differs from `brdfkit render`"
    );
    // Seeded fault: the fast frame (the step-0 document) is a different image, so a viewer
    // that stopped refining would fail the comparison above.
    let fast = tmp.path().join("fast.toml");
    let fast_text = text
        .replace("count = 128", "count = 32")
        .replace("band_skip = false", "band_skip = true");
    assert_ne!(fast_text, text);
    std::fs::write(&fast, fast_text).unwrap();
    let unrefined = render(&fast, &tmp.path().join("fast.png"), &cache);
    assert!(viewed != unrefined, "refinement changed no pixel");
}

/// `brdfkit view` with no refinement step under `[env] method = "auto"`: the frame shown
/// is the one shown while the view moves; returns the scene file it wrote, its screenshot
/// and `brdfkit render` of that file (the same cache).
fn moving_frame(args: &[&str]) -> (brdfkit::scene::SceneFile, image::RgbImage, image::RgbImage) {
    let x = start_xvfb(&xvfb_path().unwrap());
    let tmp = tempfile::tempdir().unwrap();
    let cache = tmp.path().join("cache");
    let script = tmp.path().join("script.txt");
    std::fs::write(&script, "0 drag 10 0\n").unwrap();
    let (shot, scene) = (tmp.path().join("shot.png"), tmp.path().join("shot.toml"));
    let o = Command::new(BIN)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "view",
            "--width",
            "64",
            "--height",
            "48",
            "--refine-steps",
            "0",
        ])
        .args(args)
        .args(["--script".as_ref(), script.as_os_str()])
        .args(["--screenshot".as_ref(), shot.as_os_str()])
        .args(["--write-scene".as_ref(), scene.as_os_str()])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("BRDFKIT_CACHE_DIR", &cache)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "view failed: {err}");
    let text = std::fs::read_to_string(&scene).unwrap();
    let file = brdfkit::scene::SceneFile::parse(&text).unwrap();
    let rendered = render(&scene, &tmp.path().join("render.png"), &cache);
    (file, rgb(&shot), rendered)
}

#[test]
fn under_method_auto_the_moving_frame_is_the_reflection_table_or_the_light_set() {
    if xvfb_path().is_none() {
        common::cannot_run(
            "tests/viewer.rs: the auto-method test",
            "Xvfb is not installed (Debian package xvfb)",
        );
        return;
    }
    use brdfkit::env::schema::EnvMethod;
    // The default material (Blinn-Phong): `auto` is light cuts when still; while the view
    // moves, the reflection table (a small one, so the bake takes a fraction of a second).
    let dir = tempfile::tempdir().unwrap();
    let doc = dir.path().join("bp.toml");
    let probe = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/probes/city.exr");
    std::fs::write(
        &doc,
        format!(
            "[env]\nfile = {:?}\nmethod = \"auto\"\nreflection_grid = 8\nreflection_slices = 3\nreflection_residual = 64\n",
            probe.to_str().unwrap()
        ),
    )
    .unwrap();
    let (file, shown, rendered) = moving_frame(&[doc.to_str().unwrap()]);
    assert_eq!(
        file.env.as_ref().unwrap().method,
        EnvMethod::Reflection,
        "the moving frame was not the reflection table"
    );
    assert!(
        shown == rendered,
        "the moving frame differs from `brdfkit render`"
    );
    // A D-BRDF: `auto` is light cuts (seconds per frame at window sizes) when still; while
    // the view moves, the document's delta light set.
    let (file, _, _) = moving_frame(&[
        "--env",
        "assets/probes/city.exr",
        "--material",
        "lindt-paper",
    ]);
    assert_eq!(
        file.env.as_ref().unwrap().method,
        EnvMethod::Lights,
        "the moving frame was not the delta light set"
    );
}

#[test]
fn without_a_display_view_fails_with_one_line() {
    let o = Command::new(BIN)
        .args(["view", "--width", "32", "--height", "24"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("no display") && !err.contains("panicked"),
        "{err}"
    );
}
