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
    let cosine = !brdf.includes_cosine();
    let eye = scene.camera.position.as_dvec3();
    let lights = scene.delta_lights();
    shade_per_pixel(scene, vis, progress, image, pass, |s| {
        let ([t, b, n], wo) = frame_and_view_f64(s, eye, rule);
        let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
        let p = s.position.as_dvec3();
        // The lights above the horizon, a chunk at a time, evaluated at this view together
        // (Brdf::eval_f64_at_view) and summed in the lights' order.
        let mut wi = [DVec3::ZERO; LIGHT_CHUNK];
        let mut irradiance = [DVec3::ZERO; LIGHT_CHUNK];
        let mut f = [DVec3::ZERO; LIGHT_CHUNK];
        let mut sum = DVec3::ZERO;
        for chunk in lights.chunks(LIGHT_CHUNK) {
            let mut above = 0;
            for light in chunk {
                let (l, e) = light.at_f64(p);
                let w = local(l);
                if w.z > 0.0 {
                    wi[above] = w;
                    irradiance[above] = e;
                    above += 1;
                }
            }
            brdf.eval_f64_at_view(wo, &wi[..above], &mut f[..above]);
            for k in 0..above {
                sum += if cosine { f[k] * wi[k].z } else { f[k] } * irradiance[k];
            }
        }
        sum.as_vec3()
    })
}

/// Lights evaluated together per pixel on the f64 path (stack arrays of this many).
const LIGHT_CHUNK: usize = 256;
