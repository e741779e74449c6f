//! The pixel-packed path of the analytic lane models (Lambert, Blinn-Phong) under a few
//! lights: eight pixels per group, one per lane, each pixel's sum over the lights in order.
//!
//! Design rule: with a handful of lights (the default scene's one key light, a point light
//! or two), the per-pixel path (`pixel.rs`) puts each pixel's lights across eight lanes and
//! leaves most of them empty, then gathers, compresses and sums across lanes; here the
//! lanes are pixels and each light is one step of every lane's own sum, so the cost is the
//! arithmetic the lights need. Same terms as [`FramePrep::shade_surface`]:
//! - a directional light's local direction and weight by the same fused multiply-adds as
//!   [`crate::kernel::gather::gather_dir`], a point light's by [`crate::light::Light::at`]
//!   and [`crate::conventions::ShadingFrame::to_local`] per pixel; frames and view
//!   directions resolved with the tile's surfaces (`surfaces.rs`: the scalar ones' bits,
//!   eight pixels at a time);
//! - a light at or below a pixel's horizon (or a lane without a pixel) weighs exactly 0, and
//!   its `powf` is not evaluated;
//! - with **one** light the formula is [`LaneModel::sum`]'s one-light form operation for
//!   operation, so those frames (the default scene, the thesis's single-light figures) keep
//!   their bits; with 2 ..= [`PACKED_MAX_LIGHTS`] lights each pixel sums `f w` over the
//!   lights in order (not across lanes), within [`crate::kernel::KERNEL_TOLERANCE`] of the
//!   oracle like every kernel path.
//!
//! A pixel's result depends only on its own lane, never on the pixels sharing its group,
//! so the image does not depend on the tile size or the thread count.

// The point lights' loop fills per-lane arrays indexed by the lane number, which reads as
// the lane arithmetic it is.
#![allow(clippy::needless_range_loop)]

use super::surfaces::TileSurfaces;
use super::FramePrep;
use crate::kernel::gather::{lane_weight, point_light_local, LaneFrame};
use crate::kernel::models::LaneModel;
use crate::lanes::{F32x8, Isa, LANES};
use glam::Vec3;
use std::f32::consts::PI;

/// Most lights (directional with irradiance, plus point) a frame may have for the packed
/// path: up to one group's worth, where the per-pixel path's group is mostly padding.
pub const PACKED_MAX_LIGHTS: usize = LANES;

