//! Distribution-based BRDF, D-BRDF (thesis 2.3.6; Ashikhmin & Premoze, "Distribution-based
//! BRDFs", technical report, University of Utah, 2007).
//!
//! `f(k1, k2) = c p(h) F(k.h) / ((k1.n) + (k2.n) - (k1.n)(k2.n))` with `k1 = wi`, `k2 = wo`,
//! `h = normalize(k1 + k2)`, `n` = local +z, `F` Schlick's Fresnel with RGB `R_s`
//! ([`super::ashikhmin_shirley::schlick_fresnel`]), `k.h = k1.h = k2.h`. The formula is
//! symmetric in k1, k2, so the model is reciprocal for any table.
//!
//! # The half-vector table p(h)
//! A hemispherical table over the *half vector* in the local frame, with exactly the
//! texel convention of [`crate::conventions`]: `s = azimuth_h / 2 pi` (from local +x,
//! wraps), `t = polar_h / (pi/2)` (clamps), texel `(i, j)` centred at
//! `((i+1/2)/nu, (j+1/2)/nv)`, values `p[j * nu + i]`, looked up with `GL_LINEAR`
//! semantics ([`crate::conventions::hemi_bilinear_texels`]).
//!
//! # Normalisation (what was verified, what is assumed)
//! Verified (from the thesis and the report's abstract, which the search tool returned):
//! the formula above, that `p(h)` is a distribution over half vectors covering the
//! hemisphere, that `c` is a fitted constant, and that the report fits the model to
//! measured data by a simplified measurement. Not verified (the report's body was not
//! available): its exact normalisation of `p` and value of `c`. **Assumed** here, following
//! microfacet practice: `p` is normalised over projected area,
//! `integral_{H} p(h) (h.n) dω_h = 1` ([`DBrdf::normalize_projected`] enforces it on the
//! table by exact texel solid angles), and `c = 1/4` (the microfacet Jacobian
//! `dω_h / dω_i = 1 / (4 k.h)`). With these, energy conservation follows: the directional
//! albedo is `integral 4 c p(h) F (k2.h) (k1.n) / D dω_h <= integral p(h) (k2.h)^+ dω_h <= 1`
//! because `D >= max(k1.n, k2.n)`; the tests check it by quadrature.
//! Fitting from data ([`DBrdf::from_backscatter`]) uses the backscatter slice `k1 = k2 = h`
//! (where `D = 2 h.n - (h.n)^2` and `F = F(1) = R_s`): `p(h) = f(h, h) D / (c R_s)`, then
//! renormalised; this is our reading of the report's "simplified way of measuring".

use super::ashikhmin_shirley::schlick_fresnel;
use super::Brdf;
use crate::conventions::{
    hemi_bilinear_texels, hemi_texcoord, hemi_texel_angles_f64, hemi_texel_solid_angle,
    local_angles, local_direction_f64,
};
use glam::Vec3;

/// D-BRDF with a tabulated half-vector distribution (see the module doc).
#[derive(Clone, Debug)]
pub struct DBrdf {
    nu: usize,
    nv: usize,
    p: Vec<f32>,
    /// Fresnel reflectance at normal incidence, RGB in [0, 1].
    pub rs: Vec3,
    /// The constant `c` (1/4 with the projected-area normalisation of `p`).
    pub c: f32,
}

impl DBrdf {
    /// From a table `p[j * nu + i]` (not renormalised). Panics if `nu` or `nv` is zero, the
    /// length is not `nu * nv`, or a value is negative or non-finite.
    pub fn new(nu: usize, nv: usize, p: Vec<f32>, rs: Vec3) -> Self {
        assert!(nu > 0 && nv > 0, "empty D-BRDF table");
        assert_eq!(p.len(), nu * nv, "D-BRDF table size");
        assert!(
            p.iter().all(|v| v.is_finite() && *v >= 0.0),
            "D-BRDF table values must be finite and >= 0"
        );
        DBrdf {
            nu,
            nv,
            p,
            rs,
            c: 0.25,
        }
    }

