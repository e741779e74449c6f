//! Light cuts shared by the pixels of a tile (the fast path of `[env] method = "lightcuts"`):
//! one cut per square of [`CUT_TILE`] x [`CUT_TILE`] pixels, then every pixel of the square
//! shaded with the cut's representative lights through the directional-light lane kernels
//! ([`crate::kernel::models::LaneModel`]). The per-pixel cut (`mod.rs`) stays the
//! reference (the scalar-oracle path).
//!
//! (Past 400 lines because a quarter of it is the derivation below, which the bound, the
//! criterion and the square splitting all rest on: one concept, kept in one file.)
//!
//! This is Walter et al. 2005's reuse of one cut over nearby receivers ("Lightcuts",
//! section 4.3 reconstruction cuts, here made conservative): a cluster is refined until its
//! bound *over every pixel of the tile* is at most `cut_error` x the tile's smallest pixel
//! estimate, so every pixel's cut meets the per-pixel criterion of [`crate::env::lightcuts`].
//!
//! # Why the widened cone bounds every pixel (derivation)
//! Pixel `p` has shading frame `R_p` (columns `t, b, n`) and local view `wo_p`; the tile's
//! central frame is `R_c = ShadingFrame::from_normal(mean normal)`, turned to the tile's mean
//! world view when the material's frame is view-aligned (as the pixels' are). A light of world
//! direction `w` is at `R_c^T w` in the central frame and at `R_p^T w = Q_p R_c^T w` in the
//! pixel's, `Q_p = R_p^T R_c` a rotation by an angle `a_p` with
//! `||Q_p - I||_F = ||R_c - R_p||_F = 2 sqrt(2) sin(a_p / 2)`, so it moves every direction by
//! at most `a_p` (measured exactly, so frames spinning about the normal are covered too).
//! With `a = max_p a_p`, every pixel-local direction of a cluster of cone `(axis, alpha)` lies
//! in the cone `(R_c^T axis, alpha + a)`. The pixels' local views lie within
//! `delta = max_p angle(wo_p, wo_c)` of `wo_c` (their normalised mean; `delta <= a + b` for a
//! world view spread `b`). The pixel's term `f(wi, wo) cos(polar_i) E` is then bounded by
//! the existing single-view bound ([`ConeBound::f_cos_max`]) at `wo_c` over the cone of half
//! angle `alpha + a + delta`, times a factor `K` for the models whose `f cos` depends on
//! `cos(polar_o)` directly:
//! * Blinn-Phong, the D-BRDF's `p(h)`, Ashikhmin-Shirley's `(n.h)^e`: `f` depends on the
//!   pair through `h = normalize(wi + wo)`. Let `wi' = 2 (h.wo_c) h - wo_c`, the reflection of
//!   `wo_c` about `h`; then `h(wi', wo_c) = h` (when `h.wo_c > 0`, below), and since
//!   `wi = 2 (h.wo) h - wo` is the same isometry applied to `wo`,
//!   `angle(wi', wi) = angle(wo_c, wo) <= delta`: `wi'` is in the cone of `alpha + a + delta`,
//!   so the half vector (and everything of `f` that depends on it alone) is one the bound
//!   at `wo_c` already maximises over. `cos(polar_i)` is maximised over the same (larger)
//!   cone. (The brief's "b/2 for half vectors" is the in-plane value; this reflection is the
//!   general one, paying the full `delta` on the light side.)
//! * Phong: `f` depends on `r(wo).wi`, `r` the mirror about `n` (an isometry):
//!   `r(wo)` is within `delta` of `r(wo_c)`, so a rotation `S` by `<= delta` maps it there,
//!   and `r(wo).wi = r(wo_c).(S wi)` with `S wi` in the widened cone.
//! * Schlick's `F(k.h)` (D-BRDF, Ashikhmin-Shirley) and A-S's `1/(k.h)`: the bound uses
//!   `k.h >= m/2`, `m = |wi' + wo_c|` minimised over the widened cone, i.e.
//!   `cos(gamma_max / 2)` with `gamma_max` the largest angle from `wo_c` to the widened cone.
//!   The pixel's `k.h = cos(angle(wi, wo)/2)` and `angle(wi, wo) <= angle(wi, wo_c) + delta
//!   <= gamma_max`, so the same lower bound holds.
//! * `cos(polar_o)` terms, `b_c = wo_c.z`, pixels' `b in [b_min, b_max]`: the D-BRDF's
//!   `a / (a + b - a b)` (falling in `b`, with ratio `g(a, b) / g(a, b_c) <= max(1, b_c / b)`)
//!   and A-S's `min(1, c_i / b)` are covered by `K_1 = max(1, b_c / b_min)`; A-S's diffuse
//!   `1 - (1 - b/2)^5` (rising in `b`) by `K_2 = max(1, five(b_max) / five(b_c))`.
//!   `K = 1` for Lambert, Phong and Blinn-Phong; `K_1` for the D-BRDF and Lambert + D-BRDF;
//!   `K_1 K_2` for Ashikhmin-Shirley.
//! * `h.wo_c > 0` holds when `angle(h, wo) + delta < pi/2` (`angle(h, wo_c)` is at most
//!   that), i.e. `angle(wi, wo) < pi - 2 delta`, which holds whenever the largest angle from
//!   `wo_c` to the cone of `alpha + a` is below `pi - 3 delta` (`angle(wi, wo) <=
//!   angle(wi, wo_c) + delta`); where it is not (light and view near the horizon on
//!   opposite sides), the bound is taken over the whole sphere.
//!
//! Angles are widened by [`ANGLE_SLACK`] for f32 rounding of the frames (orthonormal to a
//! few 1e-7).
//!
//! # The criterion
//! Refinement by a max-heap of tile bounds (ties by node index), as per pixel. Round one
//! stops when the largest tile bound is at most `cut_error` x the luminance of the cut's
//! estimate at the central frame and view; then every pixel of the tile is shaded with the
//! cut and, while the largest tile bound exceeds `cut_error` x the smallest pixel's
//! luminance, refinement goes on to that threshold and the pixels are shaded again (at most
//! [`MAX_ROUNDS`] rounds; `cut_max` caps the cut as per pixel). The cut therefore depends
//! only on the tile's pixels: same bits on any thread count.

