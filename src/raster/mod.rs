//! Rasterization: clip-space triangles in, a visibility buffer out.
//!
//! (Past 400 lines because it is the stage that ties the others together: the visibility
//! buffer and scratch types, binning and the entry points with their fault hooks share one
//! determinism contract, stated here; clipping, setup and the tile walk are files of their
//! own.)
//!
//! Stages (each a submodule, in the order the data flows):
//! 1. [`clip`]: homogeneous clipping against the near plane and a guard band; triangles
//!    that cross the camera plane are cut, not dropped.
//! 2. [`setup`]: snapping to fixed point (each mesh vertex once) and integer edge
//!    functions with a top-left rule, in two parallel passes: the first keeps the
//!    triangles that can cover a pixel centre ([`setup::covered_bounds`]: area, facing,
//!    bounds; most triangles of a dense mesh stop there), as a list of small survivor
//!    records in source order; the second sets up each survivor straight into the
//!    visibility buffer's triangle list (written once, never copied).
//! 3. binning (here): each set-up triangle is listed in every tile its pixel bounds touch,
//!    in source order (one flat list, [`Bins`]); the tile rectangles (exact
//!    multiply-shift divisions by the tile size) and the tile walk's compact record of
//!    each triangle ([`tile::TileTriangle`], 80 bytes to the set-up triangle's 224) are
//!    made by set-up's second pass with the triangle (the set-up list is never read back),
//!    the counting and listing are two serial passes of adds.
//! 4. [`tile`]: tiles resolve visibility in parallel (rayon): per pixel the nearest triangle
//!    (largest 1/w; ties keep the earlier triangle) and, if asked, how many triangles cover
//!    it; a triangle is tested eight pixels of a row at a time in i32 lanes where its
//!    extent allows, a large one walked in blocks classified by their corners. A reused
//!    buffer is cleared tile by tile by the task that resolves the tile, just before it
//!    (one pass over the memory); a tile with an empty bin is only cleared.
//!
//! [`rasterize_into`] reuses a previous frame's [`VisBuffer`] and [`RasterScratch`], so a
//! caller drawing frame after frame at one size touches no new memory.
//!
//! Determinism contract: every per-pixel value depends only on the pixel, the triangles in
//! source order and exact integer coverage, never on the tile size, the thread count or the
//! order in which tiles finish. The output is bit-identical for any `--threads` and any
//! tile size.

pub mod clip;
pub mod setup;
pub mod tile;

use crate::lanes::{Dispatch, KernelPath};
use clip::ClipPlanes;
use glam::Vec4;
use rayon::prelude::*;
use setup::SetupTriangle;
#[doc(hidden)]
pub use tile::RasterFault;

/// Marks a pixel no triangle covers.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// Largest width or height of a raster target (pixels): with the guard band
/// ([`clip::GUARD_PIXELS`]) it bounds snapped coordinates by 2^29 in magnitude, so the tile
/// walk's record ([`tile::TileTriangle`]) holds them in `i32`.
pub const MAX_SIDE: u32 = 1 << 20;

/// Which faces to drop before rasterization.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Cull {
    /// Keep both sides; back faces are shaded with their normal flipped (two-sided).
    #[default]
    None,
    /// Drop triangles whose winding is clockwise on screen.
    Back,
}

/// What to rasterize into.
#[derive(Clone, Copy, Debug)]
pub struct RasterConfig {
    pub width: u32,
    pub height: u32,
    /// Tile edge in pixels (>= 1).
    pub tile_size: u32,
    pub cull: Cull,
    /// Near plane distance of the projection (view-space units, > 0).
    pub near: f32,
    /// Also count, per pixel, every triangle covering it (the `coverage` AOV and the
    /// watertightness tests). Off by default: it costs a write per fragment.
    pub count_coverage: bool,
    /// Instruction set of the tile walk's lanes ([`crate::lanes`]), as a frame's shading
    /// takes it from the scene's `render.kernel`. Every path gives the same bits (integer
    /// lanes; the depth is the same scalar f64 expression); a path this CPU does not run
    /// falls back to the portable one.
    pub kernel: KernelPath,
}

