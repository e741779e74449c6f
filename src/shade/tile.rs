//! The tile loops: the fast (f32) path's ([`shade_kernels`]) and the one the per-pixel
//! paths share ([`shade_per_pixel`]: the scalar oracle, the f64 path).
//!
//! Design rule: each visible pixel is shaded exactly once, independently of every other,
//! so the image does not depend on the thread count or the tile size. Both loops are the
//! one traversal of `traverse.rs` (the image written tile by tile in place, parallel over
//! bands of one tile row; tiles no triangle touched skipped without looking at a pixel;
//! every tile, shaded or skipped, counted once into the caller's [`Progress`], per tile,
//! never per pixel: an atomic add beside a tile's thousand pixels). On the fast path the
//! tile's surfaces found (`traverse.rs`), the rest of the tile ([`ShadeTile`]) is one
//! [`Kernel`], compiled for the instruction set dispatched once per frame: the normal cone
//! that culls light chunks (provably changing no bit), then
//! the per-pixel path (`pixel.rs`) or, for SH data sets under point lights only, the
//! pixel-packed one (`packed.rs`).

use super::surfaces::TileSurfaces;
pub(super) use super::traverse::Pass;
use super::traverse::{for_each_tile, for_each_visible};
use super::{FramePrep, ShadeCounts, Surface};
use crate::image_io::Image;
use crate::kernel::{self, cluster::Cone, skip::needs_restore};
use crate::lanes::{Isa, Kernel, LANES, MAX_LANES};
use crate::mesh::Mesh;
use crate::progress::Progress;
use crate::raster::{PixelRect, VisBuffer};
use crate::scene::Scene;
use glam::Vec3;
use std::sync::Mutex;

/// The fast path: shades every visible pixel of `vis` through the kernels, as `prep`
/// decided, into `img` (linear radiance, of `vis`'s size; every pixel rewritten, background
/// black; `pass` is [`Pass::Writes`] or, on an image just allocated, [`Pass::WritesOnBlack`]),
/// the workers' buffers lent by `scratch`; returns the work done.
pub(super) fn shade_kernels(
    prep: &FramePrep,
    scene: &Scene,
    vis: &VisBuffer,
    progress: &Progress,
    img: &mut Image,
    pass: Pass,
    scratch: &ShadeScratch,
) -> ShadeCounts {
    // Per-pixel lists, or the pixel-packed point-light path's 8 or 16 lanes per light.
    let room = prep.dir.len().max(prep.dropped_dir.len()) + MAX_LANES * prep.points.len();
    // Each worker keeps its buffers across the tiles it shades.
    let shaded = for_each_tile(
        img,
        vis,
        pass,
        Some(progress),
        || scratch.lend(),
        |bufs, rect, band| {
            let bufs = &mut bufs.bufs;
            bufs.scratch.reserve(room);
            prep.dispatch.run(ShadeTile {
                prep,
                mesh: &scene.mesh,
                vis,
                rect,
                band,
                bufs,
            })
        },
    );
    let skipped = vis.tile_occupied.iter().filter(|o| !**o).count() as u64;
    shaded
        + ShadeCounts {
            tiles_skipped: skipped,
            ..ShadeCounts::default()
        }
}

/// The tile loop of the per-pixel paths (the scalar oracle, the f64 path): `radiance` of
/// the surface seen through each visible pixel, into `img` (linear radiance, of `vis`'s
/// size; every pixel rewritten, background black; `pass` as [`shade_kernels`]'s). Which tile a pixel is in changes only
/// the order of the work, never a pixel.
pub(super) fn shade_per_pixel(
    scene: &Scene,
    vis: &VisBuffer,
    progress: &Progress,
    img: &mut Image,
    pass: Pass,
    radiance: impl Fn(&Surface) -> Vec3 + Sync,
) {
    for_each_tile(
        img,
        vis,
        pass,
        Some(progress),
        || (),
        |_, rect, band| {
            for_each_visible(&scene.mesh, vis, rect, rect.y0, |p| {
                band[p.at] = radiance(&p.surface)
            });
        },
    );
}

