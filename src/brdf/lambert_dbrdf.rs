//! Lambert base plus a D-BRDF lobe: `f = rd / pi + c p(h) F(k.h) / (n.k1 + n.k2 - (n.k1)(n.k2))`
//! (thesis 2.2.1 and 2.3.6; Ashikhmin & Premoze 2007), the source model of the library's
//! plastic, synthetic fabric and velvet ([`super::stand_ins`]).
//!
//! Design rule: one type, two constructors for the two half-vector distributions the library
//! uses: [`LambertDbrdf::anisotropic_phong`] (a glossy lobe) and [`LambertDbrdf::velvet`]
//! (an inverted-Gaussian sheen). Both were once separate types (`Velvet` and
//! `LambertDbrdf`) with the same fields and the same `eval`; only the table differs.
//! The D-BRDF denominator stays above `max(n.k1, n.k2)`, so a grazing view has no
//! `1 / cos^2(polar_o)` spike (unlike Ashikhmin-Shirley, see `acquire`'s "Why the view
//! weights").

use super::{Brdf, DBrdf};
use glam::Vec3;

/// `f = rd / pi + lobe(wi, wo)` (module doc), RGB, 1/sr.
#[derive(Clone, Debug)]
pub struct LambertDbrdf {
    /// Diffuse albedo of the base, RGB.
    pub rd: Vec3,
    /// The D-BRDF lobe (glossy highlight or sheen).
    pub lobe: DBrdf,
}

impl LambertDbrdf {
    /// Anisotropic Phong lobe `p(h) ∝ (n.h)^(n_u cos^2(phi_h) + n_v sin^2(phi_h))` (the
    /// Ashikhmin-Shirley lobe in the D-BRDF form; `phi_h` from the tangent as in
    /// [`super::AshikhminShirley`]), tabulated on 32 x 32 half vectors and normalised by
    /// [`DBrdf::from_fn`]. Lobe exponents `nu` (tangent), `nv` (bitangent) >= 0, lobe
    /// `R_s = rs`, base `rd`.
    pub fn anisotropic_phong(nu: f32, nv: f32, rs: Vec3, rd: Vec3) -> Self {
        let lobe = DBrdf::from_fn(32, 32, rs, |h| {
            let s2 = h.x * h.x + h.y * h.y;
            let e = if s2 > 0.0 {
                (nu * h.x * h.x + nv * h.y * h.y) / s2
            } else {
                0.0
            };
            h.z.max(0.0).powf(e)
        });
        LambertDbrdf { rd, lobe }
    }

    /// Velvet: a sheen whose half-vector distribution is an *inverted Gaussian*,
    /// `p(h) ∝ 1 + A exp(-cot^2(polar_h) / sigma^2)`, `A = 4`, `sigma = 0.35`, on a
    /// 32 x 32 table, sheen `R_s = rs`, base `rd` (Ashikhmin, Premoze & Shirley, "A
    /// microfacet-based BRDF generator", SIGGRAPH 2000, the velvet example; the D-BRDF form
    /// is Ashikhmin & Premoze 2007). Fibres standing up from the surface reflect mostly at
    /// grazing half vectors, so the sheen brightens silhouettes (retro and grazing
    /// reflection).
    pub fn velvet(rd: Vec3, rs: Vec3) -> Self {
        let (a, sigma) = (4.0f32, 0.35f32);
        let lobe = DBrdf::from_fn(32, 32, rs, |h| {
            let c2 = h.z * h.z;
            let s2 = (1.0 - c2).max(1e-12);
            1.0 + a * (-(c2 / s2) / (sigma * sigma)).exp()
        });
        LambertDbrdf { rd, lobe }
    }
}

impl Brdf for LambertDbrdf {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.rd * std::f32::consts::FRAC_1_PI + self.lobe.eval(wi, wo)
    }

    fn name(&self) -> &str {
        "lambert-dbrdf"
    }

    fn is_isotropic(&self) -> bool {
        self.lobe.is_isotropic_table()
    }

    /// `rd / pi` plus the D-BRDF part's f64 evaluation.
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return glam::DVec3::ZERO;
        }
        self.rd.as_dvec3() * std::f64::consts::FRAC_1_PI + self.lobe.eval_f64(wi, wo)
    }

    /// `rd / pi` plus the D-BRDF part's bound ([`DBrdf`]'s `max_cosine_weighted`).
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        Some(self.rd * std::f32::consts::FRAC_1_PI + self.lobe.max_cosine_weighted()?)
    }

    /// `rd / pi`, the base.
    fn lambertian_term(&self) -> Vec3 {
        self.rd * std::f32::consts::FRAC_1_PI
    }
}