/// A rectangle of pixels: first pixel `(x0, y0)`, `w x h` pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    pub x0: u32,
    pub y0: u32,
    pub w: u32,
    pub h: u32,
}

impl PixelRect {
    /// Tile `t` (row-major, `tiles_x` to a row) of a `width x height` frame cut into tiles
    /// of `tile_size` pixels, clipped to the frame at its right and bottom edges: the one
    /// place a tile's bounds are computed (rasterizing, the G-buffer, the tile loops).
    #[inline]
    pub fn tile(t: usize, tile_size: u32, tiles_x: u32, width: u32, height: u32) -> PixelRect {
        let x0 = (t as u32 % tiles_x) * tile_size;
        let y0 = (t as u32 / tiles_x) * tile_size;
        PixelRect {
            x0,
            y0,
            w: tile_size.min(width - x0),
            h: tile_size.min(height - y0),
        }
    }
}

/// The result of rasterization, stored tile-major: tile `t` owns entries
/// `t * tile_size^2 .. (t + 1) * tile_size^2`, row-major inside the tile.
/// `VisBuffer::default()` is an empty buffer for [`rasterize_into`] to fill.
#[derive(Clone, Debug, Default)]
pub struct VisBuffer {
    pub width: u32,
    pub height: u32,
    pub tile_size: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// Index into `triangles` of the visible triangle, or [`NO_TRIANGLE`].
    pub visible: Vec<u32>,
    /// 1/w of the visible surface (0 where empty).
    pub depth: Vec<f32>,
    /// Number of covering triangles per pixel, when counted.
    pub coverage: Option<Vec<u32>>,
    /// Whether each tile received any triangle (false for every tile of a row left to
    /// another shard: [`VisBuffer::leave_tile_row`]).
    pub tile_occupied: Vec<bool>,
    /// Per row of tiles: whether it is left to another shard of a sharded still image
    /// ([`VisBuffer::leave_tile_row`]); all false from [`rasterize`].
    pub tile_row_left: Vec<bool>,
    /// The set-up triangles that `visible` indexes.
    pub triangles: Vec<SetupTriangle>,
    /// The camera ray through each pixel centre, when the caller knows the camera
    /// ([`crate::render::rasterize`] sets it): the G-buffer intersects it with a mesh's
    /// exact sphere ([`crate::mesh::Mesh::exact_sphere`]).
    pub rays: Option<PixelRays>,
}

/// The pinhole camera's rays through pixel centres, in f64 world space: pixel `(x, y)`'s ray
/// is `eye + t dir(x, y)` with `dir` the view-space vector `(ndc_x tan_x, ndc_y tan_y, -1)`
/// turned into world space, `ndc_x = 2 (x + 1/2) / width - 1`, `ndc_y = 1 - 2 (y + 1/2) /
/// height` (the rasterizer's viewport mapping, `setup.rs`), so `t` is the distance along the
/// view axis (the clip w).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelRays {
    pub eye: glam::DVec3,
    /// Columns: the camera's right, up and backward (view +x, +y, +z) world axes.
    pub world_from_view: glam::DMat3,
    /// `tan(fov_y / 2) * width / height` and `tan(fov_y / 2)`.
    pub tan_half: (f64, f64),
    pub width: u32,
    pub height: u32,
}

impl PixelRays {
    /// World direction (not unit; view-space z = -1) of the ray through pixel `(x, y)`.
    #[inline]
    pub fn dir(&self, x: u32, y: u32) -> glam::DVec3 {
        let ndc_x = 2.0 * (x as f64 + 0.5) / self.width as f64 - 1.0;
        let ndc_y = 1.0 - 2.0 * (y as f64 + 0.5) / self.height as f64;
        self.world_from_view
            * glam::DVec3::new(ndc_x * self.tan_half.0, ndc_y * self.tan_half.1, -1.0)
    }
}

impl VisBuffer {
    /// Leaves row of tiles `ty` to another shard (`render --shard`): its tiles count as
    /// empty for every pass (nothing is shaded there; its pixels stay black) and the tile
    /// loop neither visits nor counts them, so a progress bar counts this shard's tiles only.
    pub fn leave_tile_row(&mut self, ty: u32) {
        let (start, end) = (
            (ty * self.tiles_x) as usize,
            ((ty + 1) * self.tiles_x) as usize,
        );
        self.tile_occupied[start..end].fill(false);
        self.tile_row_left[ty as usize] = true;
    }