use super::{luminance, Cluster, CutStats};
use crate::conventions::{FrameRule, ShadingFrame};
use crate::env::lightcuts::{LightCuts, TileFault};
use crate::kernel::gather::{light_weight, Scratch};
use crate::kernel::models::LaneModel;
use crate::lanes::{Dispatch, Isa, Kernel};
use crate::material::cone_bound::{min_cos_to, BoundFault, Cone, ConeBound};
use crate::material::Material;
use glam::Vec3;
use std::collections::BinaryHeap;

/// Side of the square of pixels that shares one cut (measured: see `benches/lightcuts.rs`).
pub const CUT_TILE: u32 = 8;

/// Widening of every tile angle (radians) for f32 rounding of frames and views.
pub const ANGLE_SLACK: f32 = 1e-5;

/// Largest number of refine-then-shade rounds of one tile (module doc, "The criterion").
pub const MAX_ROUNDS: usize = 6;

/// One pixel of a tile: where it goes in its band, its frame and its local view.
#[derive(Clone, Copy, Debug)]
pub struct TilePixel {
    pub at: usize,
    /// Image column and row.
    pub x: u32,
    pub y: u32,
    pub frame: ShadingFrame,
    pub wo: Vec3,
}

/// The tile's geometry as the bound needs it (module doc): central frame and view, the
/// widening `a + delta` (radians) of every light cone, the light cone's own widening `a`,
/// and the factor `k` of the `cos(polar_o)` terms.
#[derive(Clone, Copy, Debug)]
pub struct TileFrame {
    pub frame: ShadingFrame,
    pub wo: Vec3,
    pub frame_spread: f32,
    pub view_spread: f32,
    pub k: f32,
    /// [`Widening`]s by `a` and by `a + delta`, and `cos(3 delta)` (module doc).
    light: Widening,
    both: Widening,
    cos_3delta: f32,
}

/// A widening of cones by an angle `w` in [0, pi]: `cos w`, `sin w`, `cos(w/2)`, `sin(w/2)`
/// (computed once per square, not per cluster).
#[derive(Clone, Copy, Debug)]
struct Widening {
    cos: f32,
    sin: f32,
    cos_half: f32,
    sin_half: f32,
}

impl Widening {
    fn by(w: f32) -> Widening {
        let w = w.clamp(0.0, std::f32::consts::PI);
        Widening {
            cos: w.cos(),
            sin: w.sin(),
            cos_half: (0.5 * w).cos(),
            sin_half: (0.5 * w).sin(),
        }
    }
}

fn five(x: f32) -> f32 {
    1.0 - (1.0 - 0.5 * x).powi(5)
}

