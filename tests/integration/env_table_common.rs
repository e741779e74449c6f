//! Shared by the scene tests of the tabulated `[env]` methods (`transfer_scene.rs`,
//! `reflection_scene.rs`): a small sphere under a shipped probe, and a table's image
//! measured against the converged reference (`RenderOptions::converged_reference()` on
//! `sampler = "full"`: f64, every texel a light) with its table and without it (its exact
//! lights alone), so each test can show both that the table is accurate and that its check
//! sees the table.

use brdfkit::image_io::Image;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Environment, Scene, SceneFile};
use std::path::Path;

/// A 24 x 24 image of the 128-segment sphere with `material` (a `[material]` body) under
/// `assets/probes/{probe}.exr`, `env_extra` added to its `[env]`.
pub fn scene(probe: &str, material: &str, env_extra: &str) -> brdfkit::error::Result<Scene> {
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 128\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\n{env_extra}\n\
         [render]\nwidth = 24\nheight = 24\n"
    );
    let file = SceneFile::parse(&text).unwrap();
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR")))
}

/// A table method's scene rendered and measured ([`against_reference`]).
pub struct TableRun {
    /// The scene of the table and its exact lights.
    pub scene: Scene,
    /// Its image, rendered as `brdfkit render` does.
    pub image: Image,
    /// Relative RMSE of `image` against the converged reference.
    pub error: f64,
    /// Relative RMSE of the exact lights alone (the table left out) against it.
    pub error_without_table: f64,
}

/// Renders `material` under `probe` with `table` (the method and its fields, an `[env]`
/// body), which must split off `exact_lights` texels as lights, and measures it and its
/// exact lights alone against the converged reference.
pub fn against_reference(
    probe: &str,
    material: &str,
    table: &str,
    exact_lights: usize,
) -> TableRun {
    let reference = render(
        &scene(probe, material, "sampler = \"full\"").unwrap(),
        &RenderOptions::converged_reference(),
    )
    .image;
    let s = scene(probe, material, table).unwrap();
    assert_eq!(
        s.delta_lights().len(),
        exact_lights,
        "{probe}: exact lights"
    );
    let image = render(&s, &RenderOptions::default()).image;
    let error = brdfkit::metrics::relative_rmse(&reference, &image, None);
    let mut lights_only = s.clone();
    lights_only.environment = Environment::Lights(s.environment.delta_lights().to_vec());
    let bare = render(&lights_only, &RenderOptions::default()).image;
    let error_without_table = brdfkit::metrics::relative_rmse(&reference, &bare, None);
    TableRun {
        scene: s,
        image,
        error,
        error_without_table,
    }
}