    /// Index of pixel `(x, y)` in the tile-major arrays.
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> usize {
        let ts = self.tile_size;
        let tile = (y / ts) * self.tiles_x + x / ts;
        (tile * ts * ts + (y % ts) * ts + x % ts) as usize
    }

    /// The pixels of tile `t` ([`PixelRect::tile`]).
    #[inline]
    pub fn tile_rect(&self, t: usize) -> PixelRect {
        PixelRect::tile(t, self.tile_size, self.tiles_x, self.width, self.height)
    }

    /// Pixel `(x, y)` of tile-major index `i`, or `None` for the padding of edge tiles.
    #[inline]
    pub fn pixel(&self, i: usize) -> Option<(u32, u32)> {
        let ts = self.tile_size as usize;
        let rect = self.tile_rect(i / (ts * ts));
        let r = i % (ts * ts);
        let (lx, ly) = ((r % ts) as u32, (r / ts) as u32);
        (lx < rect.w && ly < rect.h).then_some((rect.x0 + lx, rect.y0 + ly))
    }

    /// The coverage count as a row-major image (all zero if it was not counted).
    pub fn coverage_row_major(&self) -> Vec<u32> {
        let mut out = vec![0; (self.width * self.height) as usize];
        if let Some(c) = &self.coverage {
            for y in 0..self.height {
                for x in 0..self.width {
                    out[(y * self.width + x) as usize] = c[self.index(x, y)];
                }
            }
        }
        out
    }
}

/// A mesh vertex as set-up reads it: its clip-plane outcode and, when it is inside every
/// plane, its snapped fixed-point position ([`setup::snap`]) and clip w.
#[derive(Clone, Copy, Debug)]
struct SnappedVertex {
    x: i64,
    y: i64,
    w: f32,
    code: u32,
}

/// Triangles per set-up task (and vertices per snapping task, times two).
const SETUP_CHUNK: usize = 2048;

/// What the rasterizer keeps between frames besides the [`VisBuffer`]: the snapped
/// vertices, the set-up tasks' triangles and the bins. Passed again to
/// [`rasterize_into`] with the same buffer, a frame of the same size and a similar mesh
/// allocates (and first-touches) no memory.
#[derive(Debug, Default)]
pub struct RasterScratch {
    verts: Vec<SnappedVertex>,
    /// Set-up's first pass, per chunk of source triangles: the survivors.
    chunks: Vec<Vec<[u32; 2]>>,
    /// All chunks' survivors in source order.
    survivors: Vec<[u32; 2]>,
    bins: Bins,
}

/// Per tile, the indices of the set-up triangles whose pixel bounds touch it, in
/// increasing order: tile `t`'s are `items[offsets[t]..offsets[t + 1]]`.
#[derive(Debug, Default)]
pub struct Bins {
    offsets: Vec<u32>,
    items: Vec<u32>,
    /// Per triangle, its first and last tile column and row (binning's scratch).
    rects: Vec<[u32; 4]>,
    /// Per triangle, the tile walk's compact record of it.
    walk: Vec<tile::TileTriangle>,
}

impl Bins {
    /// The triangles of tile `t`.
    #[inline]
    pub fn tile(&self, t: usize) -> &[u32] {
        &self.items[self.offsets[t] as usize..self.offsets[t + 1] as usize]
    }

    /// Number of tiles.
    pub fn tiles(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }
}

/// Sets up every triangle (clipping where needed), in source order.
pub fn setup_triangles(
    clip: &[Vec4],
    triangles: &[[u32; 3]],
    cfg: &RasterConfig,
) -> Vec<SetupTriangle> {
    let mut out = Vec::new();
    setup_triangles_into(
        clip,
        triangles,
        cfg,
        &mut RasterScratch::default(),
        &mut out,
    );
    out
}

