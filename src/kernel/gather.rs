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
use crate::conventions::ShadingFrame;
use crate::lanes::{Arith, F32x8, Isa, Width, LANES};
use crate::light::Light;
use glam::Vec3;

/// The weight a light of irradiance `e` (RGB, at normal incidence) carries into a
/// material's sum at incidence cosine `cos_i` (`cos(polar_i)`, local z): `e cos_i`, or `e`
/// alone for a material that includes the cosine ([`crate::brdf::Brdf::includes_cosine`]).
/// The one rule of every light on every f32 path; [`lane_weight`] is its lane form.
#[inline(always)]
pub fn light_weight(e: Vec3, cos_i: f32, includes_cosine: bool) -> Vec3 {
    if includes_cosine {
        e
    } else {
        e * cos_i
    }
}

/// [`light_weight`] per lane, one colour channel per entry of `e`.
#[inline(always)]
pub fn lane_weight<V: Arith>(e: [V; 3], cos_i: V, includes_cosine: bool) -> [V; 3] {
    if includes_cosine {
        e
    } else {
        e.map(|c| c * cos_i)
    }
}

/// Point light `light` seen from world position `position` in shading frame `frame`: its
/// local direction and [`light_weight`], or `None` at or below the horizon (or NaN), where
/// it weighs exactly zero ([`Light::at`] gives the direction and the falloff).
#[inline(always)]
pub fn point_light_local(
    light: &Light,
    position: Vec3,
    frame: &ShadingFrame,
    includes_cosine: bool,
) -> Option<(Vec3, Vec3)> {
    let (l, e) = light.at(position);
    let wi = frame.to_local(l);
    (wi.z > 0.0).then(|| (wi, light_weight(e, wi.z, includes_cosine)))
}

/// A shading frame's axes in lanes, each `[x, y, z]`: one frame splatted across the lanes
/// (a pixel's lights, [`gather_dir`]) or a frame per lane (the pixel-packed paths). The one
/// place a directional light's world direction becomes local: every path that turns a
/// directional light into the frame does it with these fused sums, so they give one set of
/// bits.
#[derive(Clone, Copy)]
pub struct LaneFrame<V> {
    pub t: [V; 3],
    pub b: [V; 3],
    pub n: [V; 3],
}

impl<V: Arith> LaneFrame<V> {
    /// `frame` in every lane.
    #[inline(always)]
    pub fn splat(frame: &ShadingFrame, splat: impl Fn(f32) -> V) -> LaneFrame<V> {
        let v = |a: Vec3| [splat(a.x), splat(a.y), splat(a.z)];
        LaneFrame {
            t: v(frame.t),
            b: v(frame.b),
            n: v(frame.n),
        }
    }

    /// The local z (`cos(polar_i)`) of world direction `d`: `d.z n.z + (d.y n.y + d.x n.x)`,
    /// fused.
    #[inline(always)]
    pub fn local_z(&self, d: [V; 3]) -> V {
        dot(d, self.n)
    }

    /// The local x and y of world direction `d` (as [`LaneFrame::local_z`], against `t` and
    /// `b`).
    #[inline(always)]
    pub fn local_xy(&self, d: [V; 3]) -> (V, V) {
        (dot(d, self.t), dot(d, self.b))
    }
}

/// `d.z a.z + (d.y a.y + d.x a.x)`, fused.
#[inline(always)]
fn dot<V: Arith>(d: [V; 3], a: [V; 3]) -> V {
    d[2].fma(a[2], d[1].fma(a[1], d[0] * a[0]))
}

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
    let f = LaneFrame::splat(frame, |v| s.splat(v));
    let zero = s.zero();
    // On AVX-512, two chunks at once (16 lanes): the same per-light arithmetic, and one
    // compress of both in chunk order, so the list is the one the loop below makes.
    let mut chunks = chunks;
    if <S::Wide as Width>::N == 2 * LANES {
        let w = s.wide();
        let f = LaneFrame::splat(frame, |v| w.splat(v));
        let zero = w.zero();
        let pairs = chunks.chunks_exact(2);
        chunks = pairs.remainder();
        for pair in pairs {
            let (c0, c1) = (pair[0] as usize, pair[1] as usize);
            let at = [c0 * LANES, c1 * LANES];
            let d = [&lights.dx, &lights.dy, &lights.dz].map(|v| w.load_groups(v, at));
            let z = f.local_z(d);
            let live = lights.chunk_live_mask[c0] as u32 | (lights.chunk_live_mask[c1] as u32) << 8;
            let mask = w.gt_mask(z, zero) & live;
            if mask == 0 {
                continue;
            }
            let (x, y) = f.local_xy(d);
            let e = [&lights.er, &lights.eg, &lights.eb].map(|v| w.load_groups(v, at));
            let [wr, wg, wb] = lane_weight(e, z, includes_cosine);
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
        let d = [&lights.dx, &lights.dy, &lights.dz].map(|v| s.load(&v[o..]));
        let z = f.local_z(d);
        let mask = z.gt_mask(zero) & lights.chunk_live_mask[ch as usize] as u32;
        if mask == 0 {
            continue;
        }
        let (x, y) = f.local_xy(d);
        let e = [&lights.er, &lights.eg, &lights.eb].map(|v| s.load(&v[o..]));
        let [wr, wg, wb] = lane_weight(e, z, includes_cosine);
        let at = sc.n;
        x.compress_store(mask, &mut sc.x, at);
        y.compress_store(mask, &mut sc.y, at);
        z.compress_store(mask, &mut sc.z, at);
        wr.compress_store(mask, &mut sc.wr, at);
        wg.compress_store(mask, &mut sc.wg, at);
        sc.n += wb.compress_store(mask, &mut sc.wb, at);
    }
}
