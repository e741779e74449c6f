//! Texture filtering of the coefficient table: [`Lookup`] (`GL_NEAREST` or `GL_LINEAR`) and
//! [`ShDataset::lookup_coeffs`] (thesis 3.1.4: the view direction selects coefficients from a
//! texture).
//!
//! Design rule: the texel arithmetic is not restated here; it is
//! [`hemi_nearest_texel`] / [`hemi_bilinear_texels`] of [`crate::conventions`], so the CPU
//! filter is the GPU's, bit for bit in the texel choice and weights. The tests compare with an
//! independent restatement of the OpenGL filter rules (`gl_reference`).

use super::ShDataset;
use crate::conventions::{hemi_bilinear_texels, hemi_nearest_texel};
use crate::sh::basis::num_terms;

/// Texture filter used for a table lookup (thesis 3.1.4). In scene files and on the command
/// line (`render --lookup`): `nearest` or `bilinear`.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Lookup {
    /// `GL_NEAREST`: the texel containing `(s, t)`.
    Nearest,
    /// `GL_LINEAR`: bilinear blend of the four nearest texel centres.
    Bilinear,
}

impl ShDataset {
    /// Filtered coefficients at texture coordinates `(s, t)`, written as `[R.., G.., B..]`
    /// into `out` (`out.len()` must be `3 bands^2`, else panic).
    pub fn lookup_coeffs(&self, s: f32, t: f32, mode: Lookup, out: &mut [f32]) {
        let nt = num_terms(self.bands);
        assert_eq!(out.len(), 3 * nt, "coefficient output length");
        match mode {
            Lookup::Nearest => {
                let (i, j) = hemi_nearest_texel(s, t, self.nu, self.nv);
                let o = (j * self.nu + i) * 3 * nt;
                out.copy_from_slice(&self.coeffs[o..o + 3 * nt]);
            }
            Lookup::Bilinear => {
                out.fill(0.0);
                for (i, j, w) in hemi_bilinear_texels(s, t, self.nu, self.nv) {
                    let o = (j * self.nu + i) * 3 * nt;
                    for (d, v) in out.iter_mut().zip(&self.coeffs[o..o + 3 * nt]) {
                        *d += w * v;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::gl_reference::{
        gl_linear_ref, gl_nearest_ref, random_dataset, sample_coords,
    };
    use super::*;

    #[test]
    fn coefficient_lookups_match_gl_reference() {
        let (nu, nv, bands) = (8, 4, 2);
        let ds = random_dataset(nu, nv, bands, 1);
        let nt = num_terms(bands);
        let mut out = vec![0.0f32; 3 * nt];
        for (s, t) in sample_coords() {
            for (mode, name) in [(Lookup::Nearest, "nearest"), (Lookup::Bilinear, "linear")] {
                ds.lookup_coeffs(s, t, mode, &mut out);
                for c in 0..3 {
                    for k in 0..nt {
                        let tab: Vec<f64> = (0..nv)
                            .flat_map(|j| (0..nu).map(move |i| (i, j)))
                            .map(|(i, j)| ds.texel(i, j, c)[k] as f64)
                            .collect();
                        let r = match mode {
                            Lookup::Nearest => gl_nearest_ref(&tab, nu, nv, s as f64, t as f64),
                            Lookup::Bilinear => gl_linear_ref(&tab, nu, nv, s as f64, t as f64),
                        };
                        let got = out[c * nt + k] as f64;
                        assert!(
                            (got - r).abs() < 2e-6,
                            "{name} s={s} t={t} c={c} k={k}: {got} vs {r}"
                        );
                    }
                }
            }
        }
    }
}