/// A worker's buffers, kept across the tiles it shades: the coefficient buffer, the
/// gathered lights, the tile's surfaces.
#[derive(Default)]
struct TileBuffers {
    buf: Vec<f32>,
    scratch: kernel::gather::Scratch,
    surfaces: TileSurfaces,
}

impl TileBuffers {
    /// Empties every buffer, keeping its memory: what is read after is what a new
    /// (`default`) one would hold, zeros where it is grown.
    fn empty(&mut self) {
        self.buf.clear();
        let s = &mut self.scratch;
        for v in [
            &mut s.x, &mut s.y, &mut s.z, &mut s.wr, &mut s.wg, &mut s.wb,
        ] {
            v.clear();
        }
        s.n = 0;
        self.surfaces.clear();
    }
}

/// The fast path's worker buffers kept across frames ([`super::shade_into`]): the
/// buffers of the workers that finished, lent again to the next ones, so a steady
/// state of frames of one scene allocates none. A lent set is emptied first
/// (`TileBuffers::empty`): the image does not depend on what an earlier frame, of this
/// scene or another, left in it.
#[derive(Default)]
pub struct ShadeScratch {
    idle: Mutex<Vec<TileBuffers>>,
}

impl std::fmt::Debug for ShadeScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let idle = self.idle.lock().map_or(0, |v| v.len());
        write!(f, "ShadeScratch {{ idle worker buffers: {idle} }}")
    }
}

impl ShadeScratch {
    /// A worker's buffers: an idle set, emptied, or a new one; given back when dropped.
    fn lend(&self) -> Lent<'_> {
        let mut bufs = self
            .idle
            .lock()
            .ok()
            .and_then(|mut v| v.pop())
            .unwrap_or_default();
        bufs.empty();
        Lent { bufs, home: self }
    }
}

/// Buffers lent by a [`ShadeScratch`], given back to it when dropped.
struct Lent<'h> {
    bufs: TileBuffers,
    home: &'h ShadeScratch,
}

impl Drop for Lent<'_> {
    fn drop(&mut self) {
        // A poisoned lock (a worker panicked): the buffers are dropped instead.
        if let Ok(mut idle) = self.home.idle.lock() {
            idle.push(std::mem::take(&mut self.bufs));
        }
    }
}

/// One occupied tile (`rect` of `vis`, rasterized from `mesh`), as a [`Kernel`] so the
/// whole tile loop, its surfaces resolved first (`surfaces.rs`), is compiled for the
/// instruction set dispatched once per frame. `band` is the image rows of the tile's row
/// of tiles; `bufs` are the worker's, reused (`bufs.surfaces` the tile's).
struct ShadeTile<'p, 'a, 'o> {
    prep: &'p FramePrep<'a>,
    mesh: &'o Mesh,
    vis: &'o VisBuffer,
    rect: PixelRect,
    band: &'o mut [Vec3],
    bufs: &'o mut TileBuffers,
}