impl TileFrame {
    /// The tile frame of `pixels` (non-empty) for `material` (module doc).
    pub fn of(pixels: &[TilePixel], material: &Material, rule: &FrameRule) -> TileFrame {
        let n = pixels
            .iter()
            .fold(Vec3::ZERO, |s, p| s + p.frame.n)
            .normalize_or(pixels[0].frame.n);
        let mut frame = if rule.mesh_tangent {
            // The pixels' frames follow the mesh's tangent: so does the central one, from
            // their mean tangent, or the spread `a` would be their turn from world up.
            let t = pixels.iter().fold(Vec3::ZERO, |s, p| s + p.frame.t);
            ShadingFrame::from_normal_tangent(n, t)
        } else {
            ShadingFrame::from_normal(n)
        };
        if let Some((c, s)) = rule.view_azimuth {
            // The pixels' frames are turned to their views: so is the central frame, to
            // the tile's mean world view, or the spread `a` below would be the views'
            // azimuths about the normal.
            let v = pixels
                .iter()
                .fold(Vec3::ZERO, |s, p| s + p.frame.to_world(p.wo))
                .normalize_or(n);
            frame = frame.turned_to_view(v, c, s);
        }
        let wo = pixels
            .iter()
            .fold(Vec3::ZERO, |s, p| s + p.wo)
            .normalize_or(Vec3::Z);
        let (mut a, mut delta) = (0.0f32, 0.0f32);
        let (mut b_min, mut b_max) = (f32::INFINITY, 0.0f32);
        for p in pixels {
            let d2 = (frame.t - p.frame.t).length_squared()
                + (frame.b - p.frame.b).length_squared()
                + (frame.n - p.frame.n).length_squared();
            let s = (d2.sqrt() / (2.0 * std::f32::consts::SQRT_2)).min(1.0);
            a = a.max(2.0 * s.asin());
            let c = (0.5 * (p.wo - wo).length()).min(1.0);
            delta = delta.max(2.0 * c.asin());
            b_min = b_min.min(p.wo.z);
            b_max = b_max.max(p.wo.z);
        }
        let b_c = wo.z.max(1e-6);
        let k1 = if b_min > 0.0 {
            (b_c / b_min).max(1.0)
        } else {
            f32::INFINITY
        };
        let k2 = (five(b_max.min(1.0)) / five(b_c)).max(1.0);
        let k = match material {
            Material::DBrdf(_) | Material::LambertDbrdf(_) => k1,
            Material::AshikhminShirley(_) => k1 * k2,
            Material::Lambert(_)
            | Material::Phong(_)
            | Material::BlinnPhong(_)
            | Material::Merl(_)
            | Material::Rgl(_)
            | Material::Sh(_) => 1.0,
        };
        let (a, delta) = (a + ANGLE_SLACK, delta + ANGLE_SLACK);
        TileFrame {
            frame,
            wo,
            frame_spread: a,
            view_spread: delta,
            k: k * (1.0 + 1e-5),
            light: Widening::by(a),
            both: Widening::by(a + delta),
            cos_3delta: (3.0 * delta).min(std::f32::consts::PI).cos(),
        }
    }
}

/// `cone` (half angle `alpha`) widened to `alpha + w`, `w` in [0, pi]: the whole sphere at
/// or past `pi` (angle-sum formulas, no trigonometric call).
#[inline]
fn widen(cone: &Cone, w: &Widening) -> Cone {
    let (cw, sw) = (w.cos, w.sin);
    if cone.cos <= -cw {
        return Cone {
            axis: cone.axis,
            ..Cone::SPHERE
        };
    }
    let (cw2, sw2) = (w.cos_half, w.sin_half);
    let cos_q = (1.0 - cone.sin_half * cone.sin_half).max(0.0).sqrt();
    Cone {
        axis: cone.axis,
        cos: cone.cos * cw - cone.sin * sw,
        sin: (cone.sin * cw + cone.cos * sw).max(0.0),
        sin_half: (cone.sin_half * cw2 + cos_q * sw2).min(1.0),
    }
}