/// [`setup_triangles`] into `out` (cleared first), with `scratch`'s buffers. Each vertex is
/// tested against the clip planes and snapped once (a vertex shared by six triangles is
/// not snapped six times); a triangle no plane clips is set up from its snapped vertices
/// ([`setup::setup_snapped`], the same bits as [`setup::setup`]), a clipped one from its
/// clipped polygon. Two passes (module doc): survivors first, then each survivor set up
/// in place, so the output order is source order for any thread count.
fn setup_triangles_into(
    clip: &[Vec4],
    triangles: &[[u32; 3]],
    cfg: &RasterConfig,
    scratch: &mut RasterScratch,
    out: &mut Vec<SetupTriangle>,
) {
    let planes = ClipPlanes::new(cfg.near, cfg.width, cfg.height);
    let cull_back = cfg.cull == Cull::Back;
    let (width, height) = (cfg.width, cfg.height);
    let verts = &mut scratch.verts;
    clip.par_iter()
        .with_min_len(2 * SETUP_CHUNK)
        .map(|&p| {
            let code = planes.outcode(p);
            let (x, y) = if code == 0 {
                setup::snap(p, width, height)
            } else {
                (0, 0)
            };
            SnappedVertex { x, y, w: p.w, code }
        })
        .collect_into_vec(verts);
    let verts = &*verts;
    // Pass 1, per chunk in parallel: which set-up triangles survive, as (source triangle,
    // triangle of its clipped polygon's fan or UNCLIPPED), in source order. Only the cheap
    // rejections run here ([`setup::covered_bounds`]; most triangles of a dense mesh end
    // there); clipping is rare and done again in pass 2.
    let chunks = &mut scratch.chunks;
    chunks.resize_with(triangles.len().div_ceil(SETUP_CHUNK), Vec::new);
    chunks
        .par_iter_mut()
        .zip(triangles.par_chunks(SETUP_CHUNK))
        .enumerate()
        .for_each(|(ci, (out, chunk))| {
            // Survivors are written branch-free: each unclipped triangle's entry is stored
            // at `n`, which advances only when it survives (a slot per triangle is there
            // from the start; a clipped triangle's fan may add more).
            out.clear();
            out.resize(chunk.len(), [0, 0]);
            let mut n = 0;
            let mut poly = Vec::new();
            for (k, tri) in chunk.iter().enumerate() {
                let source = (ci * SETUP_CHUNK + k) as u32;
                let sv = tri.map(|i| verts[i as usize]);
                let codes = sv.map(|v| v.code);
                if codes[0] | codes[1] | codes[2] == 0 {
                    let p = sv.map(|v| (v.x, v.y));
                    if n == out.len() {
                        out.push([0, 0]);
                    }
                    out[n] = [source, UNCLIPPED];
                    n += setup::covers_a_centre(p, width, height, cull_back) as usize;
                    continue;
                }
                if codes[0] & codes[1] & codes[2] != 0 {
                    continue; // wholly outside one plane
                }
                planes.clip_triangle(tri.map(|i| clip[i as usize]), &mut poly);
                for i in 1..poly.len().saturating_sub(1) {
                    let p =
                        [poly[0], poly[i], poly[i + 1]].map(|v| setup::snap(v.clip, width, height));
                    if setup::covered_bounds(p, width, height, cull_back).is_some() {
                        out.truncate(n);
                        out.push([source, i as u32]);
                        n += 1;
                    }
                }
            }
            out.truncate(n);
        });
    let survivors = &mut scratch.survivors;
    survivors.clear();
    for c in chunks.iter() {
        survivors.extend_from_slice(c);
    }
    // Pass 2, in parallel: each survivor set up straight into `out` (an indexed parallel
    // iterator writes in place: the 200-byte triangles are written once, never copied).
    // With each triangle, binning's tile rectangle and the tile walk's record of it are
    // made here, from the triangle while it is in registers (three vectors written in
    // place: the set-up list is not read back).
    const IDENTITY: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let tiles = TileDiv::new(cfg.tile_size);
    let bins = &mut scratch.bins;
    let mut sink = (
        std::mem::take(out),
        (
            std::mem::take(&mut bins.rects),
            std::mem::take(&mut bins.walk),
        ),
    );
    sink.0.clear();
    sink.1 .0.clear();
    sink.1 .1.clear();
    sink.par_extend(survivors.par_iter().with_min_len(SETUP_CHUNK / 4).map_init(
        Vec::new,
        |poly, &[source, fan]| {
            let tri = triangles[source as usize];
            let set_up = if fan == UNCLIPPED {
                let sv = tri.map(|i| verts[i as usize]);
                setup::setup_snapped(
                    sv.map(|v| (v.x, v.y)),
                    sv.map(|v| v.w),
                    IDENTITY,
                    source,
                    width,
                    height,
                    cull_back,
                )
            } else {
                planes.clip_triangle(tri.map(|i| clip[i as usize]), poly);
                let f = fan as usize;
                let cv = [poly[0], poly[f], poly[f + 1]];
                setup::setup(cv, source, width, height, cull_back)
            };
            let t = set_up.expect("pass 1 kept only triangles that set up");
            (t, (tiles.rect(&t), tile::TileTriangle::new(&t)))
        },
    ));
    (*out, (bins.rects, bins.walk)) = sink;
}

