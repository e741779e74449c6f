//! The frame pipeline: scene in, image out. Stages in order: vertices to clip space,
//! rasterization (`raster`: clip, set-up, binning, per-tile visibility), deferred shading
//! (`shade`) or a debug output (`aov`).
//!
//! One entry point, [`render`], takes the settings in one struct ([`RenderOptions`]) and
//! returns the image with, when asked, the work done ([`Rendered`]); [`render_into`] is the
//! same into a [`FrameContext`] the caller keeps, whose buffers the next frame reuses.
//!
//! # Layout
//!
//! - `mod.rs`: the pipeline ([`clip_positions`], [`rasterize`], [`tile_count`], [`render`],
//!   [`render_into`]).
//! - `frame.rs`: the buffers kept across frames ([`FrameContext`]).
//! - `options.rs`: the settings ([`RenderOptions`]).
//! - `stats.rs`: the work done ([`RenderStats`]).

mod frame;
mod options;
mod stats;

pub use frame::{FrameContext, RenderedFrame};
pub use options::RenderOptions;
pub use stats::RenderStats;

use crate::aov::{self, Aov};
use crate::image_io::Image;
use crate::raster::{self, RasterConfig, RasterScratch, VisBuffer};
use crate::scene::Scene;
use crate::shade;
use crate::shard::{RowBands, Shard};
use frame::FrameBuffers;
use glam::Vec4;

/// Clip-space positions of the scene's mesh vertices (`clip_from_world` applied).
pub fn clip_positions(scene: &Scene) -> Vec<Vec4> {
    let mut clip = Vec::new();
    clip_positions_into(scene, &mut clip);
    clip
}

/// [`clip_positions`] into `clip` (its previous contents replaced, its memory kept).
fn clip_positions_into(scene: &Scene, clip: &mut Vec<Vec4>) {
    let r = &scene.render;
    let aspect = r.width as f32 / r.height as f32;
    let clip_from_world = scene.camera.clip_from_view(aspect) * scene.camera.view_from_world();
    clip.clear();
    clip.extend(
        scene
            .mesh
            .positions
            .iter()
            .map(|p| clip_from_world * p.extend(1.0)),
    );
}

/// Rasterizes the scene into a visibility buffer.
pub fn rasterize(scene: &Scene, count_coverage: bool) -> VisBuffer {
    let mut vis = VisBuffer::default();
    rasterize_into(
        scene,
        count_coverage,
        &mut Vec::new(),
        &mut RasterScratch::default(),
        &mut vis,
        None,
    );
    vis
}

/// [`rasterize`] into `vis`, with `clip` (the clip-space positions) and `scratch` reused
/// ([`raster::rasterize_into`]): the same bits whatever they held (unless a test seeds
/// `fault`).
fn rasterize_into(
    scene: &Scene,
    count_coverage: bool,
    clip: &mut Vec<Vec4>,
    scratch: &mut RasterScratch,
    vis: &mut VisBuffer,
    fault: Option<raster::RasterFault>,
) {
    let r = &scene.render;
    let cfg = RasterConfig {
        width: r.width,
        height: r.height,
        tile_size: r.tile_size,
        cull: r.cull,
        near: scene.camera.near,
        count_coverage,
        kernel: r.kernel,
    };
    clip_positions_into(scene, clip);
    raster::rasterize_into_with_fault(clip, &scene.mesh.triangles, &cfg, scratch, vis, fault);
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
///
/// [`render_into`] with a new [`FrameContext`]; a caller rendering frame after frame keeps
/// one and calls that instead.
pub fn render(scene: &Scene, opts: &RenderOptions) -> Rendered {
    let mut ctx = FrameContext::default();
    let stats = render_into(scene, opts, &mut ctx).stats;
    Rendered {
        image: ctx.take_image(),
        stats,
    }
}

/// [`render`] into `ctx`: the frame's buffers (clip positions, visibility buffer, raster
/// scratch, the shading workers' buffers, the image) and the thread pool of
/// `opts.threads` are `ctx`'s, reused from its previous frame when the size (and thread
/// count) is the same, so a steady state of frames allocates and first-touches none of
/// them. The image is the bits [`render`] returns, whatever `ctx` rendered before (another
/// scene, size, AOV or shard); it stays in `ctx` ([`FrameContext::image`]) until the next
/// frame.
pub fn render_into<'c>(
    scene: &Scene,
    opts: &RenderOptions,
    ctx: &'c mut FrameContext,
) -> RenderedFrame<'c> {
    let stats = match opts.threads {
        None => render_here(scene, opts, &mut ctx.buffers),
        Some(threads) => {
            let (buffers, pool) = ctx.buffers_and_pool(threads);
            pool.install(|| render_here(scene, opts, buffers))
        }
    };
    RenderedFrame {
        image: &ctx.buffers.image,
        stats: opts.stats.then_some(stats),
    }
}

/// [`render_into`] on the current rayon pool; returns the work done.
fn render_here(scene: &Scene, opts: &RenderOptions, ctx: &mut FrameBuffers) -> RenderStats {
    let FrameBuffers {
        clip,
        raster,
        vis,
        shading,
        image,
        fault,
    } = ctx;
    rasterize_into(
        scene,
        opts.aov.is_some_and(Aov::needs_coverage),
        clip,
        raster,
        vis,
        *fault,
    );
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
    match opts.aov {
        None => {
            let report = shade::shade_into(scene, vis, &opts.shading, image, shading);
            stats.shade = report.counts;
            stats.lights = report.lights;
            stats.lights_dropped = report.lights_dropped;
            stats.dropped_fraction = report.dropped_fraction;
            (stats.sh_bands_stored, stats.sh_bands_used) = report.sh_bands;
        }
        Some(a) => {
            let (img, n) = aov::compute_counted(scene, vis, a);
            stats.aov_pixels = n;
            *image = img;
        }
    }
    stats
}
