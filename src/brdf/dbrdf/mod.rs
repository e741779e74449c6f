//! Distribution-based BRDF, D-BRDF (thesis 2.3.6; Ashikhmin & Premoze, "Distribution-based
//! BRDFs", technical report, University of Utah, 2007).
//!
//! `f(k1, k2) = c p(h) F(k.h) / ((k1.n) + (k2.n) - (k1.n)(k2.n))` with `k1 = wi`, `k2 = wo`,
//! `h = normalize(k1 + k2)`, `n` = local +z, `F` Schlick's Fresnel with RGB `R_s`
//! ([`super::ashikhmin_shirley::schlick_fresnel`]), `k.h = k1.h = k2.h`. The formula is
//! symmetric in k1, k2, so the model is reciprocal for any table.
//!
//! (Past 400 lines because most of it is the derivation of the normalisation and of the
//! derived lookup, which the model's code follows step by step: one concept, one file; the
//! weights, the file format and the tests are in files of their own.)
//!
//! # The half-vector table p(h)
//! A hemispherical table over the *half vector* in the local frame, with exactly the
//! texel convention of [`crate::conventions`]: `s = azimuth_h / 2 pi` (from local +x,
//! wraps), `t = polar_h / (pi/2)` (clamps), texel `(i, j)` centred at
//! `((i+1/2)/nu, (j+1/2)/nv)`, values `p[j * nu + i]`, looked up with `GL_LINEAR`
//! semantics ([`crate::conventions::hemi_bilinear_texels`]).
//!
//! # The lookup the renderer evaluates (derived octahedral table)
//! The file's (polar, azimuth) table needs `acos` and `atan2` per lookup. [`DBrdf::new`]
//! therefore derives a second table, `n x n` over the half vector's hemispherical
//! octahedral coordinates `(u, v) = (s.x + s.y, s.x - s.y) / (|s.x| + |s.y| + s.z)` of any
//! positive multiple `s` of `h` (`wi + wo` itself: one division, no square root, no
//! trigonometry; map, texel centres and clamp-to-edge rule in [`crate::conventions`],
//! "Octahedral hemisphere tables"). Its texels are the file table's `GL_LINEAR` lookup at
//! the texel centres' directions (f64 angles, [`DBrdf::file_p_f64`]), times one scale `k`
//! that gives the derived function the file function's projected integral
//! `integral p(h) (h.n) dω_h` (the file's closed form below against a quadrature of the
//! derived table's bilinear weights, [`octahedral_projected_weights`]: a midpoint rule on
//! 8 x 8 cells per texel whose weights are rescaled to sum to exactly `pi`, so a constant
//! table keeps its value exactly; a random 12 x 6 table's derived function integrates to
//! 1 + 2.4e-6 by an independent 1200 x 2400 rule). `k` is 1 - 2e-4 (lindt-paper fit),
//! 1 - 5e-4 (the golden 16 x 8 file). **What the renderer evaluates is the derived
//! lookup**: [`DBrdf::p`] (the scalar oracle, [`Brdf::eval`], [`Brdf::eval_f64`]'s weights)
//! and the lane kernel (`kernel::models`) run the same texel arithmetic; the file table is
//! kept as read and written ([`mod@file`] is unchanged), and the GPU shader still samples
//! the file table (a difference within the numbers below).
//!
//! Side `n` ([`DBrdf::octahedral_side`]): the smallest power of two `>= 2 max(nu, 4 nv)`
//! (16 to 512; 256 for the 64 x 32 library fit and the 32 x 32 lobes, 64 for a 16 x 8
//! file). Along a polar great circle the map advances between `n/4` and `n/2` texels per
//! radian, the file `2 nv / pi`, so the derived table has at least 3 texels per file
//! texel in polar everywhere and more in azimuth; the resampling error falls as `1/n^2`
//! (measured: the mean relative difference for lindt-paper is 8.8e-3 at n = 128, 2.4e-3
//! at 256, 6.4e-4 at 512). Error against the file table's `GL_LINEAR` lookup
//! (`tests::octahedral_lookup_error_against_the_file_lookup`, 200k half vectors uniform on
//! the hemisphere, relative where the file value is above 1e-3 of its peak):
//!
//! | table | n | mean rel. | max rel. | max abs. / peak |
//! |---|---|---|---|---|
//! | lindt-paper library fit, 64 x 32 | 256 | 2.4e-3 | 0.24 | 0.24 (polar 1.3 deg) |
//! | golden/lindt-paper-16x8.exr | 64 | 6.1e-3 | 0.62 | 0.11 (polar 0.2 deg) |
//! | anisotropic Phong lobe 32 x 32 (n_u 40, n_v 10) | 256 | 2.7e-3 | 0.098 | 2.7e-3 |
//!
//! The largest differences are within a file texel of the pole, where the file lookup
//! itself is discontinuous (rows clamp, so at polar < half a texel it still blends texels
//! of different azimuths: its limit at the pole depends on the azimuth of approach); the
//! derived function is continuous there. Image level, new against old render of the
//! golden scenes (`brdfkit render`, `brdfkit compare`; relative RMSE = RMSE / RMS of the
//! old image): fig3-11-lindt-paper (library fit, one directional light: the highlight
//! sits at half vectors near the normal) 1.5e-2, max abs 0.23 at a peak of 6.2, FLIP mean
//! 1.0e-3; fig3-11-lindt-paper-dbrdf-file (16 x 8 file, 128 lights + key) 5.4e-3, FLIP
//! mean 2.7e-3. The SH library materials acquired from Lambert + D-BRDF stand-ins move by
//! RMSE 1.2e-6 (fig3-9) and 1.8e-5 (fig3-15).
//!
//! # Normalisation (derived)
//! The thesis (2.3.6) gives the formula above and says only that `p(h)` is a distribution
//! over half vectors covering the hemisphere and `c` a fitted constant; the report's body
//! was not available. The normalisation follows from reading the model as a microfacet BRDF
//! (Cook & Torrance 1982; Walter et al., "Microfacet models for refraction", EGSR 2007,
//! eq. 20): `f = D(h) G(k1, k2) F(k.h) / (4 (k1.n)(k2.n))`, where `D` is the density of
//! microfacet normals *per unit macro-surface area*, i.e. normalised over projected area,
//! `integral_{H} D(h) (h.n) dω_h = 1` (the microfacets' projected area is the surface's).
//! With the shadowing-masking term `G = (k1.n)(k2.n) / ((k1.n) + (k2.n) - (k1.n)(k2.n))`
//! (a value in [0, min(k1.n, k2.n)]: `a + b - a b >= max(a, b)`), the microfacet BRDF is
//! exactly `D(h) F / (4 ((k1.n) + (k2.n) - (k1.n)(k2.n)))`: the D-BRDF with `p = D` and
//! **`c = 1/4`**, `p` normalised by **`integral_{H} p(h) (h.n) dω_h = 1`**. Consequences:
//! * Energy: with `dω_i = 4 (k.h) dω_h`, the directional albedo is
//!   `integral p F G (k.h) / (k2.n) dω_h <= integral p(h) (k2.h)^+ dω_h` (`F <= 1`,
//!   `G <= k2.n`), which is exactly 1 at normal view (`k2 = n`) and close to it for the
//!   lobes used here; `brdf::tests_analytic` checks albedo <= 1 by quadrature.
//! * Closed form: a constant table is `p = 1/pi`; with `R_s = 1` (`F = 1`) the model is
//!   `f = 1 / (4 pi (a + b - a b))`, `a = k1.n`, `b = k2.n` (tested end to end in
//!   `tests/integration/closed_form_delta.rs`).
//!
//! [`DBrdf::normalize_projected`] enforces the condition *exactly for the file table's
//! lookup* (and the derived table keeps that integral to 1e-5, above): the `GL_LINEAR` lookup is linear in azimuth between texel centres
//! (periodic), so each texel's azimuthal integral is `2 pi / nu` times its value, and in the
//! polar angle it is the tent of each row (clamped to the edge row beyond the first and last
//! centres), whose integral against `cos sin` has a closed form. (Before, the condition was
//! approximated by the texel-centre cosine times the texel's solid angle, a midpoint rule off
//! by 3.0e-4 for a constant 32-row table, 1.2e-3 for 16 rows.)
//!
//! Fitting from data ([`DBrdf::from_backscatter`]) uses the backscatter slice `k1 = k2 = h`
//! (where `D = 2 h.n - (h.n)^2` and `F = F(1) = R_s`): `p(h) = f(h, h) D / (c R_s)`, then
//! renormalised; this is our reading of the report's "simplified way of measuring".
//!
//! # f64 evaluation
//! [`Brdf::eval_f64`] computes the half vector, `k.h`, Schlick's `F` and the denominator in
//! f64. The table lookup keeps the f32 texel arithmetic of [`DBrdf::p`] (the same texels
//! and weights as the f32 path, blended in f64): the table holds f32 data, and the f32
//! octahedral coordinates are within a few ulps of the f64 ones, which moves the bilinear
//! weights by < 1e-4 of a texel.
//!
//! # File format
//! The file format, [`mod@file`], stores the table as a single-channel OpenEXR image with
//! `c` and `R_s` in the header; it sits beside the type it stores (as `sh::file` sits
//! beside the SH data set).
//!
//! # Layout
//! `mod.rs` the model and its derived lookup; `weights.rs` the projected weights of texels
//! that the normalisation integrates with; `file.rs` the file format; `tests.rs` its tests.

