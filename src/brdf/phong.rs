//! Phong (thesis 2.2.2, Def. 3) written as an energy-normalised, reciprocal BRDF.
//!
//! The thesis's shading sum is `k_d (L.N) i_d + k_s (R.V)^alpha i_s` (ambient left out:
//! environment light replaces it). As a BRDF this is the "modified Phong" model
//! (Lewis, "Making shaders more physically plausible", 1994; Lafortune & Willems 1994):
//! `f_r = k_d / pi + k_s (alpha + 2) / (2 pi) max(0, r.wo)^alpha`, with
//! `r = (-wi.x, -wi.y, wi.z)` the mirror of `wi` about the normal (local +z).
//! Normalisation: `(alpha + 2)/(2 pi)` makes the specular lobe's directional albedo exactly
//! `k_s` at normal incidence (`integral cos^alpha(a) cos(a) dω = 2 pi/(alpha + 2)`) and at
//! most `k_s` elsewhere, so `k_d + k_s <= 1` conserves energy. `r.wo = wi.r'` with `r'` the
//! mirror of `wo`, so the model is reciprocal. `(L.N)` is the cosine the renderer applies.

use super::real::{Scalar, Vector3};
use super::Brdf;
use glam::Vec3;
use std::f32::consts::PI;

/// Phong with a Lambert diffuse term. `kd`, `ks` RGB in [0, 1] (`kd + ks <= 1` for energy
/// conservation), `exponent` alpha >= 0. Never fails: zero below the horizon.
#[derive(Clone, Copy, Debug)]
pub struct Phong {
    pub kd: Vec3,
    pub ks: Vec3,
    pub exponent: f32,
}

impl Phong {
    /// The formula (module doc) in the precision of `V` (mirror direction, `powf`,
    /// normalisation): the one body of [`Brdf::eval`] and [`Brdf::eval_f64`]
    /// ([`super::real`]).
    #[inline]
    pub fn f<V: Vector3>(&self, wi: V, wo: V) -> V {
        if wi.z() <= V::S::ZERO || wo.z() <= V::S::ZERO {
            return V::ZERO;
        }
        let (pi, a) = (V::S::PI, V::S::from_f32(self.exponent));
        let two = V::S::lit(2.0);
        let r = V::new(-wi.x(), -wi.y(), wi.z());
        let rv = r.dot(wo).max(V::S::ZERO);
        let spec = (a + two) / (two * pi) * rv.powf(a);
        V::from_vec3(self.kd) / pi + V::from_vec3(self.ks) * spec
    }
}

impl Brdf for Phong {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.f(wi, wo)
    }

    fn is_isotropic(&self) -> bool {
        true
    }

    fn name(&self) -> &str {
        "phong"
    }

    /// The same formula in f64 (mirror direction, `powf`, normalisation).
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        self.f(wi, wo)
    }

    /// `k_d / pi + k_s (alpha + 2) / (2 pi)`: `max(0, r.wo)^alpha <= 1`, `cos(polar_i) <= 1`.
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        Some(self.kd / PI + self.ks * ((self.exponent + 2.0) / (2.0 * PI)))
    }

    /// `k_d / pi`.
    fn lambertian_term(&self) -> Vec3 {
        self.kd / PI
    }
}