/// Division of a pixel coordinate by the tile size as a multiply and a shift (binning's
/// tile rectangles, four per set-up triangle). With `d = min(tile size, MAX_SIDE)` and
/// `m = floor(2^42 / d) + 1`, so `m d = 2^42 + e` with `0 < e <= d`: for `x = q d + r <
/// MAX_SIDE` (`0 <= r < d`), `x m / 2^42 = q + (r + x e / 2^42) / d`, and `x e <= x d <
/// 2^40` keeps `r + x e / 2^42 < d`, so `(x m) >> 42 = q` exactly (`x m < 2^63`). A tile
/// size past `MAX_SIDE` puts every pixel in tile 0, as `d = MAX_SIDE` does.
#[derive(Clone, Copy, Debug)]
struct TileDiv {
    m: u64,
}

impl TileDiv {
    fn new(tile_size: u32) -> TileDiv {
        let d = tile_size.clamp(1, MAX_SIDE) as u64;
        TileDiv {
            m: (1u64 << 42) / d + 1,
        }
    }

    /// `x / tile size`, for a pixel coordinate `x < MAX_SIDE`.
    #[inline(always)]
    fn div(self, x: u32) -> u32 {
        debug_assert!(x < MAX_SIDE);
        ((x as u64 * self.m) >> 42) as u32
    }

    /// The first and last tile column and row of `t`'s pixel bounds.
    #[inline(always)]
    fn rect(self, t: &SetupTriangle) -> [u32; 4] {
        [t.px_min, t.px_max, t.py_min, t.py_max].map(|v| self.div(v))
    }
}

/// Marks a survivor of set-up's first pass that no plane clips.
const UNCLIPPED: u32 = u32::MAX;

/// Lists, per tile, the indices of the set-up triangles whose pixel bounds touch it, in
/// increasing index order.
pub fn bin_triangles(tris: &[SetupTriangle], tiles_x: u32, tiles_y: u32, tile_size: u32) -> Bins {
    let mut bins = Bins::default();
    bin_triangles_into(tris, tiles_x, tiles_y, tile_size, &mut bins);
    bins
}

/// [`bin_triangles`] into `bins`: each triangle's tile rectangle and the tile walk's
/// compact record of it ([`tile::TileTriangle`]) computed in parallel (the rasterizer makes
/// them in set-up's second pass instead), then listed ([`list_bins`]).
fn bin_triangles_into(
    tris: &[SetupTriangle],
    tiles_x: u32,
    tiles_y: u32,
    tile_size: u32,
    bins: &mut Bins,
) {
    let tiles = TileDiv::new(tile_size);
    tris.par_iter()
        .with_min_len(SETUP_CHUNK)
        .map(|t| (tiles.rect(t), tile::TileTriangle::new(t)))
        .unzip_into_vecs(&mut bins.rects, &mut bins.walk);
    list_bins(tiles_x, tiles_y, bins);
}