impl Kernel for ShadeTile<'_, '_, '_> {
    type Out = ShadeCounts;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> ShadeCounts {
        let ShadeTile {
            prep,
            mesh,
            vis,
            rect,
            band,
            bufs,
        } = self;
        let TileBuffers {
            buf,
            scratch,
            surfaces,
        } = bufs;
        surfaces.resolve(s, mesh, vis, rect, prep.eye, &prep.rule);
        let count = surfaces.len();
        let cone = if prep.cull_lights {
            Cone::around((0..count).map(|k| surfaces.normal(k)))
        } else {
            None
        };
        let chunks = prep.dir.chunks_for(cone);
        let mut restored = 0u64;
        // Lane utilisation (`ShadeCounts::pairs_summed` of `lane_slots`).
        let (mut summed, mut slots) = (0u64, 0u64);
        match &prep.sh {
            Some((ds, rec)) if prep.dir.is_empty() && !prep.has_transfer() => {
                let width = super::packed::packed_width(s);
                let np = prep.points.len() as u64;
                for o in (0..count).step_by(width) {
                    let len = (count - o).min(width);
                    let rgb = prep.shade_packed(s, ds, rec, (surfaces, o, len), buf, scratch);
                    for (k, at) in surfaces.at[o..o + len].iter().enumerate() {
                        band[*at] = rgb[k];
                    }
                    summed += len as u64 * np;
                    slots += width as u64 * np;
                }
            }
            _ if prep.packs_analytic() => {
                let nl = prep.live_lights() as u64;
                for o in (0..count).step_by(LANES) {
                    let len = (count - o).min(LANES);
                    let rgb = prep.shade_packed_analytic(s, surfaces, o, len);
                    for (k, at) in surfaces.at[o..o + len].iter().enumerate() {
                        band[*at] = rgb[k];
                    }
                    summed += len as u64 * nl;
                    slots += LANES as u64 * nl;
                }
            }
            _ => {
                for (k, at) in surfaces.at.iter().enumerate() {
                    let surf = &surfaces.surface(k);
                    let fv = surfaces.frame_and_view(k);
                    let mut rgb = prep.shade_surface(s, surf, fv, &chunks, buf, scratch);
                    summed += scratch.n as u64;
                    slots += prep.lane_slots(scratch.n);
                    if !prep.dropped.removed.is_empty()
                        && needs_restore(rgb, prep.dropped.restore_below(surf.normal))
                    {
                        rgb += prep.shade_dropped(s, fv, buf, scratch);
                        summed += scratch.n as u64;
                        slots += prep.lane_slots(scratch.n);
                        restored += 1;
                    }
                    band[*at] = rgb;
                }
            }
        }
        let lights = chunks
            .iter()
            .map(|&c| prep.chunk_live[c as usize] as u64)
            .sum::<u64>()
            + prep.points.len() as u64;
        ShadeCounts {
            tiles_shaded: 1,
            tiles_skipped: 0,
            pixels_shaded: count as u64,
            light_pairs: count as u64 * lights + restored * prep.dropped.removed.len() as u64,
            pixels_restored: restored,
            pairs_summed: summed,
            lane_slots: slots,
        }
    }
}

impl FramePrep<'_> {
    /// **Bench only** (`benches/frame.rs`, row `surfaces`): the fast path's surfaces of
    /// every occupied tile of `vis` (rasterized from `scene`), with their shading frames and
    /// local views, one tile after the other on one thread, nothing shaded. Returns the
    /// number of surfaces, and a sum of their local views' z (so nothing is left out).
    #[doc(hidden)]
    pub fn surfaces_alone(&self, scene: &Scene, vis: &VisBuffer) -> (usize, f32) {
        let mut bufs = TileBuffers::default();
        let (mut count, mut sum) = (0, 0.0);
        for t in (0..vis.tile_occupied.len()).filter(|&t| vis.tile_occupied[t]) {
            let (c, z) = self.dispatch.run(SurfacesAlone {
                prep: self,
                scene,
                vis,
                rect: vis.tile_rect(t),
                bufs: &mut bufs,
            });
            count += c;
            sum += z;
        }
        (count, sum)
    }
}

/// One tile of [`FramePrep::surfaces_alone`], as a [`Kernel`] like [`ShadeTile`].
struct SurfacesAlone<'p, 'a, 'o> {
    prep: &'p FramePrep<'a>,
    scene: &'o Scene,
    vis: &'o VisBuffer,
    rect: crate::raster::PixelRect,
    bufs: &'o mut TileBuffers,
}

impl Kernel for SurfacesAlone<'_, '_, '_> {
    type Out = (usize, f32);
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> (usize, f32) {
        let SurfacesAlone {
            prep,
            scene,
            vis,
            rect,
            bufs,
        } = self;
        let tile = &mut bufs.surfaces;
        tile.resolve(s, &scene.mesh, vis, rect, prep.eye, &prep.rule);
        let sum = tile.wo[2].iter().sum::<f32>();
        (bufs.surfaces.len(), sum)
    }
}