    /// Tabulates `p(h)` from a function of the local half vector at texel centres, then
    /// normalises it ([`DBrdf::normalize_projected`]). Panics as [`DBrdf::new`].
    pub fn from_fn(nu: usize, nv: usize, rs: Vec3, p: impl Fn(Vec3) -> f32) -> Self {
        let mut t = Vec::with_capacity(nu * nv);
        for j in 0..nv {
            for i in 0..nu {
                let (pol, az) = hemi_texel_angles_f64(i, j, nu, nv);
                t.push(p(local_direction_f64(pol, az).as_vec3()));
            }
        }
        let mut d = DBrdf::new(nu, nv, t, rs);
        d.normalize_projected();
        d
    }

    /// Fits `p(h)` from the backscatter slice of any BRDF (module doc), using the mean of
    /// the RGB channels and `R_s`. Panics as [`DBrdf::new`] (e.g. if the source is negative).
    pub fn from_backscatter(src: &dyn Brdf, nu: usize, nv: usize, rs: Vec3) -> Self {
        let f1 = rs.x.max(rs.y).max(rs.z).max(1e-6);
        DBrdf::from_fn(nu, nv, rs, |h| {
            let v = src.eval(h, h);
            let f = if src.includes_cosine() {
                v / h.z.max(1e-6)
            } else {
                v
            };
            let n = h.z;
            (f.element_sum() / 3.0) * (2.0 * n - n * n) / (0.25 * f1)
        })
    }

    /// Rescales the table so that `sum_texels p (cos polar_centre) solid_angle = 1`, the
    /// discrete form of `integral p(h) (h.n) dω_h = 1`. A zero table is left unchanged.
    pub fn normalize_projected(&mut self) {
        let mut s = 0.0f64;
        for j in 0..self.nv {
            let (pol, _) = hemi_texel_angles_f64(0, j, self.nu, self.nv);
            let w = pol.cos() * hemi_texel_solid_angle(j, self.nu, self.nv);
            for i in 0..self.nu {
                s += self.p[j * self.nu + i] as f64 * w;
            }
        }
        if s > 0.0 {
            for v in &mut self.p {
                *v = (*v as f64 / s) as f32;
            }
        }
    }

    /// `(nu, nv)` of the half-vector table.
    pub fn grid(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// The table (layout in the module doc).
    pub fn table(&self) -> &[f32] {
        &self.p
    }

    /// `p(h)` by bilinear (GL_LINEAR) lookup at the local half vector `h`.
    pub fn p(&self, h: Vec3) -> f32 {
        let (pol, az) = local_angles(h);
        let (s, t) = hemi_texcoord(pol, az);
        hemi_bilinear_texels(s, t, self.nu, self.nv)
            .iter()
            .map(|&(i, j, w)| w * self.p[j * self.nu + i])
            .sum()
    }
}

impl Brdf for DBrdf {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        // `k.h = |k1 + k2| / 2` (unit k1, k2), exactly symmetric in floating point.
        let sum = wi + wo;
        let len = sum.length();
        if len <= 1e-6 {
            return Vec3::ZERO;
        }
        let h = sum / len;
        let (a, b) = (wi.z.min(1.0), wo.z.min(1.0));
        let denom = a + b - a * b;
        let kh = (0.5 * len).clamp(0.0, 1.0);
        self.c * self.p(h) * schlick_fresnel(self.rs, kh) / denom
    }

    fn name(&self) -> &str {
        "d-brdf"
    }

    /// `c max(p) max(1, R_s)`: the bilinear `p(h)` is a convex blend of table values, so at
    /// most the table's largest; Schlick's `F` lies between `R_s` and 1; and
    /// `cos(polar_i) / D <= 1` because `D = a + b - a b = a + b (1 - a) >= a = cos(polar_i)`.
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        let pmax = self.p.iter().copied().fold(0.0f32, f32::max);
        Some(self.c * pmax * self.rs.max(Vec3::ONE))
    }

    fn lane_model(&self) -> Option<crate::kernel::models::LaneModel<'_>> {
        Some(crate::kernel::models::LaneModel::DBrdf(self))
    }
}