/// Lists each tile's triangles from their tile rectangles (`bins.rects`): one pass counts
/// each tile's triangles and a second lists them in triangle order (serial passes of adds;
/// a triangle in one tile, most of a dense mesh's, costs one add in each).
fn list_bins(tiles_x: u32, tiles_y: u32, bins: &mut Bins) {
    let n = (tiles_x * tiles_y) as usize;
    let rects = &bins.rects;
    let offsets = &mut bins.offsets;
    offsets.clear();
    offsets.resize(n + 1, 0);
    for &[x0, x1, y0, y1] in rects {
        if x0 == x1 && y0 == y1 {
            offsets[(y0 * tiles_x + x0) as usize + 1] += 1;
            continue;
        }
        for ty in y0..=y1 {
            let row = (ty * tiles_x) as usize + 1;
            for tx in x0..=x1 {
                offsets[row + tx as usize] += 1;
            }
        }
    }
    for t in 0..n {
        offsets[t + 1] += offsets[t];
    }
    let items = &mut bins.items;
    items.clear();
    items.resize(offsets[n] as usize, 0);
    // Each tile's next free slot, kept in `offsets[t]` while filling and restored after.
    for (i, &[x0, x1, y0, y1]) in rects.iter().enumerate() {
        if x0 == x1 && y0 == y1 {
            let slot = &mut offsets[(y0 * tiles_x + x0) as usize];
            items[*slot as usize] = i as u32;
            *slot += 1;
            continue;
        }
        for ty in y0..=y1 {
            let row = (ty * tiles_x) as usize;
            for tx in x0..=x1 {
                let slot = &mut offsets[row + tx as usize];
                items[*slot as usize] = i as u32;
                *slot += 1;
            }
        }
    }
    // Slot t now holds the end of tile t, the start of tile t + 1.
    for t in (1..=n).rev() {
        offsets[t] = offsets[t - 1];
    }
    offsets[0] = 0;
}

/// Rasterizes `triangles` (indices into `clip`, clip-space positions) into a visibility
/// buffer. Panics if the config has a zero width, height or tile size, or a side over
/// [`MAX_SIDE`] pixels.
pub fn rasterize(clip: &[Vec4], triangles: &[[u32; 3]], cfg: &RasterConfig) -> VisBuffer {
    let mut vis = VisBuffer::default();
    rasterize_into(
        clip,
        triangles,
        cfg,
        &mut RasterScratch::default(),
        &mut vis,
    );
    vis
}

/// [`rasterize`] with a fault seeded into the block walk (tests only).
#[doc(hidden)]
pub fn rasterize_with_fault(
    clip: &[Vec4],
    triangles: &[[u32; 3]],
    cfg: &RasterConfig,
    fault: RasterFault,
) -> VisBuffer {
    let mut vis = VisBuffer::default();
    let mut scratch = RasterScratch::default();
    rasterize_into_with_fault(clip, triangles, cfg, &mut scratch, &mut vis, Some(fault));
    vis
}

