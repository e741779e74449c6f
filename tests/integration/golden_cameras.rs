//! Every golden scene states its camera (`[camera]`), so a GPU build draws the same frame
//! without re-implementing auto-framing; the stated camera is exactly the one
//! auto-framing gives (same bits), so the stored images stay valid.

use brdfkit::scene::{Scene, SceneFile};
use std::path::{Path, PathBuf};

fn golden_scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let manifest = brdfkit::golden::load_manifest(&dir).unwrap();
    let mut scenes: Vec<PathBuf> = manifest
        .entries
        .iter()
        .map(|e| dir.join(&e.scene))
        .collect();
    scenes.sort();
    scenes.dedup();
    scenes
}

/// The scene resolved without its environment (the camera does not depend on it).
fn resolve(file: &mut SceneFile, dir: &Path) -> Scene {
    file.env = None;
    Scene::resolve(file, dir).unwrap()
}

fn camera_bits(s: &Scene) -> Vec<u32> {
    let c = &s.camera;
    [c.position, c.target, c.up]
        .iter()
        .flat_map(|v| v.to_array())
        .chain([c.fov_y_deg, c.near])
        .map(f32::to_bits)
        .collect()
}

#[test]
fn every_golden_scene_states_the_auto_framed_camera() {
    let scenes = golden_scenes();
    assert!(scenes.len() >= 20, "{} scenes", scenes.len());
    for path in scenes {
        let dir = path.parent().unwrap();
        let mut file = SceneFile::load(&path).unwrap();
        let spec = file.camera.clone();
        let spec = spec.unwrap_or_else(|| panic!("{}: no [camera]", path.display()));
        for (field, given) in [
            ("position", spec.position.is_some()),
            ("target", spec.target.is_some()),
            ("up", spec.up.is_some()),
            ("fov_y_deg", spec.fov_y_deg.is_some()),
            ("near", spec.near.is_some()),
        ] {
            assert!(given, "{}: camera.{field} not stated", path.display());
        }
        let stated = resolve(&mut file, dir);
        file.camera = None;
        let auto = resolve(&mut file, dir);
        assert_eq!(
            camera_bits(&stated),
            camera_bits(&auto),
            "{}: the stated camera is not auto-framing's ({:?} vs {:?})",
            path.display(),
            stated.camera,
            auto.camera
        );
    }
}

#[test]
fn a_camera_printed_with_six_digits_fails_the_comparison() {
    // Seeded fault: values written with `{:.6e}` (7 significant digits, not round-trip)
    // instead of the shortest round-trip form; the bit comparison above must see it.
    let path = golden_scenes()
        .into_iter()
        .find(|p| p.ends_with("default-160x120.toml"))
        .unwrap();
    let dir = path.parent().unwrap();
    let mut file = SceneFile::load(&path).unwrap();
    let stated = resolve(&mut file, dir);
    let six = |v: [f32; 3]| v.map(|x| format!("{x:.6e}").parse::<f32>().unwrap());
    let mut cam = file.camera.clone().unwrap();
    cam.position = cam.position.map(six);
    cam.near = cam.near.map(|x| format!("{x:.6e}").parse().unwrap());
    file.camera = Some(cam);
    let rounded = resolve(&mut file, dir);
    assert_ne!(camera_bits(&stated), camera_bits(&rounded));
}
