//! The f64 path: every light, no culling, frames, directions, the BRDF and the light sum
//! in f64, rounded to f32 once per pixel.
//!
//! Design rule: it restates no shading rule. The surface comes from `gbuffer.rs`, the
//! shading frame from [`ShadingFrame::from_normal`] (widened exactly to f64), the view
//! lifting from [`lift_above_horizon_f64`] (one body with [`super::local_view`]'s) and the
//! point-light falloff from [`crate::light::Light::at_f64`] (one body with
//! [`crate::light::Light::at`]); only the arithmetic differs from the scalar oracle
//! ([`super::shade_reference`]).

use super::{lift_above_horizon_f64, surface_at};
use crate::conventions::ShadingFrame;
use crate::image_io::Image;
use crate::raster::VisBuffer;
use crate::scene::Scene;
use glam::DVec3;
use rayon::prelude::*;

/// The reference render: every light, no culling, the BRDF through
/// [`crate::brdf::Brdf::eval_f64`], frames, directions and the light sum in f64; the result
/// is rounded to f32 once per pixel. Used by `brdfkit render --reference` (with the full
/// probe as the light set) and as the converged reference of the run-time-against-error
/// measurements.
pub fn shade_reference_f64(scene: &Scene, vis: &VisBuffer) -> Image {
    let mut img = Image::new(vis.width, vis.height);
    let brdf = scene.material.as_brdf();
    let eye = scene.camera.position.as_dvec3();
    img.pixels
        .par_chunks_mut(vis.width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, out) in row.iter_mut().enumerate() {
                let Some(s) = surface_at(&scene.mesh, vis, x as u32, y as u32) else {
                    continue;
                };
                let f = ShadingFrame::from_normal(s.normal);
                let (t, b, n) = (f.t.as_dvec3(), f.b.as_dvec3(), f.n.as_dvec3());
                let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
                let p = s.position.as_dvec3();
                let wo = lift_above_horizon_f64(local((eye - p).normalize_or(n)));
                let mut sum = DVec3::ZERO;
                for light in &scene.lights {
                    let (l, e) = light.at_f64(p);
                    let wi = local(l);
                    if wi.z > 0.0 {
                        let f = brdf.eval_f64(wi, wo);
                        sum += if brdf.includes_cosine() { f } else { f * wi.z } * e;
                    }
                }
                *out = sum.as_vec3();
            }
        });
    img
}