/// [`rasterize_into`] with a fault seeded (tests only; [`RasterFault::PreviousFrameKept`]
/// is a fault of the reuse).
#[doc(hidden)]
pub fn rasterize_into_with_fault(
    clip: &[Vec4],
    triangles: &[[u32; 3]],
    cfg: &RasterConfig,
    scratch: &mut RasterScratch,
    vis: &mut VisBuffer,
    fault: Option<RasterFault>,
) {
    assert!(
        cfg.width > 0 && cfg.height > 0 && cfg.tile_size > 0,
        "empty raster target"
    );
    assert!(
        cfg.width <= MAX_SIDE && cfg.height <= MAX_SIDE,
        "raster target over {MAX_SIDE} pixels a side"
    );
    let isa = Dispatch::choose(cfg.kernel).unwrap_or_else(Dispatch::portable);
    let ts = cfg.tile_size;
    let tiles_x = cfg.width.div_ceil(ts);
    let tiles_y = cfg.height.div_ceil(ts);
    setup_triangles_into(clip, triangles, cfg, scratch, &mut vis.triangles);
    let bins = &mut scratch.bins;
    list_bins(tiles_x, tiles_y, bins);
    let bins = &*bins;
    let per_tile = (ts * ts) as usize;
    let n = per_tile * (tiles_x * tiles_y) as usize;
    // A buffer of another size (a first frame) is filled here, in parallel; one of this
    // size is cleared tile by tile just before the tile is resolved, while its memory is
    // in cache (one pass over it, not two).
    let keep = fault == Some(RasterFault::PreviousFrameKept);
    let refill = vis.visible.len() != n || vis.depth.len() != n;
    if refill {
        if keep {
            vis.visible.resize(n, NO_TRIANGLE);
            vis.depth.resize(n, 0.0);
        } else {
            vis.visible.clear();
            vis.visible
                .par_extend(rayon::iter::repeat_n(NO_TRIANGLE, n));
            vis.depth.clear();
            vis.depth.par_extend(rayon::iter::repeat_n(0.0, n));
        }
    }
    let clear_tiles = !refill && !keep;
    let mut clear_coverage = false;
    if cfg.count_coverage {
        let c = vis.coverage.get_or_insert_with(Vec::new);
        if c.len() == n {
            clear_coverage = true;
        } else {
            c.clear();
            c.par_extend(rayon::iter::repeat_n(0, n));
        }
    } else {
        vis.coverage = None;
    }
    vis.tile_occupied.clear();
    vis.tile_occupied
        .extend((0..bins.tiles()).map(|t| !bins.tile(t).is_empty()));
    {
        let cov_chunks: Vec<Option<&mut [u32]>> = match vis.coverage.as_mut() {
            Some(c) => c.chunks_mut(per_tile).map(Some).collect(),
            None => (0..bins.tiles()).map(|_| None).collect(),
        };
        vis.visible
            .par_chunks_mut(per_tile)
            .zip(vis.depth.par_chunks_mut(per_tile))
            .zip(cov_chunks.into_par_iter())
            .enumerate()
            .for_each(|(t, ((visible, depth), mut coverage))| {
                if clear_tiles {
                    visible.fill(NO_TRIANGLE);
                    depth.fill(0.0);
                }
                if clear_coverage {
                    if let Some(c) = coverage.as_deref_mut() {
                        c.fill(0);
                    }
                }
                let bin = bins.tile(t);
                if bin.is_empty() {
                    return;
                }
                let r = PixelRect::tile(t, ts, tiles_x, cfg.width, cfg.height);
                let tile = tile::TileTarget {
                    x0: r.x0,
                    y0: r.y0,
                    x1: r.x0 + r.w - 1,
                    y1: r.y0 + r.h - 1,
                    stride: ts,
                };
                let mut out = tile::TileBuffers {
                    visible,
                    depth,
                    coverage,
                };
                isa.run(tile::ResolveTile {
                    tile: &tile,
                    tris: &bins.walk,
                    bin,
                    out: &mut out,
                    fault,
                });
            });
    }
    vis.width = cfg.width;
    vis.height = cfg.height;
    vis.tile_size = ts;
    vis.tiles_x = tiles_x;
    vis.tiles_y = tiles_y;
    vis.tile_row_left.clear();
    vis.tile_row_left.resize(tiles_y as usize, false);
    vis.rays = None;
}

/// [`rasterize`] into `vis`, reusing its buffers and `scratch`'s: the same bits as
/// [`rasterize`] whatever they held before (every field of `vis` is rewritten; `rays` is
/// reset to `None`). A caller drawing frame after frame at one size (the viewer, a
/// turntable, a bench) keeps both and touches no new memory in a steady state.
pub fn rasterize_into(
    clip: &[Vec4],
    triangles: &[[u32; 3]],
    cfg: &RasterConfig,
    scratch: &mut RasterScratch,
    vis: &mut VisBuffer,
) {
    rasterize_into_with_fault(clip, triangles, cfg, scratch, vis, None);
}

#[cfg(test)]
mod tests {
    use super::{TileDiv, MAX_SIDE};

    /// The multiply-shift tile division against `/` for every pixel coordinate at a spread
    /// of tile sizes, past `MAX_SIDE` included (19 x 2^20 divisions: tens of milliseconds).
    #[test]
    fn tile_div_is_exact() {
        for d in [
            1,
            2,
            3,
            5,
            7,
            8,
            13,
            16,
            31,
            32,
            64,
            100,
            128,
            1000,
            65_537,
            MAX_SIDE - 1,
            MAX_SIDE,
            MAX_SIDE + 1,
            u32::MAX,
        ] {
            let t = TileDiv::new(d);
            for x in 0..MAX_SIDE {
                assert_eq!(t.div(x), x / d, "{x} / {d}");
            }
        }
    }
}
