//! The frame pipeline: scene in, image out. Stages in order: vertices to clip space,
//! rasterization (`raster`: clip, set-up, binning, per-tile visibility), deferred shading
//! (`shade`) or a debug output (`aov`).

use crate::aov::{self, Aov};
use crate::image_io::Image;
use crate::raster::{self, RasterConfig, VisBuffer};
use crate::scene::{Precision, Scene};
use glam::Vec4;

/// Clip-space positions of the scene's mesh vertices (`clip_from_world` applied).
pub fn clip_positions(scene: &Scene) -> Vec<Vec4> {
    let r = &scene.render;
    let aspect = r.width as f32 / r.height as f32;
    let clip_from_world = scene.camera.clip_from_view(aspect) * scene.camera.view_from_world();
    scene
        .mesh
        .positions
        .iter()
        .map(|p| clip_from_world * p.extend(1.0))
        .collect()
}

/// Rasterizes the scene into a visibility buffer.
pub fn rasterize(scene: &Scene, count_coverage: bool) -> VisBuffer {
    let r = &scene.render;
    let cfg = RasterConfig {
        width: r.width,
        height: r.height,
        tile_size: r.tile_size,
        cull: r.cull,
        near: scene.camera.near,
        count_coverage,
    };
    raster::rasterize(&clip_positions(scene), &scene.mesh.triangles, &cfg)
}

/// Renders the beauty image (linear radiance) or, with `aov`, that debug output. The beauty
/// image follows the scene's `render.precision`: [`crate::shade::shade`] (f32 kernels) or
/// [`crate::shade::shade_reference_f64`] (f64, every light).
pub fn render(scene: &Scene, aov: Option<Aov>) -> Image {
    let vis = rasterize(scene, aov.is_some_and(Aov::needs_coverage));
    match (aov, scene.render.precision) {
        (None, Precision::F32) => crate::shade::shade(scene, &vis),
        (None, Precision::F64) => crate::shade::shade_reference_f64(scene, &vis),
        (Some(a), _) => aov::compute(scene, &vis, a),
    }
}

/// The reference render (`--reference`): [`crate::shade::shade_reference_f64`]; the scene
/// should carry the full probe as its environment light set (the CLI sets that up).
pub fn render_reference(scene: &Scene) -> Image {
    let vis = rasterize(scene, false);
    crate::shade::shade_reference_f64(scene, &vis)
}

/// [`render`] on a dedicated pool of `threads` worker threads (0: one per core).
pub fn render_with_threads(scene: &Scene, aov: Option<Aov>, threads: usize) -> Image {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| render(scene, aov))
}