impl FramePrep<'_> {
    /// The frame's lights that carry irradiance: the live directional lights of every
    /// chunk, plus the point lights (what the packed analytic path sums per pixel).
    pub(super) fn live_lights(&self) -> usize {
        self.chunk_live.iter().map(|&c| c as usize).sum::<usize>() + self.points.len()
    }

    /// Whether the tile loop shades this frame on the packed analytic path: a Lambert or
    /// Blinn-Phong material, 1 ..= [`PACKED_MAX_LIGHTS`] lights (directional ones with
    /// irradiance, plus point lights), no environment term, no dropped light to restore,
    /// no seeded fault.
    pub fn packs_analytic(&self) -> bool {
        let lights = self.live_lights();
        self.sh.is_none()
            && self.transfer.is_none()
            && self.fault.is_none()
            && self.dropped.removed.is_empty()
            && matches!(
                self.model,
                LaneModel::Lambert { .. } | LaneModel::BlinnPhong { .. }
            )
            && (1..=PACKED_MAX_LIGHTS).contains(&lights)
    }

    /// Up to [`LANES`] pixels of a Lambert or Blinn-Phong material, one per lane, each lit
    /// by every light of the frame in order (module doc): `tile`'s pixels `o .. o + count`
    /// (`count <= LANES`). Results in the first `count` entries.
    #[inline(always)]
    pub(super) fn shade_packed_analytic<S: Isa>(
        &self,
        s: S,
        tile: &TileSurfaces,
        o: usize,
        count: usize,
    ) -> [Vec3; LANES] {
        let px = tile.lanes(o, count);
        let includes_cosine = self.brdf.includes_cosine();
        let zero = s.zero();
        let lanes = |a: &[&[f32]; 3]| [s.load(a[0]), s.load(a[1]), s.load(a[2])];
        let f = LaneFrame {
            t: lanes(&px.t),
            b: lanes(&px.b),
            n: lanes(&px.n),
        };
        let [wox, woy, woz] = lanes(&px.wo);
        let mut acc = (zero, zero, zero);
        // Directional lights with irradiance, in order: local direction and weight as
        // gather_dir computes them (the pixel's frame in lanes, `LaneFrame`).
        let d = &self.dir;
        for c in 0..d.chunks() {
            let live = d.chunk_live_mask[c] as u32;
            for i in (0..LANES).filter(|i| live >> i & 1 == 1) {
                let o = c * LANES + i;
                let dir = [s.splat(d.dx[o]), s.splat(d.dy[o]), s.splat(d.dz[o])];
                let z = f.local_z(dir);
                let mask = z.gt_mask(zero) & px.present;
                if mask == 0 {
                    continue;
                }
                let (x, y) = f.local_xy(dir);
                let e = [s.splat(d.er[o]), s.splat(d.eg[o]), s.splat(d.eb[o])];
                let [wr, wg, wb] = lane_weight(e, z, includes_cosine);
                let w = (wr.keep(mask), wg.keep(mask), wb.keep(mask));
                self.add_light(s, (x, y, z), w, mask, (wox, woy, woz), &mut acc);
            }
        }
        // Point lights, in order: direction and falloff per pixel (Light::at), as the
        // per-pixel path computes them.
        for light in &self.points {
            let mut a = [[0.0f32; LANES]; 6];
            let mut mask = 0u32;
            for p in 0..count {
                let position = tile.position(o + p);
                if let Some((wi, w)) =
                    point_light_local(light, position, &px.frame(p), includes_cosine)
                {
                    (a[0][p], a[1][p], a[2][p]) = (wi.x, wi.y, wi.z);
                    (a[3][p], a[4][p], a[5][p]) = (w.x, w.y, w.z);
                    mask |= 1 << p;
                } else {
                    a[2][p] = 1.0;
                }
            }
            if mask == 0 {
                continue;
            }
            let (x, y, z) = (s.load(&a[0]), s.load(&a[1]), s.load(&a[2]));
            let (wr, wg, wb) = (s.load(&a[3]), s.load(&a[4]), s.load(&a[5]));
            self.add_light(s, (x, y, z), (wr, wg, wb), mask, (wox, woy, woz), &mut acc);
        }
        let (mut r, mut g, mut b) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
        acc.0.store(&mut r);
        acc.1.store(&mut g);
        acc.2.store(&mut b);
        std::array::from_fn(|p| {
            let sum = Vec3::new(r[p], g[p], b[p]);
            match self.model {
                LaneModel::Lambert { albedo } => sum * (albedo / PI),
                _ => sum,
            }
        })
    }

    /// Adds one light's term to every lane's sum: Lambert `w` (scaled by `albedo / pi` at
    /// the end), Blinn-Phong `(kd / pi + ks (a + 8) / (8 pi) (n.h)^a) w` with `h = wi + wo`
    /// and `n.h = h.z / |h|` ([`LaneModel::sum`]'s one-light form), `powf` per lane where
    /// `mask` is set. `w` is 0 outside `mask`.
    #[inline(always)]
    fn add_light<S: Isa>(
        &self,
        s: S,
        wi: (S::V, S::V, S::V),
        w: (S::V, S::V, S::V),
        mask: u32,
        wo: (S::V, S::V, S::V),
        acc: &mut (S::V, S::V, S::V),
    ) {
        match self.model {
            LaneModel::BlinnPhong { kd, ks, exponent } => {
                let hx = wi.0 + wo.0;
                let hy = wi.1 + wo.1;
                let hz = wi.2 + wo.2;
                // glam's length: ((x x + y y) + z z).sqrt(), unfused.
                let len = ((hx * hx + hy * hy) + hz * hz).sqrt();
                let nh = hz.div(len).max(s.zero());
                let mut p = [0.0f32; LANES];
                nh.store(&mut p);
                for (k, v) in p.iter_mut().enumerate() {
                    *v = if mask >> k & 1 == 1 {
                        v.powf(exponent)
                    } else {
                        0.0
                    };
                }
                let spec = s.splat((exponent + 8.0) / (8.0 * PI)) * s.load(&p);
                let kd = kd / PI;
                let fr = s.splat(kd.x) + s.splat(ks.x) * spec;
                let fg = s.splat(kd.y) + s.splat(ks.y) * spec;
                let fb = s.splat(kd.z) + s.splat(ks.z) * spec;
                acc.0 += fr * w.0;
                acc.1 += fg * w.1;
                acc.2 += fb * w.2;
            }
            _ => {
                acc.0 += w.0;
                acc.1 += w.1;
                acc.2 += w.2;
            }
        }
    }
}
