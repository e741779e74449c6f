//! The scalar f32 oracle: the plain per-light loop over [`Brdf::eval`], in f32, that the
//! kernels are tested against.
//!
//! Design rule: no kernel, no lanes, no culling, nothing shared with the fast path but the
//! surface (`gbuffer.rs`), the view lifting ([`super::local_view`]) and the frame's
//! per-scene decisions ([`FramePrep::new`]), so the two differ only by the kernel's
//! arithmetic.

use super::tile::{shade_per_pixel, Pass};
use super::{frame_and_view, FramePrep, Surface};
use crate::brdf::{eval_cosine_weighted, Brdf};
use crate::conventions::FrameRule;
use crate::image_io::Image;
use crate::kernel::skip::needs_restore;
use crate::light::Light;
use crate::progress::Progress;
use crate::raster::VisBuffer;
use crate::scene::Scene;
use glam::Vec3;

/// Reflected radiance at one surface point: `sum_k f(l_k, v) cos E_k` (thesis Def. 10), in
/// the shading frame of `rule` ([`crate::material::Material::frame_rule`], the frame's
/// [`FramePrep::rule`]). `lights` is the frame's light set (the scene's, less any dropped
/// as negligible).
#[inline]
pub fn shade_point(
    brdf: &dyn Brdf,
    lights: &[Light],
    surface: &Surface,
    eye: Vec3,
    rule: &FrameRule,
) -> Vec3 {
    let (frame, wo) = frame_and_view(surface, eye, rule);
    let mut sum = Vec3::ZERO;
    for light in lights {
        let (l, e) = light.at(surface.position);
        let wi = frame.to_local(l);
        if wi.z > 0.0 {
            sum += eval_cosine_weighted(brdf, wi, wo) * e;
        }
    }
    sum
}

/// The scalar oracle ([`super::ShadingPath::ScalarOracle`]): [`shade_point`] at every
/// visible pixel of `image` (of `vis`'s size; every pixel rewritten), no kernel, no culling; every tile counted into `progress`.
///
/// It shades what the fast path shades: the light set and SH bands that `prep` kept, plus
/// the dropped lights at the pixels [`needs_restore`] picks (dropping negligible lights and
/// bands is a decision about the scene, bounded in [`crate::kernel::skip`], not about the
/// kernel), so the two differ only by the kernel's arithmetic. The f64 path (`f64_path.rs`) is the other check: every light, every band, f64.
pub(super) fn shade_scalar_oracle(
    prep: &FramePrep,
    scene: &Scene,
    vis: &VisBuffer,
    progress: &Progress,
    image: &mut Image,
    pass: Pass,
) {
    let brdf: &dyn Brdf = match &prep.sh {
        Some((ds, _)) => ds.as_ref(),
        None => scene.material.as_brdf(),
    };
    let d = &prep.dropped;
    shade_per_pixel(scene, vis, progress, image, pass, |s| {
        let kept = shade_point(brdf, &d.kept, s, scene.camera.position, &prep.rule);
        if !d.removed.is_empty() && needs_restore(kept, d.restore_below(s.normal)) {
            kept + shade_point(brdf, &d.removed, s, scene.camera.position, &prep.rule)
        } else {
            kept
        }
    })
}