pub mod file;
mod weights;

pub use weights::{octahedral_projected_weights, polar_row_projected_weight};

use super::ashikhmin_shirley::schlick_fresnel;
use super::Brdf;
use crate::conventions::{
    hemi_bilinear_texels_f64, hemi_oct_bilinear_texels, hemi_oct_decode_f64, hemi_oct_encode,
    hemi_oct_texel_center_f64, hemi_oct_texel_coord, hemi_texel_angles_f64, local_angles_f64,
    local_direction_f64,
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
    /// Side of the derived octahedral table (module doc, "The lookup the renderer
    /// evaluates").
    n_oct: usize,
    /// The derived octahedral table, `oct[j n_oct + i]`.
    oct: Vec<f32>,
    /// The factor the derived table's samples were multiplied by to keep the file
    /// function's projected integral (1 up to the quadrature's and f32's rounding).
    oct_scale: f64,
}

/// Largest spread of a polar row of `p(h)` (max - min over azimuth, relative to the row's
/// largest value) for which [`DBrdf::is_isotropic_table`] calls the table isotropic: the f32
/// rounding of a fitted isotropic lobe (`n_u cos^2 + n_v sin^2` with `n_u = n_v` is not
/// exactly `n_u` in f32) stays below 1e-5; an anisotropic lobe of exponents 30 and 31 at
/// 30 degrees from the normal spreads by 2e-2.
pub const ISOTROPY_TOLERANCE: f32 = 1e-4;

