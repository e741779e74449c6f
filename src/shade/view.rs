//! The view direction in the shading frame, lifted above the horizon.
//!
//! Design rule: one definition of the lifting for both arithmetics. Interpolated normals
//! can face slightly away from the camera at silhouettes, and a BRDF is not defined below
//! the horizon, so the local view direction is clamped to at least [`MIN_VIEW_COS`] above
//! it, keeping its azimuth (src/conventions/mod.rs, "view direction"). The f32 form
//! ([`lift_above_horizon`], through [`local_view`]) serves the kernels and the scalar
//! oracle; the f64 form ([`lift_above_horizon_f64`]) serves the f64 path
//! (`f64_path.rs`). Both are expanded from the one body in
//! `lift_above_horizon!`, each in its own arithmetic (the f32 form rounds in f32, as the
//! fast path always has).

use super::Surface;
use crate::conventions::{FrameRule, ShadingFrame, VIEW_TURN_MIN_SIN};
use glam::{DVec3, Vec3};

/// Smallest cosine between the view direction and the normal used for shading.
pub const MIN_VIEW_COS: f32 = 1e-3;

/// The body of [`lift_above_horizon`] and [`lift_above_horizon_f64`]: `$wo` (a local
/// direction of vector type `$V`, scalar type `$S`) unchanged when its z is at least
/// [`MIN_VIEW_COS`]; otherwise the direction of the same azimuth at exactly that cosine,
/// or the normal (+z) when the azimuth is undefined (x = y = 0).
macro_rules! lift_above_horizon {
    ($wo:expr, $V:ident, $S:ty) => {{
        let wo: $V = $wo;
        let c = MIN_VIEW_COS as $S;
        if wo.z < c {
            let h = (wo.x * wo.x + wo.y * wo.y).sqrt();
            let s = (1.0 - c * c).sqrt();
            if h > 0.0 {
                $V::new(wo.x / h * s, wo.y / h * s, c)
            } else {
                $V::Z
            }
        } else {
            wo
        }
    }};
}

/// A local view direction (unit, local +z the normal) lifted to at least [`MIN_VIEW_COS`]
/// above the horizon, its azimuth kept; f32 arithmetic.
#[inline]
pub fn lift_above_horizon(wo: Vec3) -> Vec3 {
    lift_above_horizon!(wo, Vec3, f32)
}

/// [`lift_above_horizon`] in f64 arithmetic (the f64 path).
#[inline]
pub fn lift_above_horizon_f64(wo: DVec3) -> DVec3 {
    lift_above_horizon!(wo, DVec3, f64)
}

/// Local view direction at a surface: `local_from_world(v)`, lifted above the horizon.
#[inline]
pub fn local_view(frame: &ShadingFrame, surface: &Surface, eye: Vec3) -> Vec3 {
    let v = (eye - surface.position).normalize_or(frame.n);
    lift_above_horizon(frame.to_local(v))
}

/// The shading frame of a surface under `rule` ([`FrameRule::apply`] of
/// [`FrameRule::base`]: [`ShadingFrame::from_normal`], or the mesh tangent's frame, turned
/// by the unit world view) and the local view in it,
/// lifted above the horizon ([`local_view`]). Under [`FrameRule::UP`] these are exactly
/// `from_normal` and [`local_view`]'s bits.
#[inline]
pub fn frame_and_view(surface: &Surface, eye: Vec3, rule: &FrameRule) -> (ShadingFrame, Vec3) {
    let base = rule.base(surface.normal, surface.tangent);
    let v = (eye - surface.position).normalize_or(base.n);
    let frame = rule.apply(base, v);
    (frame, lift_above_horizon(frame.to_local(v)))
}

/// The f64 path's frame under `rule` ([`frame_and_view`] in f64): the f32 base frame
/// (scrambled when the rule says so) widened exactly, turned in f64 to the view's azimuth,
/// and the lifted f64 local view. Returns the frame's axes `(t, b, n)` and the view.
#[inline]
pub fn frame_and_view_f64(surface: &Surface, eye: DVec3, rule: &FrameRule) -> ([DVec3; 3], DVec3) {
    let unturned = FrameRule {
        view_azimuth: None,
        ..*rule
    };
    let f = unturned.apply(rule.base(surface.normal, surface.tangent), Vec3::Z);
    let (mut t, mut b, n) = (f.t.as_dvec3(), f.b.as_dvec3(), f.n.as_dvec3());
    let v = (eye - surface.position.as_dvec3()).normalize_or(n);
    if let Some((c, s)) = rule.view_azimuth {
        let (x, y) = (v.dot(t), v.dot(b));
        let h = (x * x + y * y).sqrt();
        if h > VIEW_TURN_MIN_SIN as f64 {
            let (cp, sp) = (x / h, y / h);
            let (c, s) = (c as f64, s as f64);
            let (ct, st) = (cp * c + sp * s, sp * c - cp * s);
            (t, b) = (t * ct + b * st, b * ct - t * st);
        }
    }
    let wo = DVec3::new(v.dot(t), v.dot(b), v.dot(n));
    ([t, b, n], lift_above_horizon_f64(wo))
}
