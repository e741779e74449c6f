//! A group of pixels as lanes: the shading frames and local view directions of up to
//! [`MAX_LANES`] surfaces, computed eight pixels per vector operation.
//!
//! Design rule: the same bits as the scalar definitions, pixel by pixel:
//! [`ShadingFrame::from_normal`] and [`local_view`] (`view.rs`) are computed here lane by
//! lane with the same IEEE operations in the same order (glam's unfused dot products and
//! cross product, its `try_normalize` / `normalize_or` fallbacks, the horizon lift), so a
//! packed path (`packed.rs`, `packed_analytic.rs`) shades each pixel exactly as the
//! per-pixel path would have set it up; `tests` checks this bit for bit on every
//! instruction set, edge cases included (the poles, degenerate normals, views below the
//! horizon).

use super::{Surface, MIN_VIEW_COS};
use crate::conventions::{FrameRule, ShadingFrame};
use crate::kernel::lanes::{F32x8, Isa, LANES, MAX_LANES};
use glam::Vec3;

/// Frames (`t`, `b`, `n`) and lifted local view directions `wo` of up to [`MAX_LANES`]
/// pixels, one per lane (`[axis][lane]`); empty lanes hold the identity frame and `+z`.
pub struct PixelLanes {
    pub t: [[f32; MAX_LANES]; 3],
    pub b: [[f32; MAX_LANES]; 3],
    pub n: [[f32; MAX_LANES]; 3],
    pub wo: [[f32; MAX_LANES]; 3],
    /// Bit `p` set where lane `p` holds a pixel.
    pub present: u32,
}

impl PixelLanes {
    /// The frames and view directions of `surfaces` (at most [`MAX_LANES`]) seen from `eye`,
    /// under `rule`: the world-up frame ([`FrameRule::UP`]) in lanes, any other rule
    /// (view-aligned frames) pixel by pixel through [`super::frame_and_view`] itself.
    #[inline(always)]
    pub fn of<'s, S: Isa>(
        s: S,
        surfaces: impl ExactSizeIterator<Item = &'s Surface>,
        eye: Vec3,
        rule: &FrameRule,
    ) -> PixelLanes {
        let count = surfaces.len();
        debug_assert!(count <= MAX_LANES);
        if *rule != FrameRule::UP {
            return PixelLanes::scalar(surfaces, eye, rule);
        }
        let mut pos = [[0.0f32; MAX_LANES]; 3];
        let mut nrm = [[0.0f32; MAX_LANES]; 3];
        for (p, surf) in surfaces.enumerate() {
            for a in 0..3 {
                pos[a][p] = surf.position[a];
                nrm[a][p] = surf.normal[a];
            }
        }
        let mut out = PixelLanes {
            t: [[0.0; MAX_LANES]; 3],
            b: [[0.0; MAX_LANES]; 3],
            n: [[0.0; MAX_LANES]; 3],
            wo: [[0.0; MAX_LANES]; 3],
            present: (1u32 << count) - 1,
        };
        for o in (0..count.max(1)).step_by(LANES) {
            let nrm = [
                s.load(&nrm[0][o..]),
                s.load(&nrm[1][o..]),
                s.load(&nrm[2][o..]),
            ];
            let pos = [
                s.load(&pos[0][o..]),
                s.load(&pos[1][o..]),
                s.load(&pos[2][o..]),
            ];
            let (t, b, n, wo) = frame_and_view(s, nrm, pos, eye);
            for a in 0..3 {
                t[a].store(&mut out.t[a][o..]);
                b[a].store(&mut out.b[a][o..]);
                n[a].store(&mut out.n[a][o..]);
                wo[a].store(&mut out.wo[a][o..]);
            }
        }
        // Empty lanes: the identity frame and +z (finite values; their weights are 0).
        for p in count..MAX_LANES {
            for a in 0..3 {
                out.t[a][p] = (a == 0) as u8 as f32;
                out.b[a][p] = (a == 1) as u8 as f32;
                out.n[a][p] = (a == 2) as u8 as f32;
                out.wo[a][p] = (a == 2) as u8 as f32;
            }
        }
        out
    }

    /// [`PixelLanes::of`] for the rules other than [`FrameRule::UP`]: each lane's frame
    /// and view from [`super::frame_and_view`] (the turn to the view costs a division and a
    /// square root per pixel, beside a lookup and a sum over lights that dominate).
    fn scalar<'s>(
        surfaces: impl ExactSizeIterator<Item = &'s Surface>,
        eye: Vec3,
        rule: &FrameRule,
    ) -> PixelLanes {
        let count = surfaces.len();
        let mut out = PixelLanes {
            t: [[0.0; MAX_LANES]; 3],
            b: [[0.0; MAX_LANES]; 3],
            n: [[0.0; MAX_LANES]; 3],
            wo: [[0.0; MAX_LANES]; 3],
            present: (1u32 << count) - 1,
        };
        // Empty lanes: the identity frame and +z, as [`PixelLanes::of`] leaves them.
        for p in count..MAX_LANES {
            for a in 0..3 {
                out.t[a][p] = (a == 0) as u8 as f32;
                out.b[a][p] = (a == 1) as u8 as f32;
                out.n[a][p] = (a == 2) as u8 as f32;
                out.wo[a][p] = (a == 2) as u8 as f32;
            }
        }
        for (p, surf) in surfaces.enumerate() {
            let (f, wo) = super::frame_and_view(surf, eye, rule);
            for a in 0..3 {
                out.t[a][p] = f.t[a];
                out.b[a][p] = f.b[a];
                out.n[a][p] = f.n[a];
                out.wo[a][p] = wo[a];
            }
        }
        out
    }

    /// Lane `p`'s frame, as [`ShadingFrame::from_normal`] gives it.
    #[inline(always)]
    pub fn frame(&self, p: usize) -> ShadingFrame {
        let v = |m: &[[f32; MAX_LANES]; 3]| Vec3::new(m[0][p], m[1][p], m[2][p]);
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
fn frame_and_view<S: Isa>(s: S, nrm: V3<S::V>, pos: V3<S::V>, eye: Vec3) -> FrameAndView<S::V> {
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
    use crate::kernel::lanes::{Dispatch, Kernel, KernelPath};
    use crate::shade::local_view;

    struct Lanes(Vec<Surface>, Vec3);
    impl Kernel for Lanes {
        type Out = Vec<(ShadingFrame, Vec3)>;
        fn run<S: Isa>(self, s: S) -> Self::Out {
            let mut out = Vec::new();
            for group in self.0.chunks(MAX_LANES) {
                let l = PixelLanes::of(s, group.iter(), self.1, &FrameRule::UP);
                out.extend((0..group.len()).map(|p| (l.frame(p), l.view(p))));
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
