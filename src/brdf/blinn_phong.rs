//! Blinn-Phong (thesis Def. 4), written as an energy-normalised BRDF.
//!
//! The thesis gives the shading sum `k_d (L.N) i_d + k_s (N.H)^alpha i_s` (ambient left
//! out: environment light replaces it). As a BRDF that is
//! `f_r = k_d / pi + k_s (alpha + 8) / (8 pi) (n.h)^alpha`, the common normalisation of the
//! specular lobe (Akenine-Moeller et al., Real-Time Rendering, 3rd ed., 7.6) that keeps the
//! lobe's peak albedo close to `k_s` for every exponent; `(L.N)` is the cosine the renderer
//! applies. `h = normalize(wi + wo)`.

use super::real::{Scalar, Vector3};
use super::Brdf;
use glam::Vec3;
use std::f32::consts::PI;

/// Blinn-Phong with a Lambert diffuse term. `kd`, `ks` are RGB in [0, 1] with
/// `kd + ks <= 1` for energy conservation; `exponent` (alpha) >= 0.
#[derive(Clone, Copy, Debug)]
pub struct BlinnPhong {
    pub kd: Vec3,
    pub ks: Vec3,
    pub exponent: f32,
}

impl BlinnPhong {
    /// The formula (module doc) in the precision of `V` (half vector, `powf`,
    /// normalisation): the one body of [`Brdf::eval`] and [`Brdf::eval_f64`]
    /// ([`super::real`]).
    #[inline]
    pub fn f<V: Vector3>(&self, wi: V, wo: V) -> V {
        if wi.z() <= V::S::ZERO || wo.z() <= V::S::ZERO {
            return V::ZERO;
        }
        let (pi, a) = (V::S::PI, V::S::from_f32(self.exponent));
        let eight = V::S::lit(8.0);
        let h = (wi + wo).normalize_or_zero();
        let nh = h.z().max(V::S::ZERO);
        let spec = (a + eight) / (eight * pi) * nh.powf(a);
        V::from_vec3(self.kd) / pi + V::from_vec3(self.ks) * spec
    }
}

impl Brdf for BlinnPhong {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.f(wi, wo)
    }

    fn is_isotropic(&self) -> bool {
        true
    }

    fn name(&self) -> &str {
        "blinn-phong"
    }

    /// The same formula in f64 (half vector, `powf`, normalisation).
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        self.f(wi, wo)
    }

    /// `k_d / pi + k_s (alpha + 8) / (8 pi)`: `(n.h)^alpha <= 1` and `cos(polar_i) <= 1`
    /// (reached at `wi = wo = n`).
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        Some(self.kd / PI + self.ks * ((self.exponent + 8.0) / (8.0 * PI)))
    }

    /// `k_d / pi`.
    fn lambertian_term(&self) -> Vec3 {
        self.kd / PI
    }
}