impl DBrdf {
    /// Whether `p(h)` depends on the polar angle of `h` only: every row `j` of the table
    /// constant over its `nu` azimuth texels within [`ISOTROPY_TOLERANCE`] (relative to the
    /// row's largest value; an all-zero row is constant).
    pub fn is_isotropic_table(&self) -> bool {
        self.p.chunks_exact(self.nu).all(|row| {
            let (lo, hi) = row.iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
            hi - lo <= ISOTROPY_TOLERANCE * hi
        })
    }

    /// From a table `p[j * nu + i]` (not renormalised). Panics if `nu` or `nv` is zero, the
    /// length is not `nu * nv`, or a value is negative or non-finite.
    pub fn new(nu: usize, nv: usize, p: Vec<f32>, rs: Vec3) -> Self {
        assert!(nu > 0 && nv > 0, "empty D-BRDF table");
        assert_eq!(p.len(), nu * nv, "D-BRDF table size");
        assert!(
            p.iter().all(|v| v.is_finite() && *v >= 0.0),
            "D-BRDF table values must be finite and >= 0"
        );
        let mut d = DBrdf {
            nu,
            nv,
            p,
            rs,
            c: 0.25,
            n_oct: 0,
            oct: Vec::new(),
            oct_scale: 1.0,
        };
        d.derive_octahedral();
        d
    }

