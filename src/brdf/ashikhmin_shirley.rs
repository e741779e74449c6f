//! Ashikhmin-Shirley anisotropic Phong BRDF (thesis 2.3.5; Ashikhmin & Shirley, "An
//! anisotropic Phong BRDF model", J. Graphics Tools 5(2), 2000).
//!
//! `f = p_s + p_d` with `k1 = wi`, `k2 = wo`, `h = normalize(k1 + k2)`, `n` = local +z:
//! * `p_s = sqrt((n_u + 1)(n_v + 1)) / (8 pi) * (n.h)^e / ((h.k) max(n.k1, n.k2)) * F(k.h)`,
//!   `e = n_u cos^2(phi_h) + n_v sin^2(phi_h) = (n_u h_x^2 + n_v h_y^2) / (1 - h_z^2)`,
//!   where `phi_h` is the azimuth of `h` in the local frame measured from local +x (the
//!   tangent of [`crate::conventions::ShadingFrame`]: world up projected), so `n_u` is the
//!   exponent along the tangent and `n_v` along the bitangent. At `h = n` the exponent is
//!   irrelevant (`(n.h)^e = 1`).
//! * `F(k.h) = R_s + (1 - R_s)(1 - k.h)^5` (Schlick); `k.h` is the same for k1 and k2.
//! * `p_d = 28 R_d / (23 pi) (1 - R_s) (1 - (1 - n.k1/2)^5) (1 - (1 - n.k2/2)^5)`.
//!
//! Both terms are symmetric in (k1, k2), so the model is reciprocal. Ashikhmin & Shirley
//! derive `p_d` so that the sum conserves energy for `R_s, R_d` in [0, 1]; the tests check
//! directional albedo <= 1 by quadrature for such parameters.

use super::real::{Scalar, Vector3};
use super::Brdf;
use glam::Vec3;

/// Parameters: `nu`, `nv` >= 0 lobe exponents (tangent, bitangent), `rs` specular and `rd`
/// diffuse RGB reflectance in [0, 1]. Never fails: zero below the horizon.
#[derive(Clone, Copy, Debug)]
pub struct AshikhminShirley {
    pub nu: f32,
    pub nv: f32,
    pub rs: Vec3,
    pub rd: Vec3,
}

/// Schlick's Fresnel approximation `R_s + (1 - R_s)(1 - c)^5` for `c = k.h` in [0, 1].
#[inline]
pub fn schlick_fresnel<V: Vector3>(rs: V, c: V::S) -> V {
    let m = (V::S::ONE - c.clamp(V::S::ZERO, V::S::ONE)).powi(5);
    rs + (V::ONE - rs) * m
}

impl AshikhminShirley {
    /// The formula (module doc) in the precision of `V`, with its guards: the one body of
    /// [`Brdf::eval`] and [`Brdf::eval_f64`] ([`super::real`]).
    #[inline]
    pub fn f<V: Vector3>(&self, wi: V, wo: V) -> V {
        let (zero, one) = (V::S::ZERO, V::S::ONE);
        if wi.z() <= zero || wo.z() <= zero {
            return V::ZERO;
        }
        let (rs, rd) = (V::from_vec3(self.rs), V::from_vec3(self.rd));
        let (nu, nv) = (V::S::from_f32(self.nu), V::S::from_f32(self.nv));
        let (half, eps) = (V::S::lit(0.5), V::S::lit(1e-6));
        let (n1, n2) = (wi.z().min(one), wo.z().min(one));
        let d = rd
            * (V::S::lit(28.0) / (V::S::lit(23.0) * V::S::PI))
            * (V::ONE - rs)
            * (one - (one - half * n1).powi(5))
            * (one - (one - half * n2).powi(5));
        // `k.h = |k1 + k2| / 2` for unit k1, k2: symmetric in floating point (k1 + k2 is
        // computed identically both ways), unlike `k1.h`, which breaks reciprocity near
        // grazing opposite directions.
        let sum = wi + wo;
        let len = sum.length();
        if len <= eps {
            return d;
        }
        let h = sum / len;
        let kh = (half * len).clamp(eps, one);
        let s2 = h.x() * h.x() + h.y() * h.y();
        let e = if s2 > zero {
            (nu * h.x() * h.x() + nv * h.y() * h.y()) / s2
        } else {
            zero
        };
        let norm = ((nu + one) * (nv + one)).sqrt() / (V::S::lit(8.0) * V::S::PI);
        let spec = norm * h.z().max(zero).powf(e) / (kh * n1.max(n2));
        d + schlick_fresnel(rs, kh) * spec
    }
}

impl Brdf for AshikhminShirley {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.f(wi, wo)
    }

    fn name(&self) -> &str {
        "ashikhmin-shirley"
    }

    fn is_isotropic(&self) -> bool {
        self.nu == self.nv
    }

    /// The same formula (module doc) in f64, with the same guards ([`AshikhminShirley::f`]).
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        self.f(wi, wo)
    }
}