/// The tile bound of a cluster of cone `cone` (central-frame local, not yet widened):
/// an upper bound of `f cos(polar_i)` (RGB, 1/sr) over every pixel of the tile and every
/// direction of the cone (module doc). `faults` are the seeded faults of the tests
/// (the per-pixel bound's and the tile's; [`LightCuts`]), `material` evaluates `f` for
/// [`BoundFault::IgnoreCone`].
#[inline]
pub fn tile_f_cos_max(
    bound: &ConeBound,
    tf: &TileFrame,
    cone: &Cone,
    faults: (BoundFault, TileFault),
    material: &Material,
) -> Vec3 {
    let single = |c: &Cone| {
        if faults.0 == BoundFault::None {
            bound.f_cos_max(c, tf.wo)
        } else {
            bound.f_cos_max_with_fault(material, c, tf.wo, faults.0)
        }
    };
    if faults.1 == TileFault::NoWidening {
        return single(cone);
    }
    let light = widen(cone, &tf.light);
    // h.wo_c > 0 for every pair unless the cone reaches within 3 delta of -wo_c.
    let far = min_cos_to(&light, tf.wo);
    let wide = if far <= -tf.cos_3delta {
        Cone {
            axis: cone.axis,
            ..Cone::SPHERE
        }
    } else {
        widen(cone, &tf.both)
    };
    single(&wide) * tf.k
}

/// What a tile's shading needs, borrowed from the frame.
pub struct TileCtx<'a> {
    pub cuts: &'a LightCuts,
    pub bound: &'a ConeBound,
    pub material: &'a Material,
    pub model: LaneModel<'a>,
    pub includes_cosine: bool,
    /// The material's frame rule (the pixels' frames; [`TileFrame::of`] turns the central
    /// frame the same way).
    pub rule: FrameRule,
}

/// The bounding cone of interior node `i` of `tree` (a leaf has none) in the local
/// coordinates of `frame`.
#[inline]
pub fn node_cone(tree: &crate::env::lightcuts::LightTree, i: usize, frame: &ShadingFrame) -> Cone {
    let c = tree.cone_slot(i);
    Cone {
        axis: frame.to_local(tree.axis[c]),
        cos: tree.cos_half[c],
        sin: tree.sin_half[c],
        sin_half: tree.sin_quarter[c],
    }
}

impl TileCtx<'_> {
    fn cluster(&self, tf: &TileFrame, i: usize) -> Cluster {
        let tree = &self.cuts.tree;
        let e = tree.irradiance[i];
        let wi = tf.frame.to_local(tree.rep[i]);
        let estimate = if wi.z > 0.0 {
            self.material.eval(wi, tf.wo) * wi.z * e
        } else {
            Vec3::ZERO
        };
        let err = if tree.is_leaf(i) {
            0.0
        } else {
            let cone = node_cone(tree, i, &tf.frame);
            let faults = (self.cuts.fault, self.cuts.tile_fault);
            let b = tile_f_cos_max(self.bound, tf, &cone, faults, self.material);
            luminance(b * e)
        };
        Cluster::new(err, i, estimate)
    }
}

/// Per-worker scratch of the tile path.
#[derive(Default)]
pub struct TileScratch {
    heap: BinaryHeap<Cluster>,
    dirs: Vec<Vec3>,
    irr: Vec<Vec3>,
    pub lights: Scratch,
    pub out: Vec<Vec3>,
}

/// Shades the pixels of one tile with one shared cut (module doc) into `sc.out` (one
/// radiance per pixel, in order); returns the cut's statistics.
pub struct ShadeCutTile<'c, 'a, 'p> {
    pub ctx: &'c TileCtx<'a>,
    pub tf: TileFrame,
    pub pixels: &'p [TilePixel],
    pub sc: &'p mut TileScratch,
}

