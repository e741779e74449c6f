//! Pixels as lanes: the shading frames and local view directions of surfaces computed
//! eight pixels per vector operation (`frame_and_view_lanes`, which `surfaces.rs` runs
//! over a tile once), and a group of up to [`crate::lanes::MAX_LANES`] of them as
//! the packed paths read it (`PixelLanes`).
//!
//! Design rule: the same bits as the scalar definitions, pixel by pixel:
//! [`ShadingFrame::from_normal`] and [`local_view`] (`view.rs`) are computed here lane by
//! lane with the same IEEE operations in the same order (glam's unfused dot products and
//! cross product, its `try_normalize` / `normalize_or` fallbacks, the horizon lift), so a
//! packed path (`packed.rs`, `packed_analytic.rs`) shades each pixel exactly as the
//! per-pixel path would have set it up; `tests` checks this bit for bit on every
//! instruction set, edge cases included (the poles, degenerate normals, views below the
//! horizon).

use super::MIN_VIEW_COS;
use crate::conventions::ShadingFrame;
use crate::lanes::{F32x8, Isa};
use glam::Vec3;

/// Frames (`t`, `b`, `n`) and lifted local view directions `wo` of up to
/// [`crate::lanes::MAX_LANES`] pixels, one per lane (`[axis][lane..]`, slices of a
/// tile's arrays, `surfaces.rs`, each long enough for the widest load); lanes without a
/// pixel hold the identity frame and `+z`.
pub struct PixelLanes<'a> {
    pub t: [&'a [f32]; 3],
    pub b: [&'a [f32]; 3],
    pub n: [&'a [f32]; 3],
    pub wo: [&'a [f32]; 3],
    /// Bit `p` set where lane `p` holds a pixel.
    pub present: u32,
}

impl PixelLanes<'_> {
    /// Lane `p`'s frame, as [`ShadingFrame::from_normal`] gives it.
    #[inline(always)]
    pub fn frame(&self, p: usize) -> ShadingFrame {
        let v = |m: &[&[f32]; 3]| Vec3::new(m[0][p], m[1][p], m[2][p]);
        ShadingFrame {
            t: v(&self.t),
            b: v(&self.b),
            n: v(&self.n),
        }
    }

    /// Lane `p`'s local view direction, as [`super::local_view`] gives it.
    #[inline(always)]
    pub fn view(&self, p: usize) -> Vec3 {
        Vec3::new(self.wo[0][p], self.wo[1][p], self.wo[2][p])
    }
}

type V3<V> = [V; 3];

/// A frame (`t`, `b`, `n`) and a view direction, per lane.
type FrameAndView<V> = (V3<V>, V3<V>, V3<V>, V3<V>);

/// glam's `Vec3::dot`: `(a.x b.x + a.y b.y) + a.z b.z`, unfused.
#[inline(always)]
fn dot<V: F32x8>(a: &V3<V>, b: &V3<V>) -> V {
    (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]
}

/// `v * rcp` where `rcp = 1 / |v|` is finite and positive, else `fallback` (glam's
/// `try_normalize` / `normalize_or`).
#[inline(always)]
fn normalize_or<S: Isa>(s: S, v: V3<S::V>, fallback: V3<S::V>) -> V3<S::V> {
    let rcp = s.splat(1.0).div(dot(&v, &v).sqrt());
    let zero = s.zero();
    let inf = s.splat(f32::INFINITY);
    // ok where 0 < rcp < inf (false for NaN).
    let [x, y, z] = v;
    let [fx, fy, fz] = fallback;
    [
        inf.select_gt(rcp, rcp.select_gt(zero, x * rcp, fx), fx),
        inf.select_gt(rcp, rcp.select_gt(zero, y * rcp, fy), fy),
        inf.select_gt(rcp, rcp.select_gt(zero, z * rcp, fz), fz),
    ]
}

/// [`ShadingFrame::from_normal`] of normals `nrm` and [`super::local_view`] from `eye` at
/// positions `pos`, per lane.
#[inline(always)]
pub(super) fn frame_and_view_lanes<S: Isa>(
    s: S,
    nrm: V3<S::V>,
    pos: V3<S::V>,
    eye: Vec3,
) -> FrameAndView<S::V> {
    let (zero, one) = (s.zero(), s.splat(1.0));
    let minus = s.splat(-1.0);
    let n = normalize_or(s, nrm, [zero, zero, one]);
    // from_normal: t = (-n.x n.y / s, s, -n.z n.y / s) with s = sqrt(n.x^2 + n.z^2), or
    // (0, 0, -signum(n.y)) where s^2 = 0 (there n.y = +-1; +0 would give -1 as here).
    let s2 = n[0] * n[0] + n[2] * n[2];
    let sq = s2.sqrt();
    let inv = one.div(sq);
    let t_reg = [(n[0] * minus) * n[1] * inv, sq, (n[2] * minus) * n[1] * inv];
    let t_pole = [zero, zero, zero.select_gt(n[1], one, minus)];
    let t = [
        s2.select_gt(zero, t_reg[0], t_pole[0]),
        s2.select_gt(zero, t_reg[1], t_pole[1]),
        s2.select_gt(zero, t_reg[2], t_pole[2]),
    ];
    // b = n x t (glam's cross).
    let b = [
        n[1] * t[2] - t[1] * n[2],
        n[2] * t[0] - t[2] * n[0],
        n[0] * t[1] - t[0] * n[1],
    ];
    // local_view: (eye - p) normalised or n, to local, lifted above the horizon.
    let d = [
        s.splat(eye.x) - pos[0],
        s.splat(eye.y) - pos[1],
        s.splat(eye.z) - pos[2],
    ];
    let v = normalize_or(s, d, n);
    let wo = [dot(&v, &t), dot(&v, &b), dot(&v, &n)];
    let c = s.splat(MIN_VIEW_COS);
    let h = (wo[0] * wo[0] + wo[1] * wo[1]).sqrt();
    let sin = s.splat((1.0 - MIN_VIEW_COS * MIN_VIEW_COS).sqrt());
    let lifted = [
        h.select_gt(zero, wo[0].div(h) * sin, zero),
        h.select_gt(zero, wo[1].div(h) * sin, zero),
        h.select_gt(zero, c, one),
    ];
    let wo = [
        c.select_gt(wo[2], lifted[0], wo[0]),
        c.select_gt(wo[2], lifted[1], wo[1]),
        c.select_gt(wo[2], lifted[2], wo[2]),
    ];
    (t, b, n, wo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conventions::FrameRule;
    use crate::lanes::{Dispatch, Kernel, KernelPath, MAX_LANES};
    use crate::shade::surfaces::TileSurfaces;
    use crate::shade::{local_view, Surface};

    struct Lanes(Vec<Surface>, Vec3);
    impl Kernel for Lanes {
        type Out = Vec<(ShadingFrame, Vec3)>;
        fn run<S: Isa>(self, s: S) -> Self::Out {
            let tile = TileSurfaces::of_surfaces(s, &self.0, self.1, &FrameRule::UP);
            let mut out = Vec::new();
            for o in (0..self.0.len()).step_by(MAX_LANES) {
                let count = (self.0.len() - o).min(MAX_LANES);
                let l = tile.lanes(o, count);
                out.extend((0..count).map(|p| (l.frame(p), l.view(p))));
            }
            out
        }
    }

    fn surface(position: Vec3, normal: Vec3) -> Surface {
        Surface {
            position,
            normal,
            front_facing: true,
            view_depth: 1.0,
            tangent: Vec3::ZERO,
        }
    }

    #[test]
    fn lanes_give_the_scalar_frames_and_views_bit_for_bit() {
        let eye = Vec3::new(0.3, 1.7, 4.0);
        let mut surfaces = vec![
            // Poles of from_normal (n.x = n.z = 0), a zero and a NaN-free tiny normal.
            surface(Vec3::ZERO, Vec3::Y),
            surface(Vec3::ZERO, -Vec3::Y),
            surface(Vec3::X, Vec3::ZERO),
            surface(Vec3::X, Vec3::new(1e-30, 0.0, 0.0)),
            // The eye itself (view falls back to the normal), views below the horizon.
            surface(eye, Vec3::Z),
            surface(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, -1.0, -1e-3)),
            surface(Vec3::new(0.0, 5.0, 0.0), Vec3::new(0.0, 1.0, 0.0)),
            surface(Vec3::new(1.0, 1.7, 4.0), Vec3::new(1.0, 0.0, 0.0)),
        ];
        // A deterministic spread of positions and unnormalised normals.
        let mut x = 0x2545_f491u32;
        let mut r = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            (x as f32 / u32::MAX as f32) * 2.0 - 1.0
        };
        for _ in 0..997 {
            let p = Vec3::new(r(), r(), r()) * 2.0;
            let n = Vec3::new(r(), r(), r());
            surfaces.push(surface(p, n));
        }
        for path in KernelPath::available() {
            let got = Dispatch::choose(path)
                .unwrap()
                .run(Lanes(surfaces.clone(), eye));
            for (surf, (frame, wo)) in surfaces.iter().zip(got) {
                let f = ShadingFrame::from_normal(surf.normal);
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                let what = format!("{} {surf:?}", path.name());
                assert_eq!(bits(frame.t), bits(f.t), "t {what}");
                assert_eq!(bits(frame.b), bits(f.b), "b {what}");
                assert_eq!(bits(frame.n), bits(f.n), "n {what}");
                assert_eq!(bits(wo), bits(local_view(&f, surf, eye)), "wo {what}");
            }
        }
    }
}
