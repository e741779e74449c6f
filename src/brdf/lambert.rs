//! Lambertian diffuse reflection (thesis 2.2.1): `f_r = albedo / pi`.

use super::Brdf;
use glam::Vec3;
use std::f32::consts::FRAC_1_PI;

/// Ideal diffuse reflector. `albedo` is the RGB directional-hemispherical reflectance in
/// [0, 1]; values above 1 are accepted but not energy conserving.
#[derive(Clone, Copy, Debug)]
pub struct Lambert {
    pub albedo: Vec3,
}

impl Brdf for Lambert {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * FRAC_1_PI
    }

    fn name(&self) -> &str {
        "lambert"
    }

    /// `albedo / pi` in f64 (zero below either horizon).
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return glam::DVec3::ZERO;
        }
        self.albedo.as_dvec3() * std::f64::consts::FRAC_1_PI
    }

    /// `albedo / pi`: `f_r` is constant and `cos(polar_i) <= 1`.
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        Some(self.albedo * FRAC_1_PI)
    }
}
