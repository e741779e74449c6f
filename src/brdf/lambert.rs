//! Lambertian diffuse reflection (thesis 2.2.1): `f_r = albedo / pi`.

use super::real::{Scalar, Vector3};
use super::Brdf;
use glam::Vec3;
use std::f32::consts::FRAC_1_PI;

/// Ideal diffuse reflector. `albedo` is the RGB directional-hemispherical reflectance in
/// [0, 1]; values above 1 are accepted but not energy conserving.
#[derive(Clone, Copy, Debug)]
pub struct Lambert {
    pub albedo: Vec3,
}

impl Lambert {
    /// `albedo / pi` (zero below either horizon), in the precision of `V`: the one body of
    /// [`Brdf::eval`] and [`Brdf::eval_f64`] ([`super::real`]).
    #[inline]
    pub fn f<V: Vector3>(&self, wi: V, wo: V) -> V {
        if wi.z() <= V::S::ZERO || wo.z() <= V::S::ZERO {
            return V::ZERO;
        }
        V::from_vec3(self.albedo) * V::S::FRAC_1_PI
    }
}

impl Brdf for Lambert {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.f(wi, wo)
    }

    fn is_isotropic(&self) -> bool {
        true
    }

    fn name(&self) -> &str {
        "lambert"
    }

    /// `albedo / pi` in f64 (zero below either horizon).
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        self.f(wi, wo)
    }

    /// `albedo / pi`: `f_r` is constant and `cos(polar_i) <= 1`.
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        Some(self.albedo * FRAC_1_PI)
    }

    /// `albedo / pi`: all of it.
    fn lambertian_term(&self) -> Vec3 {
        self.albedo * FRAC_1_PI
    }
}
