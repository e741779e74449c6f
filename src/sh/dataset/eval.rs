//! Evaluation of a data set: [`ShDataset::reconstruct`] (`sum_k c_k(wo) Y_k(wi)` with the
//! analytic basis, thesis Def. 12, Code 4) and the [`Brdf`] impl, plus
//! [`ShDataset::reconstruct_tabulated`], what a GPU build that samples a basis table computes.
//!
//! Design rule: every renderer path (f32 `eval`, `eval_f64`, the kernels) uses the analytic
//! basis of [`crate::sh::basis`]; the basis table is read only by `reconstruct_tabulated`,
//! which the renderer never calls (parent module doc).

use super::{Lookup, ShDataset, MAX_BANDS};
use crate::brdf::Brdf;
use crate::conventions::{hemi_bilinear_texels, hemi_nearest_texel, hemi_texcoord, local_angles};
use crate::sh::basis::{eval_sh_f32, eval_sh_f64, num_terms};
use glam::Vec3;

impl ShDataset {
    /// `sum_k c_k(wo) Y_k(wi)` (RGB) for local directions, with the analytic basis (the data
    /// set's definition, module doc) and the coefficient filter; zero below the horizon. Not
    /// clamped (see the module doc).
    pub fn reconstruct(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.reconstruct_with(wi, wo, false)
    }

    /// What a GPU build that samples the basis table computes (thesis Code 4): as
    /// [`ShDataset::reconstruct`], with `Y_k(wi)` filtered from the basis table
    /// ([`ShDataset::basis_lookup`]) when one is set. Not the data set's value: for
    /// measuring a table's discretisation error (module doc); the renderer never calls it.
    pub fn reconstruct_tabulated(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.reconstruct_with(wi, wo, true)
    }

    fn reconstruct_with(&self, wi: Vec3, wo: Vec3, tabulated: bool) -> Vec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        let nt = num_terms(self.bands);
        let mut ybuf = [0.0f32; MAX_BANDS * MAX_BANDS];
        let y = &mut ybuf[..nt];
        match self.basis.as_ref().filter(|_| tabulated) {
            Some(tb) => {
                let (p, a) = local_angles(wi);
                let (s, t) = hemi_texcoord(p, a);
                tb.lookup(s, t, self.basis_lookup, y);
            }
            None => eval_sh_f32(wi, y),
        }
        let (p, a) = local_angles(wo);
        let (s, t) = hemi_texcoord(p, a);
        let dot = |c: &[f32]| -> f32 { c.iter().zip(y.iter()).map(|(a, b)| a * b).sum() };
        let mut rgb = Vec3::ZERO;
        let mut acc = |i: usize, j: usize, w: f32| {
            if w != 0.0 {
                rgb += w * Vec3::new(
                    dot(self.texel(i, j, 0)),
                    dot(self.texel(i, j, 1)),
                    dot(self.texel(i, j, 2)),
                );
            }
        };
        match self.coeff_lookup {
            Lookup::Nearest => {
                let (i, j) = hemi_nearest_texel(s, t, self.nu, self.nv);
                acc(i, j, 1.0);
            }
            Lookup::Bilinear => {
                for (i, j, w) in hemi_bilinear_texels(s, t, self.nu, self.nv) {
                    acc(i, j, w);
                }
            }
        }
        rgb
    }
}

