//! Gathering a pixel's lights: the directional lights above the pixel's horizon, in local
//! shading coordinates with their weights, compacted into a per-worker [`Scratch`] that every
//! material's kernel then sums over (the SH kernel, [`super::sh`], and the lane models,
//! [`super::models`]).
//!
//! Design rule: what is gathered depends only on the pixel and the lights (lights at or
//! below the horizon weigh exactly zero in the oracle and are never kept), never on which
//! chunks a tile's culling ([`super::cluster`]) dropped, so culling changes no bit. Units:
//! weights are irradiance at normal incidence times `cos(polar_i)` (W/m^2, RGB), or the
//! irradiance alone for a material that includes the cosine; directions are unit vectors in
//! the frame of [`crate::conventions::ShadingFrame`].

use super::cluster::DirLights;
use super::lanes::{Arith, F32x8, Isa, Width, LANES};
use crate::conventions::ShadingFrame;
use glam::Vec3;

/// Per-worker scratch space, reused across the pixels of a tile (and across tiles): the
/// lights above one pixel's horizon as a structure of arrays, local direction `(x, y, z)`
/// and RGB weight, `n` of them. Sized once by [`Scratch::reserve`]; nothing is pushed or
/// allocated per pixel.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
    pub wr: Vec<f32>,
    pub wg: Vec<f32>,
    pub wb: Vec<f32>,
    pub n: usize,
}

impl Scratch {
    /// Room for `lights` lights (plus a group of padding); never shrinks.
    pub fn reserve(&mut self, lights: usize) {
        let len = lights + 2 * LANES;
        if self.x.len() < len {
            for v in [
                &mut self.x,
                &mut self.y,
                &mut self.z,
                &mut self.wr,
                &mut self.wg,
                &mut self.wb,
            ] {
                v.resize(len, 0.0);
            }
        }
        self.n = 0;
    }

    /// Empties the list (keeps the room).
    #[inline(always)]
    pub fn clear(&mut self) {
        self.n = 0;
    }

    /// Appends one light (local direction, RGB weight). Panics past the reserved room.
    #[inline(always)]
    pub fn push(&mut self, l: Vec3, w: Vec3) {
        let i = self.n;
        self.x[i] = l.x;
        self.y[i] = l.y;
        self.z[i] = l.z;
        self.wr[i] = w.x;
        self.wg[i] = w.y;
        self.wb[i] = w.z;
        self.n += 1;
    }

    /// Pads the list to whole groups of [`LANES`] with lights of zero weight pointing
    /// along the normal (so every basis value stays finite), and returns the padded count.
    #[inline(always)]
    pub fn pad(&mut self) -> usize {
        let end = padded(self.n);
        for i in self.n..end {
            self.x[i] = 0.0;
            self.y[i] = 0.0;
            self.z[i] = 1.0;
            self.wr[i] = 0.0;
            self.wg[i] = 0.0;
            self.wb[i] = 0.0;
        }
        end
    }
}

/// `n` lights padded to whole groups of [`LANES`] (what [`Scratch::pad`] fills).
#[inline(always)]
pub fn padded(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
}

/// Appends to `sc` the lights of chunks `chunks` of `lights` that lie above the horizon of
/// `frame` (and carry irradiance), in light order, as local directions with weights `E cos`
/// (`E` when `includes_cosine`). Lights at or below the horizon weigh exactly zero in the
/// oracle and are not kept, so what is kept (and the result) depends only on the pixel and
/// the lights, never on which chunks a tile's culling dropped.
#[inline(always)]
pub fn gather_dir<S: Isa>(
    s: S,
    frame: &ShadingFrame,
    includes_cosine: bool,
    lights: &DirLights,
    chunks: &[u32],
    sc: &mut Scratch,
) {
    let (t, b, n) = (frame.t, frame.b, frame.n);
    let (tx, ty, tz) = (s.splat(t.x), s.splat(t.y), s.splat(t.z));
    let (bx, by, bz) = (s.splat(b.x), s.splat(b.y), s.splat(b.z));
    let (nx, ny, nz) = (s.splat(n.x), s.splat(n.y), s.splat(n.z));
    let zero = s.zero();
    // On AVX-512, two chunks at once (16 lanes): the same per-light arithmetic, and one
    // compress of both in chunk order, so the list is the one the loop below makes.
    let mut chunks = chunks;
    if <S::Wide as Width>::N == 2 * LANES {
        let w = s.wide();
        let (tx, ty, tz) = (w.splat(t.x), w.splat(t.y), w.splat(t.z));
        let (bx, by, bz) = (w.splat(b.x), w.splat(b.y), w.splat(b.z));
        let (nx, ny, nz) = (w.splat(n.x), w.splat(n.y), w.splat(n.z));
        let zero = w.zero();
        let pairs = chunks.chunks_exact(2);
        chunks = pairs.remainder();
        for pair in pairs {
            let (c0, c1) = (pair[0] as usize, pair[1] as usize);
            let at = [c0 * LANES, c1 * LANES];
            let dx = w.load_groups(&lights.dx, at);
            let dy = w.load_groups(&lights.dy, at);
            let dz = w.load_groups(&lights.dz, at);
            let z = dz.fma(nz, dy.fma(ny, dx * nx));
            let live = lights.chunk_live_mask[c0] as u32 | (lights.chunk_live_mask[c1] as u32) << 8;
            let mask = w.gt_mask(z, zero) & live;
            if mask == 0 {
                continue;
            }
            let x = dz.fma(tz, dy.fma(ty, dx * tx));
            let y = dz.fma(bz, dy.fma(by, dx * bx));
            let (er, eg, eb) = (
                w.load_groups(&lights.er, at),
                w.load_groups(&lights.eg, at),
                w.load_groups(&lights.eb, at),
            );
            let (wr, wg, wb) = if includes_cosine {
                (er, eg, eb)
            } else {
                (er * z, eg * z, eb * z)
            };
            let at = sc.n;
            w.compress_store(x, mask, &mut sc.x, at);
            w.compress_store(y, mask, &mut sc.y, at);
            w.compress_store(z, mask, &mut sc.z, at);
            w.compress_store(wr, mask, &mut sc.wr, at);
            w.compress_store(wg, mask, &mut sc.wg, at);
            sc.n += w.compress_store(wb, mask, &mut sc.wb, at);
        }
    }
    for &ch in chunks {
        let o = ch as usize * LANES;
        let dx = s.load(&lights.dx[o..]);
        let dy = s.load(&lights.dy[o..]);
        let dz = s.load(&lights.dz[o..]);
        let z = dz.mul_add(nz, dy.mul_add(ny, dx * nx));
        let mask = z.gt_mask(zero) & lights.chunk_live_mask[ch as usize] as u32;
        if mask == 0 {
            continue;
        }
        let x = dz.mul_add(tz, dy.mul_add(ty, dx * tx));
        let y = dz.mul_add(bz, dy.mul_add(by, dx * bx));
        let (er, eg, eb) = (
            s.load(&lights.er[o..]),
            s.load(&lights.eg[o..]),
            s.load(&lights.eb[o..]),
        );
        let (wr, wg, wb) = if includes_cosine {
            (er, eg, eb)
        } else {
            (er * z, eg * z, eb * z)
        };
        let at = sc.n;
        x.compress_store(mask, &mut sc.x, at);
        y.compress_store(mask, &mut sc.y, at);
        z.compress_store(mask, &mut sc.z, at);
        wr.compress_store(mask, &mut sc.wr, at);
        wg.compress_store(mask, &mut sc.wg, at);
        sc.n += wb.compress_store(mask, &mut sc.wb, at);
    }
}
