//! The frame pipeline: scene in, image out. Stages in order: vertices to clip space,
//! rasterization (`raster`: clip, set-up, binning, per-tile visibility), deferred shading
//! (`shade`) or a debug output (`aov`).

use crate::aov::{self, Aov};
use crate::image_io::Image;
use crate::raster::{self, RasterConfig, VisBuffer};
use crate::scene::{Precision, Scene};
use crate::shade::{shade_with_counts, FramePrep, ShadeCounts};
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
    render_with_stats(scene, aov).0
}

/// The work one render did, to show what was skipped (`brdfkit render --stats`). Counts are
/// gathered per tile (or per row for AOVs) and summed after, so they do not depend on the
/// thread count; the tile counts do depend on the tile size.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Tiles of the frame.
    pub tiles: u64,
    /// Shading work (all zero for an AOV render).
    pub shade: ShadeCounts,
    /// Directional lights in the scene, and how many were dropped as negligible.
    pub lights: usize,
    pub lights_dropped: usize,
    /// Dropped irradiance over total irradiance, largest over the channels (0 if none).
    pub dropped_fraction: f32,
    /// SH bands stored in the material's data set and bands shaded (0, 0 if not SH).
    pub sh_bands_stored: usize,
    pub sh_bands_used: usize,
    /// Pixels whose AOV value was computed (0 for a beauty render).
    pub aov_pixels: u64,
    /// Whether the rasterizer counted per-pixel coverage (only the `coverage` AOV needs it).
    pub coverage_counted: bool,
}

impl std::fmt::Display for RenderStats {
    /// One `name: value` line per counter.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = &self.shade;
        writeln!(f, "tiles: {}", self.tiles)?;
        writeln!(f, "tiles shaded: {}", s.tiles_shaded)?;
        writeln!(f, "tiles skipped (empty): {}", s.tiles_skipped)?;
        writeln!(f, "pixels shaded: {}", s.pixels_shaded)?;
        writeln!(f, "pixel x light pairs: {}", s.light_pairs)?;
        writeln!(
            f,
            "lights: {} ({} dropped, {:.3e} of the irradiance)",
            self.lights, self.lights_dropped, self.dropped_fraction
        )?;
        writeln!(
            f,
            "sh bands: {} of {}",
            self.sh_bands_used, self.sh_bands_stored
        )?;
        writeln!(f, "aov pixels: {}", self.aov_pixels)?;
        write!(f, "coverage counted: {}", self.coverage_counted)
    }
}

/// [`render`], also returning the work done ([`RenderStats`]). A beauty render computes no
/// AOV and counts no coverage; an AOV render shades nothing.
pub fn render_with_stats(scene: &Scene, aov: Option<Aov>) -> (Image, RenderStats) {
    let vis = rasterize(scene, aov.is_some_and(Aov::needs_coverage));
    let mut stats = RenderStats {
        tiles: vis.tile_occupied.len() as u64,
        coverage_counted: vis.coverage.is_some(),
        ..RenderStats::default()
    };
    let img = match aov {
        None if scene.render.precision == Precision::F64 => {
            // The f64 path shades every light with no skip and no culling.
            stats.lights = scene.lights.len();
            crate::shade::shade_reference_f64(scene, &vis)
        }
        None => {
            let prep = FramePrep::new(scene);
            let (img, counts) = shade_with_counts(&prep, scene, &vis);
            stats.shade = counts;
            stats.lights = prep.lights_total;
            stats.lights_dropped = prep.dropped.dropped;
            let d = &prep.dropped;
            stats.dropped_fraction = (0..3)
                .filter(|&c| d.total_irradiance[c] > 0.0)
                .map(|c| d.dropped_irradiance[c] / d.total_irradiance[c])
                .fold(0.0, f32::max);
            (stats.sh_bands_stored, stats.sh_bands_used) = prep.sh_bands;
            img
        }
        Some(a) => {
            let (img, n) = aov::compute_counted(scene, &vis, a);
            stats.aov_pixels = n;
            img
        }
    };
    (img, stats)
}

/// The reference render (`--reference`): [`crate::shade::shade_reference_f64`]; the scene
/// should carry the full probe as its environment light set (the CLI sets that up).
pub fn render_reference(scene: &Scene) -> Image {
    let vis = rasterize(scene, false);
    crate::shade::shade_reference_f64(scene, &vis)
}

/// [`render`] on a dedicated pool of `threads` worker threads (0: one per core).
pub fn render_with_threads(scene: &Scene, aov: Option<Aov>, threads: usize) -> Image {
    render_with_threads_stats(scene, aov, threads).0
}

/// [`render_with_stats`] on a dedicated pool of `threads` worker threads (0: one per core).
pub fn render_with_threads_stats(
    scene: &Scene,
    aov: Option<Aov>,
    threads: usize,
) -> (Image, RenderStats) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| render_with_stats(scene, aov))
}