impl Kernel for ShadeCutTile<'_, '_, '_> {
    type Out = CutStats;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> CutStats {
        let ShadeCutTile {
            ctx,
            tf,
            pixels,
            sc,
        } = self;
        let cuts = ctx.cuts;
        let tree = &cuts.tree;
        sc.out.clear();
        sc.out.resize(pixels.len(), Vec3::ZERO);
        sc.heap.clear();
        if tree.is_empty() || pixels.is_empty() {
            return CutStats {
                pixels: pixels.len() as u64,
                ..CutStats::default()
            };
        }
        let root = ctx.cluster(&tf, 0);
        let mut total = root.estimate;
        sc.heap.push(root);
        let mut capped = false;
        // Round 1: relative to the central estimate; later rounds: to the smallest pixel.
        let mut threshold: Option<f32> = None;
        for _round in 0..MAX_ROUNDS {
            while let Some(top) = sc.heap.peek() {
                let limit = threshold.unwrap_or(cuts.cut_error * luminance(total));
                if !(top.bound() > limit) {
                    break;
                }
                if sc.heap.len() >= cuts.cut_max {
                    capped = true;
                    break;
                }
                let top = sc.heap.pop().expect("peeked");
                let i = top.node();
                let (l, r) = (
                    ctx.cluster(&tf, tree.left(i)),
                    ctx.cluster(&tf, tree.right(i)),
                );
                total += l.estimate + r.estimate - top.estimate;
                sc.heap.push(l);
                sc.heap.push(r);
            }
            // Shade every pixel with the cut (heap storage order: deterministic).
            sc.dirs.clear();
            sc.irr.clear();
            for c in sc.heap.iter() {
                let i = c.node();
                sc.dirs.push(tree.rep[i]);
                sc.irr.push(tree.irradiance[i]);
            }
            sc.lights.reserve(sc.dirs.len());
            let mut min_lum = f32::INFINITY;
            for (p, out) in pixels.iter().zip(sc.out.iter_mut()) {
                sc.lights.clear();
                for (&d, &e) in sc.dirs.iter().zip(&sc.irr) {
                    let l = p.frame.to_local(d);
                    if l.z > 0.0 {
                        sc.lights.push(l, light_weight(e, l.z, ctx.includes_cosine));
                    }
                }
                *out = ctx.model.sum(s, p.wo, &mut sc.lights);
                min_lum = min_lum.min(luminance(*out));
            }
            let top = sc.heap.peek().map_or(0.0, Cluster::bound);
            let limit = cuts.cut_error * min_lum.max(0.0);
            if capped || !(top > limit) {
                break;
            }
            threshold = Some(limit);
        }
        let n = sc.heap.len() as u64;
        CutStats {
            pixels: pixels.len() as u64,
            clusters: n * pixels.len() as u64,
            largest: n,
            capped: if capped { pixels.len() as u64 } else { 0 },
            tiles: 1,
        }
    }
}

/// Largest spread `a + delta` (radians, module doc) of a square that shares one cut; a
/// square over it is split into its four quarters (down to single pixels), so silhouettes
/// and small images, where normals turn fast, get smaller squares. Measured (640 x 480
/// bench frame, city, Blinn-Phong 200, one release frame): 0.04 rad: 21494 cuts (7.6
/// pixels each), mean cut 295, 2.11 s; 0.08: 8692 cuts, mean 341, 1.53 s; 0.15: 4884 cuts
/// (33 pixels each), mean 372, 1.39 s (per-pixel cuts: 9.9 s, mean 251).
pub const MAX_SPREAD: f32 = 0.15;

/// Shades the square of side `side` at `(x0, y0)` holding `pixels` (module doc), splitting
/// it while its spread exceeds [`MAX_SPREAD`]; `write(pixel, radiance)` gets every pixel
/// once. Returns the cuts' statistics. The squares depend only on pixel positions and the
/// pixels' own frames and views, so the result does not depend on the thread count.
#[allow(clippy::too_many_arguments)]
pub fn shade_square(
    dispatch: Dispatch,
    ctx: &TileCtx<'_>,
    pixels: &mut [TilePixel],
    side: u32,
    x0: u32,
    y0: u32,
    sc: &mut TileScratch,
    write: &mut impl FnMut(&TilePixel, Vec3),
) -> CutStats {
    if pixels.is_empty() {
        return CutStats::default();
    }
    let tf = TileFrame::of(pixels, ctx.material, &ctx.rule);
    if side > 1 && tf.frame_spread + tf.view_spread > MAX_SPREAD {
        let h = side / 2;
        let quarter = |p: &TilePixel| ((p.y - y0 >= h) as u8) * 2 + (p.x - x0 >= h) as u8;
        pixels.sort_by_key(quarter);
        let mut stats = CutStats::default();
        let mut rest = pixels;
        for q in 0..4u8 {
            let n = rest.iter().take_while(|p| quarter(p) == q).count();
            let (these, tail) = rest.split_at_mut(n);
            rest = tail;
            let (qx, qy) = (x0 + h * (q as u32 & 1), y0 + h * (q as u32 >> 1));
            let s = side - h;
            stats = stats + shade_square(dispatch, ctx, these, s, qx, qy, sc, write);
        }
        return stats;
    }
    let stats = dispatch.run(ShadeCutTile {
        ctx,
        tf,
        pixels,
        sc,
    });
    for (p, l) in pixels.iter().zip(&sc.out) {
        write(p, *l);
    }
    stats
}