impl Brdf for ShDataset {
    /// [`ShDataset::reconstruct`]: `f_r` or `f_r cos(polar_i)` depending on
    /// [`Brdf::includes_cosine`].
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.reconstruct(wi, wo)
    }

    fn includes_cosine(&self) -> bool {
        self.includes_cosine
    }

    fn name(&self) -> &str {
        "sh-dataset"
    }

    fn is_isotropic(&self) -> bool {
        self.isotropic
    }

    /// Cauchy-Schwarz and the SH addition theorem (`sum_m Y_lm(w)^2 = (2l+1)/(4 pi)` for
    /// every direction, so `sum_{l<L} sum_m Y_lm^2 = L^2/(4 pi)`):
    /// `|sum_k c_k Y_k(wi)| <= |c| L / sqrt(4 pi)`, with `|c|` at most the largest texel
    /// norm ([`ShDataset::max_texel_norm`]; a bilinear lookup blends texels convexly, which
    /// cannot raise the norm). Times `cos(polar_i) <= 1` when the table excludes the cosine.
    fn max_cosine_weighted(&self) -> Option<Vec3> {
        let k = self.bands as f64 / (4.0 * std::f64::consts::PI).sqrt();
        Some(self.max_texel_norm(0) * k as f32)
    }

    /// `sum_k c_k(wo) Y_k(wi)` with the basis evaluated and the sum accumulated in f64 (the
    /// coefficients are the stored f32 values, filtered as in [`ShDataset::reconstruct`]);
    /// the analytic basis, like every path (a basis table is never read, module doc).
    fn eval_f64(&self, wi: glam::DVec3, wo: glam::DVec3) -> glam::DVec3 {
        if wo.z <= 0.0 {
            return glam::DVec3::ZERO;
        }
        let mut cbuf = [0.0f32; 3 * MAX_BANDS * MAX_BANDS];
        let c = self.view_coeffs(wo, &mut cbuf);
        self.eval_f64_with_coeffs(wi, c)
    }

    /// [`Brdf::eval_f64`] for every `wi`, the coefficients `c_k(wo)` looked up once: the
    /// same bits as one call per direction.
    fn eval_f64_at_view(&self, wo: glam::DVec3, wi: &[glam::DVec3], out: &mut [glam::DVec3]) {
        if wo.z <= 0.0 {
            out.fill(glam::DVec3::ZERO);
            return;
        }
        let mut cbuf = [0.0f32; 3 * MAX_BANDS * MAX_BANDS];
        let c = self.view_coeffs(wo, &mut cbuf);
        for (o, &w) in out.iter_mut().zip(wi) {
            *o = self.eval_f64_with_coeffs(w, c);
        }
    }
}

impl ShDataset {
    /// The coefficients `c_k(wo)` of the three channels (channel-major, `3 x` the data
    /// set's terms, the front of `buf`), looked up as [`ShDataset::reconstruct`] does.
    fn view_coeffs<'a>(&self, wo: glam::DVec3, buf: &'a mut [f32]) -> &'a [f32] {
        let c = &mut buf[..3 * num_terms(self.bands)];
        let (p, a) = local_angles(wo.as_vec3());
        let (s, t) = hemi_texcoord(p, a);
        self.lookup_coeffs(s, t, self.coeff_lookup, c);
        c
    }

    /// `sum_k c_k Y_k(wi)` in f64 for the coefficients `c` of [`ShDataset::view_coeffs`];
    /// zero below the horizon.
    fn eval_f64_with_coeffs(&self, wi: glam::DVec3, c: &[f32]) -> glam::DVec3 {
        if wi.z <= 0.0 {
            return glam::DVec3::ZERO;
        }
        let nt = num_terms(self.bands);
        let mut ybuf = [0.0f64; MAX_BANDS * MAX_BANDS];
        let y = &mut ybuf[..nt];
        eval_sh_f64(wi, y);
        let dot = |o: usize| -> f64 { (0..nt).map(|k| c[o + k] as f64 * y[k]).sum() };
        glam::DVec3::new(dot(0), dot(nt), dot(2 * nt))
    }
}

#[cfg(test)]
mod tests {
    use super::super::gl_reference::random_dataset;
    use super::super::ShBasisTable;
    use super::*;
    use crate::conventions::{hemi_texel_angles_f64, local_direction};
    use rand::{Rng, SeedableRng};

    #[test]
    fn eval_at_texel_centres_is_the_sh_sum_and_zero_below_horizon() {
        let (nu, nv, bands) = (8, 4, 3);
        let ds = random_dataset(nu, nv, bands, 2);
        let nt = num_terms(bands);
        let mut y = vec![0.0f64; nt];
        let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
        for mode in [Lookup::Nearest, Lookup::Bilinear] {
            let mut d = ds.clone();
            d.coeff_lookup = mode;
            for _ in 0..50 {
                let (i, j) = (rng.gen_range(0..nu), rng.gen_range(0..nv));
                let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
                let wo = local_direction(p as f32, a as f32);
                let wi = local_direction(
                    rng.gen_range(0.0..1.5),
                    rng.gen_range(0.0..std::f32::consts::TAU),
                );
                eval_sh_f64(wi.as_dvec3(), &mut y);
                let got = d.eval(wi, wo);
                for c in 0..3 {
                    let r: f64 = (0..nt).map(|k| ds.texel(i, j, c)[k] as f64 * y[k]).sum();
                    assert!(
                        (got[c] as f64 - r).abs() < 1e-4,
                        "{mode:?} {} vs {r}",
                        got[c]
                    );
                }
                assert_eq!(d.eval(-wi, wo), Vec3::ZERO);
                assert_eq!(d.eval(wi, Vec3::new(wo.x, wo.y, -wo.z)), Vec3::ZERO);
            }
        }
    }

