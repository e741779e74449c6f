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

use super::Brdf;
use glam::Vec3;
use std::f32::consts::PI;

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
pub fn schlick_fresnel(rs: Vec3, c: f32) -> Vec3 {
    let m = (1.0 - c.clamp(0.0, 1.0)).powi(5);
    rs + (Vec3::ONE - rs) * m
}

impl Brdf for AshikhminShirley {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        let (n1, n2) = (wi.z.min(1.0), wo.z.min(1.0));
        let d = (28.0 / (23.0 * PI))
            * self.rd
            * (Vec3::ONE - self.rs)
            * (1.0 - (1.0 - 0.5 * n1).powi(5))
            * (1.0 - (1.0 - 0.5 * n2).powi(5));
        // `k.h = |k1 + k2| / 2` for unit k1, k2: symmetric in floating point (k1 + k2 is
        // computed identically both ways), unlike `k1.h`, which breaks reciprocity near
        // grazing opposite directions.
        let sum = wi + wo;
        let len = sum.length();
        if len <= 1e-6 {
            return d;
        }
        let h = sum / len;
        let kh = (0.5 * len).clamp(1e-6, 1.0);
        let s2 = h.x * h.x + h.y * h.y;
        let e = if s2 > 0.0 {
            (self.nu * h.x * h.x + self.nv * h.y * h.y) / s2
        } else {
            0.0
        };
        let norm = ((self.nu + 1.0) * (self.nv + 1.0)).sqrt() / (8.0 * PI);
        let spec = norm * h.z.max(0.0).powf(e) / (kh * n1.max(n2));
        d + spec * schlick_fresnel(self.rs, kh)
    }

    fn name(&self) -> &str {
        "ashikhmin-shirley"
    }

    /// The same formula (module doc) in f64, with the same guards.
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        use glam::DVec3;
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return DVec3::ZERO;
        }
        let pi = std::f64::consts::PI;
        let (rs, rd) = (self.rs.as_dvec3(), self.rd.as_dvec3());
        let (nu, nv) = (self.nu as f64, self.nv as f64);
        let (n1, n2) = (wi.z.min(1.0), wo.z.min(1.0));
        let d = (28.0 / (23.0 * pi))
            * rd
            * (DVec3::ONE - rs)
            * (1.0 - (1.0 - 0.5 * n1).powi(5))
            * (1.0 - (1.0 - 0.5 * n2).powi(5));
        let sum = wi + wo;
        let len = sum.length();
        if len <= 1e-6 {
            return d;
        }
        let h = sum / len;
        let kh = (0.5 * len).clamp(1e-6, 1.0);
        let s2 = h.x * h.x + h.y * h.y;
        let e = if s2 > 0.0 {
            (nu * h.x * h.x + nv * h.y * h.y) / s2
        } else {
            0.0
        };
        let norm = ((nu + 1.0) * (nv + 1.0)).sqrt() / (8.0 * pi);
        let spec = norm * h.z.max(0.0).powf(e) / (kh * n1.max(n2));
        let fresnel = rs + (DVec3::ONE - rs) * (1.0 - kh).powi(5);
        d + spec * fresnel
    }
}
