//! The f64 path with no skips: every light, every band, no culling; frames, directions,
//! the BRDF and the light sum in f64, rounded to f32 once per pixel.
//!
//! Design rule: it restates no shading rule. The surface comes from `gbuffer.rs`, the
//! shading frame from [`crate::conventions::ShadingFrame::from_normal`] (widened exactly to
//! f64, then turned in f64 under the material's [`FrameRule`]: [`super::frame_and_view_f64`]),
//! the view lifting from [`super::lift_above_horizon_f64`] (one body with
//! [`super::local_view`]'s) and the
//! point-light falloff from [`crate::light::Light::at_f64`] (one body with
//! [`crate::light::Light::at`]); only the arithmetic (and the skips) differ from the scalar
//! oracle (`scalar_oracle.rs`). The tile loop is the one the scalar oracle uses
//! (`tile.rs`).

use super::frame_and_view_f64;
use super::tile::{shade_per_pixel, Pass};
use crate::conventions::FrameRule;
use crate::image_io::Image;
use crate::progress::Progress;
use crate::raster::VisBuffer;
use crate::scene::Scene;
use glam::DVec3;

/// The f64 path with no skips ([`super::ShadingPath::F64NoSkips`]): every light of the
/// scene (none dropped), every SH band, no culling; the BRDF through
/// [`crate::brdf::Brdf::eval_f64`], frames, directions and the light sum in f64, the result
/// rounded to f32 once per pixel, into `image` (of `vis`'s size; every pixel rewritten); every tile counted into `progress`. On a scene whose light
/// set is the full probe this is the converged reference (`brdfkit render --reference`, the
/// golden bounds, the sweep's error measurements).
pub(super) fn shade_f64_no_skips(
    scene: &Scene,
    vis: &VisBuffer,
    progress: &Progress,
    rule: &FrameRule,
    image: &mut Image,
    pass: Pass,
) {
    let brdf = scene.material.as_brdf();
    let eye = scene.camera.position.as_dvec3();
    let lights = scene.delta_lights();
    shade_per_pixel(scene, vis, progress, image, pass, |s| {
        let ([t, b, n], wo) = frame_and_view_f64(s, eye, rule);
        let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
        let p = s.position.as_dvec3();
        let mut sum = DVec3::ZERO;
        for light in lights.iter() {
            let (l, e) = light.at_f64(p);
            let wi = local(l);
            if wi.z > 0.0 {
                let f = brdf.eval_f64(wi, wo);
                sum += if brdf.includes_cosine() { f } else { f * wi.z } * e;
            }
        }
        sum.as_vec3()
    })
}
