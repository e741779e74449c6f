//! The one per-pixel traversal every shading path takes (the kernels' tile loop, the
//! scalar oracle, the f64 path, the transfer term's and the light cuts' passes): the image
//! in bands of rows shaded in parallel ([`bands`]), a band's tiles in order with the empty
//! ones skipped ([`for_each_tile`]), a rectangle's visible pixels in row-major order with
//! the surface seen through each ([`for_each_visible`]); the frame and local view of a
//! pixel are then [`super::frame_and_view`]'s.
//!
//! Design rule: each visible pixel is visited exactly once, by one task, and what a task
//! returns is summed in band order, so nothing depends on the thread count; which tile or
//! band a pixel falls in changes only the order of the work, never a pixel. The image is
//! written in place: a band is contiguous rows of the image, and a pixel's index in its
//! band is [`VisiblePixel::at`].

use super::{surface_at_index, Surface};
use crate::image_io::Image;
use crate::mesh::Mesh;
use crate::progress::Progress;
use crate::raster::{PixelRect, VisBuffer, NO_TRIANGLE};
use glam::Vec3;
use rayon::prelude::*;

/// A visible pixel: its index in the image rows of its band (`(y - band's first row) width
/// + x`), its coordinates, and the surface seen through it.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePixel {
    pub at: usize,
    pub x: u32,
    pub y: u32,
    pub surface: Surface,
}

/// `f` for every visible pixel of `rect` (inside the frame), row by row and left to right
/// (row-major image order, whatever the tile size). A row is read in segments, one per tile
/// it crosses: a segment of a tile no triangle touched is skipped without a look at its
/// pixels, and an empty pixel is skipped before any triangle is read; one tile-major index
/// per segment, no division per pixel. `band_y0`: the first image row of the band that
/// [`VisiblePixel::at`] counts from.
#[inline(always)]
pub fn for_each_visible(
    mesh: &Mesh,
    vis: &VisBuffer,
    rect: PixelRect,
    band_y0: u32,
    mut f: impl FnMut(VisiblePixel),
) {
    for_each_visible_index(vis, rect, band_y0, |at, i, x, y| {
        if let Some(surface) = surface_at_index(mesh, vis, i, x, y) {
            f(VisiblePixel { at, x, y, surface });
        }
    });
}

/// The pixels [`for_each_visible`] visits, in its order, without their surfaces:
/// `f(at, i, x, y)` with [`VisiblePixel::at`], the tile-major index `i` of the visibility
/// buffer and the pixel's coordinates (what `surfaces.rs` resolves in lanes).
#[inline(always)]
pub(super) fn for_each_visible_index(
    vis: &VisBuffer,
    rect: PixelRect,
    band_y0: u32,
    mut f: impl FnMut(usize, usize, u32, u32),
) {
    let ts = vis.tile_size;
    let x_end = rect.x0 + rect.w;
    for y in rect.y0..rect.y0 + rect.h {
        let row_at = ((y - band_y0) * vis.width) as usize;
        let tile_row = (y / ts) * vis.tiles_x;
        let mut x = rect.x0;
        while x < x_end {
            let tx = x / ts;
            let end = ((tx + 1) * ts).min(x_end);
            if vis.tile_occupied[(tile_row + tx) as usize] {
                let first = vis.index(x, y);
                let ids = &vis.visible[first..first + (end - x) as usize];
                for (k, &id) in ids.iter().enumerate() {
                    if id == NO_TRIANGLE {
                        continue;
                    }
                    let px = x + k as u32;
                    f(row_at + px as usize, first + k, px, y);
                }
            }
            x = end;
        }
    }
}

/// The surfaces of the visible pixels of tile `rect` ([`for_each_visible`] over it), each
/// with its [`VisiblePixel::at`] in the tile's row of tiles, into `out` (cleared first): the
/// per-tile G-buffer of the kernels' path (`tile.rs`).
pub fn tile_surfaces(
    mesh: &Mesh,
    vis: &VisBuffer,
    rect: PixelRect,
    out: &mut Vec<(usize, Surface)>,
) {
    out.clear();
    for_each_visible(mesh, vis, rect, rect.y0, |p| out.push((p.at, p.surface)));
}

/// `image` in bands of `rows` image rows (the last one shorter), each shaded by one task in
/// parallel: `band(state, index, first row, the band's pixels)`, with the worker's `state`
/// from `init` (kept across the bands one worker takes). The results in band order.
pub(super) fn bands<W, R: Send>(
    image: &mut Image,
    rows: u32,
    init: impl Fn() -> W + Sync + Send,
    band: impl Fn(&mut W, usize, u32, &mut [Vec3]) -> R + Sync + Send,
) -> Vec<R> {
    let band_len = (image.width * rows) as usize;
    image
        .pixels
        .par_chunks_mut(band_len)
        .enumerate()
        .map_init(init, |state, (i, pixels)| {
            band(state, i, i as u32 * rows, pixels)
        })
        .collect()
}

/// What a pass of [`for_each_tile`] does to the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Pass {
    /// The pass that writes the image (the lights' pass of every path): each band is
    /// cleared to black first, by the task that shades it, so every pixel is rewritten
    /// whatever the image held (a frame context's image, kept from the previous frame).
    Writes,
    /// The pass that writes the image into one just allocated black: nothing is cleared
    /// (the pages of the empty tiles' rows are never touched, as before frame contexts).
    WritesOnBlack,
    /// A pass that adds a term to the image the writing pass left (transfer, reflection,
    /// light cuts).
    Adds,
}

/// The tile loop of every shading path: [`bands`] of one row of tiles, and in each (after
/// clearing it, on a [`Pass::Writes`]) its tiles
/// in order: `tile(state, tile's pixels, the band's pixels)` for each tile a triangle
/// touched (the others are skipped without a look at a pixel), every tile, shaded or
/// skipped, counted into `progress` once it is done (per tile, never per pixel); a row of
/// tiles left to another shard ([`VisBuffer::leave_tile_row`]) is neither shaded nor counted. Returns
/// the tiles' results summed, per band in tile order and then in band order.
pub(super) fn for_each_tile<W, R>(
    image: &mut Image,
    vis: &VisBuffer,
    pass: Pass,
    progress: Option<&Progress>,
    init: impl Fn() -> W + Sync + Send,
    tile: impl Fn(&mut W, PixelRect, &mut [Vec3]) -> R + Sync + Send,
) -> R
where
    R: TileSum,
{
    bands(image, vis.tile_size, init, |state, ty, _, band| {
        let mut sum = R::default();
        match pass {
            Pass::Writes => band.fill(Vec3::ZERO),
            Pass::WritesOnBlack | Pass::Adds => {}
        }
        // A row left to another shard: not shaded, not counted.
        if vis.tile_row_left[ty] {
            return sum;
        }
        for tx in 0..vis.tiles_x as usize {
            let t = ty * vis.tiles_x as usize + tx;
            if vis.tile_occupied[t] {
                sum = sum.plus(tile(state, vis.tile_rect(t), band));
            }
            if let Some(p) = progress {
                p.inc(1);
            }
        }
        sum
    })
    .into_iter()
    .fold(R::default(), R::plus)
}

/// What a tile of [`for_each_tile`] returns, summed over the tiles and the bands: the
/// work counters (implemented beside them), or nothing.
pub(super) trait TileSum: Default + Send {
    fn plus(self, o: Self) -> Self;
}

impl TileSum for () {
    fn plus(self, _: ()) {}
}