    /// Side of the derived octahedral table for an `nu x nv` file table (module doc):
    /// the smallest power of two `>= 2 max(nu, 4 nv)`, at least 16 and at most 512.
    pub fn octahedral_side(nu: usize, nv: usize) -> usize {
        (2 * nu.max(4 * nv)).next_power_of_two().clamp(16, 512)
    }

    /// (Re)builds the octahedral table from the file table (module doc): the file table's
    /// `GL_LINEAR` lookup sampled at the octahedral texel centres (f64 angles), scaled so
    /// that its projected integral equals the file function's closed-form one.
    fn derive_octahedral(&mut self) {
        let n = Self::octahedral_side(self.nu, self.nv);
        let mut samples = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let h = hemi_oct_decode_f64(
                    hemi_oct_texel_center_f64(i, n),
                    hemi_oct_texel_center_f64(j, n),
                );
                samples.push(self.file_p_f64(h));
            }
        }
        let weights = octahedral_projected_weights(n);
        let oct_integral: f64 = samples.iter().zip(weights.iter()).map(|(p, w)| p * w).sum();
        let file_integral = self.file_projected_integral();
        let scale = if oct_integral > 0.0 {
            file_integral / oct_integral
        } else {
            1.0
        };
        self.n_oct = n;
        self.oct = samples.iter().map(|&p| (p * scale) as f32).collect();
        self.oct_scale = scale;
    }

    /// `p(h)` of the *file* table: its `GL_LINEAR` lookup at the f64 angles of the unit
    /// local `h` (the parameterisation of [`mod@file`]; the renderer evaluates the derived
    /// table instead, [`DBrdf::p`]).
    pub fn file_p_f64(&self, h: glam::DVec3) -> f64 {
        let (pol, az) = local_angles_f64(h);
        let (s, t) = (
            az / std::f64::consts::TAU,
            pol / std::f64::consts::FRAC_PI_2,
        );
        hemi_bilinear_texels_f64(s, t, self.nu, self.nv)
            .iter()
            .map(|&(i, j, w)| w * self.p[j * self.nu + i] as f64)
            .sum()
    }

    /// `integral_H p_file(h) (h.n) dω_h` in closed form (see
    /// [`DBrdf::normalize_projected`]).
    fn file_projected_integral(&self) -> f64 {
        let mut s = 0.0f64;
        let daz = std::f64::consts::TAU / self.nu as f64;
        for j in 0..self.nv {
            let w = daz * polar_row_projected_weight(j, self.nv);
            for i in 0..self.nu {
                s += self.p[j * self.nu + i] as f64 * w;
            }
        }
        s
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

    /// Rescales the table so that `integral_{H} p(h) (h.n) dω_h = 1` holds for the
    /// bilinearly looked-up `p` (module doc): `sum_texels p_ij (2 pi / nu) W_j = 1`, with
    /// `W_j` the projected weight of row `j` ([`polar_row_projected_weight`]). Exact for
    /// any table (to f64 rounding, then the f32 rounding of the stored values); a constant
    /// table becomes `1/pi`. A zero table is left unchanged.
    pub fn normalize_projected(&mut self) {
        let s = self.file_projected_integral();
        if s > 0.0 {
            for v in &mut self.p {
                *v = (*v as f64 / s) as f32;
            }
            self.derive_octahedral();
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

    /// Side `n` of the derived octahedral table (`n x n`).
    pub fn octahedral_grid(&self) -> usize {
        self.n_oct
    }

    /// The derived octahedral table, `[j n + i]` ([`crate::conventions`], "Octahedral
    /// hemisphere tables").
    pub fn octahedral_table(&self) -> &[f32] {
        &self.oct
    }

    /// The factor the derived table's samples of the file function were scaled by (module
    /// doc; 1 to about 1e-4 for the shipped tables).
    pub fn octahedral_scale(&self) -> f64 {
        self.oct_scale
    }

    /// `p(h)` as the renderer evaluates it: the derived octahedral table's `GL_LINEAR`
    /// lookup at the local half vector `h`, or any positive multiple of it, such as
    /// `wi + wo` (the map needs no normalisation). The lane kernel
    /// (`kernel::models`) computes the same texel arithmetic per lane.
    #[inline]
    pub fn p(&self, h: Vec3) -> f32 {
        let (u, v) = hemi_oct_encode(h);
        let n = self.n_oct;
        let (cu, cv) = (hemi_oct_texel_coord(u, n), hemi_oct_texel_coord(v, n));
        let t = hemi_oct_bilinear_texels(cu, cv, n);
        let p = |k: usize| self.oct[t[k].1 * n + t[k].0];
        (t[0].2 * p(0) + t[1].2 * p(1)) + (t[2].2 * p(2) + t[3].2 * p(3))
    }

    /// The lobe (thesis 2.3.6, [`Brdf::eval`]) where its half vector's table value is
    /// already known: `c p_h F(kh) / (a + b - a b)` with `p_h = p(h)`, `kh = k.h` in
    /// `[0, 1]`, `a = min(wi_z, 1)`, `b = min(wo_z, 1)` (the local polar cosines, both
    /// positive: the caller checks), `F` Schlick's Fresnel of [`DBrdf::rs`]; 1/sr, RGB. The
    /// operations and their order are [`Brdf::eval`]'s, which calls it: filtered importance
    /// sampling, whose half vectors are fixed, looks `p` up once per half vector instead of
    /// once per pixel and sample.
    #[inline]
    pub fn eval_at_half(&self, p_h: f32, kh: f32, wi_z: f32, wo_z: f32) -> Vec3 {
        let (a, b) = (wi_z.min(1.0), wo_z.min(1.0));
        let denom = a + b - a * b;
        self.c * p_h * schlick_fresnel(self.rs, kh) / denom
    }

    /// [`DBrdf::p`] with the same texels and f32 weights, blended in f64.
    pub(crate) fn p_f64_blend(&self, h: Vec3) -> f64 {
        let (u, v) = hemi_oct_encode(h);
        let n = self.n_oct;
        let (cu, cv) = (hemi_oct_texel_coord(u, n), hemi_oct_texel_coord(v, n));
        hemi_oct_bilinear_texels(cu, cv, n)
            .iter()
            .map(|&(i, j, w)| w as f64 * self.oct[j * n + i] as f64)
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
        let kh = (0.5 * len).clamp(0.0, 1.0);
        // The lookup takes the unnormalised sum, as the lane kernel does.
        self.eval_at_half(self.p(sum), kh, wi.z, wo.z)
    }

    fn name(&self) -> &str {
        "d-brdf"
    }

    /// True when every polar row of the table is constant in azimuth to
    /// [`ISOTROPY_TOLERANCE`] of the row's largest value ([`DBrdf::is_isotropic_table`]).
    fn is_isotropic(&self) -> bool {
        self.is_isotropic_table()
    }

    /// [`Brdf::eval`] in f64 except the table lookup (module doc, "f64 evaluation").
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return glam::DVec3::ZERO;
        }
        let sum = wi + wo;
        let len = sum.length();
        if len <= 1e-6 {
            return glam::DVec3::ZERO;
        }
        let h = sum / len;
        let (a, b) = (wi.z.min(1.0), wo.z.min(1.0));
        let denom = a + b - a * b;
        let kh = (0.5 * len).clamp(0.0, 1.0);
        let rs = self.rs.as_dvec3();
        let fresnel = rs + (glam::DVec3::ONE - rs) * (1.0 - kh).powi(5);
        let p = self.p_f64_blend(h.as_vec3());
        self.c as f64 * p * fresnel / denom
    }

    /// `c max(p) max(1, R_s)`: the bilinear `p(h)` is a convex blend of table values, so at
    /// most the table's largest; Schlick's `F` lies between `R_s` and 1; and
    /// `cos(polar_i) / D <= 1` because `D = a + b - a b = a + b (1 - a) >= a = cos(polar_i)`.
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        let pmax = self.oct.iter().copied().fold(0.0f32, f32::max);
        Some(self.c * pmax * self.rs.max(Vec3::ONE))
    }
}

#[cfg(test)]
mod tests;
