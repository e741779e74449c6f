//! The frame pipeline: scene in, image out. Stages in order: vertices to clip space,
//! rasterization (`raster`: clip, set-up, binning, per-tile visibility), deferred shading
//! (`shade`) or a debug output (`aov`).
//!
//! One entry point, [`render`], takes the settings in one struct ([`RenderOptions`]) and
//! returns the image with, when asked, the work done ([`Rendered`]).
//!
//! # Layout
//!
//! - `mod.rs`: the pipeline ([`clip_positions`], [`rasterize`], [`tile_count`], [`render`]).
//! - `options.rs`: the settings ([`RenderOptions`]).
//! - `stats.rs`: the work done ([`RenderStats`]).

mod options;
mod stats;

pub use options::RenderOptions;
pub use stats::RenderStats;

use crate::aov::{self, Aov};
use crate::image_io::Image;
use crate::raster::{self, RasterConfig, VisBuffer};
use crate::scene::Scene;
use crate::shade;
use crate::shard::{RowBands, Shard};
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
    let mut vis = raster::rasterize(&clip_positions(scene), &scene.mesh.triangles, &cfg);
    let view_from_world = scene.camera.view_from_world().as_dmat4();
    let ty = (0.5 * scene.camera.fov_y_deg as f64).to_radians().tan();
    vis.rays = Some(raster::PixelRays {
        eye: scene.camera.position.as_dvec3(),
        // The inverse of a rotation is its transpose.
        world_from_view: glam::DMat3::from_mat4(view_from_world).transpose(),
        tan_half: (ty * r.width as f64 / r.height as f64, ty),
        width: r.width,
        height: r.height,
    });
    vis
}

/// Tiles of the frame `scene` renders to (its `render.width` x `render.height` in tiles of
/// `render.tile_size`): the length of a progress bar over [`render`]'s tiles
/// ([`crate::shade::ShadeOptions::progress`]).
pub fn tile_count(scene: &Scene) -> u64 {
    let r = &scene.render;
    r.width.div_ceil(r.tile_size) as u64 * r.height.div_ceil(r.tile_size) as u64
}

/// Image rows per band of a sharded still image ([`RowBands`], [`RenderOptions::rows`]) at
/// tile size `tile_size` (the scene's `render.tile_size`): the least common multiple of it and the light cuts' square
/// ([`shade::CUT_TILE`]), so a band holds whole tiles and whole cut squares, and a shard
/// shades exactly what the unsharded render shades there.
pub fn shard_rows(tile_size: u32) -> u32 {
    let (a, b) = (tile_size, shade::CUT_TILE);
    let gcd = |mut a: u32, mut b: u32| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    a / gcd(a, b) * b
}

/// The bands of shard `shard` of an image rendered at tile size `tile_size` ([`shard_rows`]).
pub fn row_bands(tile_size: u32, shard: Shard) -> RowBands {
    RowBands {
        shard,
        rows: shard_rows(tile_size),
    }
}

/// Tiles a render with [`RenderOptions::rows`] `rows` shades or skips: [`tile_count`]'s,
/// less the rows of tiles left to other shards (the length of that render's progress bar).
pub fn tile_count_in(scene: &Scene, rows: Option<RowBands>) -> u64 {
    let r = &scene.render;
    let tiles_x = r.width.div_ceil(r.tile_size) as u64;
    match rows {
        None => tile_count(scene),
        Some(b) => {
            let kept = (0..r.height.div_ceil(r.tile_size))
                .filter(|&ty| b.owns(ty * r.tile_size))
                .count() as u64;
            kept * tiles_x
        }
    }
}

/// A rendered image and, when [`RenderOptions::stats`] asked for it, the work done.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The beauty image (linear radiance) or the AOV asked for.
    pub image: Image,
    /// The work done ([`RenderStats`]); `None` unless [`RenderOptions::stats`].
    pub stats: Option<RenderStats>,
}

/// Renders `scene` as `opts` says: the beauty image (linear radiance) on the shading path
/// chosen ([`crate::shade::shade`]: the scene's `render.precision` unless
/// `opts.shading.path` overrides it) or, with `opts.aov`, that debug output. A beauty render
/// computes no AOV and counts no coverage; an AOV render shades nothing. With
/// `opts.threads`, on a dedicated pool of that many threads; the image is the same for any
/// thread count. With `opts.rows`, only that shard's rows (the others black; an AOV is
/// computed whole, it is cheap).
pub fn render(scene: &Scene, opts: &RenderOptions) -> Rendered {
    match opts.threads {
        None => render_here(scene, opts),
        Some(threads) => rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| render_here(scene, opts)),
    }
}

/// [`render`] on the current rayon pool.
fn render_here(scene: &Scene, opts: &RenderOptions) -> Rendered {
    let mut vis = rasterize(scene, opts.aov.is_some_and(Aov::needs_coverage));
    if let Some(b) = opts.rows {
        assert_eq!(b.rows % vis.tile_size, 0, "shard bands of whole tiles");
        for ty in 0..vis.tiles_y {
            if !b.owns(ty * vis.tile_size) {
                vis.leave_tile_row(ty);
            }
        }
    }
    let mut stats = RenderStats {
        tiles: vis.tile_occupied.len() as u64,
        coverage_counted: vis.coverage.is_some(),
        ..RenderStats::default()
    };
    let image = match opts.aov {
        None => {
            let shaded = shade::shade(scene, &vis, &opts.shading);
            stats.shade = shaded.counts;
            stats.lights = shaded.lights;
            stats.lights_dropped = shaded.lights_dropped;
            stats.dropped_fraction = shaded.dropped_fraction;
            (stats.sh_bands_stored, stats.sh_bands_used) = shaded.sh_bands;
            shaded.image
        }
        Some(a) => {
            let (img, n) = aov::compute_counted(scene, &vis, a);
            stats.aov_pixels = n;
            img
        }
    };
    Rendered {
        image,
        stats: opts.stats.then_some(stats),
    }
}