    #[test]
    fn table_basis_matches_analytic_at_light_texel_centres() {
        let (nu, nv, bands) = (8, 4, 4);
        let mut ds = random_dataset(nu, nv, bands, 4);
        let analytic = ds.clone();
        ds.set_basis_table(Some(ShBasisTable::tabulate(32, 16, bands).unwrap()))
            .unwrap();
        let wo = local_direction(0.4, 1.0);
        for j in 0..16 {
            for i in 0..32 {
                let (p, a) = hemi_texel_angles_f64(i, j, 32, 16);
                let wi = local_direction(p as f32, a as f32);
                let (x, y) = (ds.reconstruct_tabulated(wi, wo), analytic.eval(wi, wo));
                assert!((x - y).abs().max_element() < 1e-4, "{x} vs {y}");
            }
        }
        assert!(ds
            .set_basis_table(Some(ShBasisTable::tabulate(4, 4, 2).unwrap()))
            .is_err());
    }

    /// The analytic basis defines the data set (module doc): a table changes no value of
    /// `eval` or `eval_f64`, even between texel centres, where a nearest lookup of a coarse
    /// table is far off (checked, so the table is not trivially equal to the basis there).
    #[test]
    fn a_basis_table_changes_no_evaluation() {
        let (nu, nv, bands) = (8, 4, 6);
        let analytic = random_dataset(nu, nv, bands, 5);
        let mut ds = analytic.clone();
        ds.set_basis_table(Some(ShBasisTable::tabulate(8, 4, bands).unwrap()))
            .unwrap();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(6);
        let mut table_error = 0.0f32;
        for _ in 0..500 {
            let tau = std::f32::consts::TAU;
            let wi = local_direction(rng.gen_range(0.0..1.5), rng.gen_range(0.0..tau));
            let wo = local_direction(rng.gen_range(0.0..1.5), rng.gen_range(0.0..tau));
            assert_eq!(ds.eval(wi, wo), analytic.eval(wi, wo));
            let (a, b) = (wi.as_dvec3(), wo.as_dvec3());
            assert_eq!(ds.eval_f64(a, b), analytic.eval_f64(a, b));
            let d = ds.reconstruct_tabulated(wi, wo) - analytic.eval(wi, wo);
            table_error = table_error.max(d.abs().max_element());
        }
        assert!(table_error > 0.1, "coarse table error only {table_error}");
    }

    /// The reference path's batch at one view has the bits of one `eval_f64` per direction,
    /// below the horizon too (wi or wo), for both lookups.
    #[test]
    fn eval_f64_at_view_is_eval_f64_per_direction() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        for lookup in [Lookup::Nearest, Lookup::Bilinear] {
            let mut ds = random_dataset(8, 4, 5, 3);
            ds.coeff_lookup = lookup;
            for _ in 0..20 {
                let tau = std::f32::consts::TAU;
                let wo = local_direction(rng.gen_range(0.0..1.7), rng.gen_range(0.0..tau));
                let wi: Vec<_> = (0..40)
                    .map(|_| {
                        local_direction(rng.gen_range(0.0..3.1), rng.gen_range(0.0..tau)).as_dvec3()
                    })
                    .collect();
                let mut got = vec![glam::DVec3::NAN; wi.len()];
                ds.eval_f64_at_view(wo.as_dvec3(), &wi, &mut got);
                for (w, g) in wi.iter().zip(&got) {
                    assert_eq!(*g, ds.eval_f64(*w, wo.as_dvec3()), "{lookup:?} {w} {wo}");
                }
            }
        }
    }
}
