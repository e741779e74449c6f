//! SH BRDF data sets: coefficient tables `c_lm(view texel)` and optional basis tables
//! `Y_lm(light texel)` on hemispherical grids (thesis 2.3.3-2.3.4 Def. 12, 3.1.3-3.1.5).
//!
//! Design rule: the CPU lookups reproduce the GPU's texture filtering exactly (the texel
//! arithmetic lives in [`crate::conventions`]:
//! [`hemi_nearest_texel`](crate::conventions::hemi_nearest_texel) for `GL_NEAREST`,
//! [`hemi_bilinear_texels`](crate::conventions::hemi_bilinear_texels) for `GL_LINEAR`), so
//! this module can serve as an oracle for a GPU build that stores the tables as 3D textures.
//!
//! # Grids
//! A table has `nu` azimuth texels by `nv` polar texels over the upper hemisphere; texel
//! `(i, j)` (i azimuth, j polar) is centred at `s = (i+1/2)/nu`, `t = (j+1/2)/nv` with
//! `s = azimuth / 2 pi`, `t = polar / (pi/2)` in the local shading frame. Azimuth wraps,
//! polar clamps.
//!
//! # Memory layout (for a later SIMD kernel)
//! Coefficients are `f32`, row-major over texels with the polar index slowest:
//! `coeffs[((j * nu + i) * 3 + c) * T + k]`, `T = bands^2`, `c` = 0 (R), 1 (G), 2 (B),
//! `k = l*l + l + m`. So for one view texel, all `T` coefficients of one colour are
//! contiguous, followed by the next colour: a texel is one `3 T` block of
//! `[R_0..R_{T-1}, G_0..G_{T-1}, B_0..B_{T-1}]`.
//! The basis table is `values[(j * nu + i) * T + k]` (one contiguous `T` block per light
//! texel).
//!
//! # Evaluation (thesis Def. 12, Code 4)
//! `f(wi, wo) = sum_k c_k(wo) Y_k(wi)` per colour, with `c_k(wo)` filtered from the
//! coefficient table and `Y_k(wi)` the analytic real SH of [`crate::sh::basis`] (see the next
//! section for the basis table). Values are **not** clamped: SH ringing can give negative
//! values above the horizon, exactly as the thesis's shader does; below the horizon
//! (`wi.z <= 0` or `wo.z <= 0`) the result is zero (the thesis's backface test, 3.1.2).
//! Whether the table includes `cos(polar_i)` is recorded in `includes_cosine`.
//!
//! # Which basis defines a data set: the analytic one, always
//! A data set may carry a basis table ([`ShBasisTable`]: `Y_k` at the texel centres of a
//! light grid, thesis 3.1.4-3.1.5, the `shTexture` of Code 4). It is **not** part of the data
//! set's definition, and no renderer path reads it:
//! - the coefficients are projections onto the continuous basis: the acquisition device
//!   illuminates the sample with the SH functions themselves (basis illumination, thesis
//!   2.3.3 and its reference \[7\]), and [`crate::acquire`] projects with
//!   [`eval_sh_f64`](crate::sh::basis::eval_sh_f64) at quadrature nodes. The function the
//!   coefficients describe is `sum_k c_k Y_k` with the analytic `Y_k`;
//! - the thesis stores the basis in a texture only because its fragment shader cannot
//!   evaluate it (3.1.4: "the fourth component stores the basis value for the spherical
//!   harmonics function", sampled with `GL_NEAREST` on its hardware). A table is the same
//!   functions sampled at texel centres; a nearest or bilinear lookup between centres is a
//!   discretisation error of that GPU build (at 8 bands on a 16 x 8 grid, far larger than
//!   any rounding), which an oracle must expose, not reproduce;
//! - one definition is what makes every light kind agree: a directional light and the same
//!   light as a distant point light must give the same image, whichever kernel path, the
//!   scalar oracle or the f64 path shades it, with or without the band skip
//!   (tests/integration/sh_basis.rs). Earlier versions used the table for point lights only and so
//!   rendered the two differently (FLIP mean 0.053).
//!
//! So [`ShDataset::reconstruct`], [`Brdf::eval`](crate::brdf::Brdf::eval),
//! [`Brdf::eval_f64`](crate::brdf::Brdf::eval_f64) and the kernels all use the analytic basis.
//! The table is kept (files round-trip it, [`ShDataset::truncated`] truncates it with the
//! coefficients) for GPU builds to upload, and
//! [`ShDataset::set_basis_table`] accepts only a table that *is* this basis at its texel
//! centres (within [`BASIS_TABLE_TOLERANCE`]), so a file cannot carry a table in another
//! convention that the CPU would silently disagree with. What a GPU build computes with its
//! table is [`ShDataset::reconstruct_tabulated`], for measuring that build's discretisation
//! error; nothing in the renderer calls it.
//!
//! # Layout
//! One concept per file:
//! - this file: the [`ShDataset`] type (grid, coefficients, provenance, constructors,
//!   truncation, texel accessors), its error [`ShDataError`] and [`MAX_BANDS`];
//! - [`lookup`] -- the texture filter [`Lookup`] and [`ShDataset::lookup_coeffs`] (the GPU's
//!   `GL_NEAREST` / `GL_LINEAR` on the coefficient table);
//! - [`basis_table`] -- [`ShBasisTable`], the optional tabulated basis, and
//!   [`ShDataset::set_basis_table`], which accepts only the analytic basis;
//! - [`eval`] -- [`ShDataset::reconstruct`] and the [`Brdf`](crate::brdf::Brdf) impl (the
//!   analytic-basis sum of the section above);
//! - [`band_skip`] -- the declared band energy threshold and
//!   [`ShDataset::effective_bands`] (the band skip policy bounded in [`crate::kernel::skip`]).

pub mod band_skip;
pub mod basis_table;
pub mod eval;
#[cfg(test)]
mod gl_reference;
pub mod lookup;

pub use band_skip::DEFAULT_BAND_THRESHOLD;
pub use basis_table::{ShBasisTable, BASIS_TABLE_TOLERANCE};
pub use lookup::Lookup;

use super::basis::num_terms;

/// Largest number of bands a data set may have (all l < 32, 1024 terms): evaluation uses a
/// fixed stack buffer of this many terms, and file readers reject larger counts as absurd.
pub const MAX_BANDS: usize = 32;

/// Errors building a data set from raw parts.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ShDataError {
    #[error("band count {0} out of range 1..={MAX_BANDS}")]
    Bands(usize),
    #[error("empty grid {nu} x {nv}")]
    EmptyGrid { nu: usize, nv: usize },
    #[error("coefficient table has {got} values, expected {expected} (nu * nv * 3 * bands^2)")]
    Size { got: usize, expected: usize },
    #[error("non-finite value at flat index {0}")]
    NonFinite(usize),
    #[error("band energy threshold {0} out of range (0 <= threshold < 1)")]
    BandThreshold(f32),
    #[error(
        "basis table texel ({i}, {j}) term {k} is {got}, the SH basis there is {expected} \
         (the table must be the analytic basis of sh::basis at its texel centres)"
    )]
    BasisTable {
        i: usize,
        j: usize,
        k: usize,
        got: f32,
        expected: f64,
    },
}

fn check_grid(nu: usize, nv: usize, bands: usize) -> Result<(), ShDataError> {
    if bands == 0 || bands > MAX_BANDS {
        return Err(ShDataError::Bands(bands));
    }
    if nu == 0 || nv == 0 {
        return Err(ShDataError::EmptyGrid { nu, nv });
    }
    Ok(())
}

/// An SH BRDF data set: RGB coefficients per view texel (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct ShDataset {
    nu: usize,
    nv: usize,
    bands: usize,
    includes_cosine: bool,
    provenance: String,
    coeffs: Vec<f32>,
    basis: Option<ShBasisTable>,
    /// Declared band energy threshold (see [`ShDataset::effective_bands`]).
    band_threshold: f32,
    /// Filter for the coefficient table (view direction). Default `Nearest` (thesis 3.1.4:
    /// float textures required `GL_NEAREST` on the thesis's hardware).
    pub coeff_lookup: Lookup,
    /// Filter for the basis table (light direction), used only by
    /// [`ShDataset::reconstruct_tabulated`] (never by rendering, see the module doc).
    pub basis_lookup: Lookup,
    /// Whether the data describe an isotropic BRDF (acquired from one: `brdfkit acquire`
    /// records its source's [`crate::brdf::Brdf::is_isotropic`]). Isotropic data sets are
    /// shaded in the view-aligned frame ([`crate::conventions`], "Frame of isotropic
    /// tabulated materials"), so their lookup is always at azimuth texel 0's centre; the
    /// others in the world-up frame. `false` unless set (every file written before the
    /// flag existed).
    pub isotropic: bool,
}

impl ShDataset {
    /// A data set from raw coefficients (layout in the module doc). Err on a bad band count
    /// (`1..=MAX_BANDS`), an empty grid, a size mismatch or a non-finite coefficient.
    pub fn new(
        nu: usize,
        nv: usize,
        bands: usize,
        includes_cosine: bool,
        provenance: impl Into<String>,
        coeffs: Vec<f32>,
    ) -> Result<Self, ShDataError> {
        check_grid(nu, nv, bands)?;
        let expected = nu * nv * 3 * num_terms(bands);
        if coeffs.len() != expected {
            return Err(ShDataError::Size {
                got: coeffs.len(),
                expected,
            });
        }
        if let Some(p) = coeffs.iter().position(|v| !v.is_finite()) {
            return Err(ShDataError::NonFinite(p));
        }
        Ok(ShDataset {
            nu,
            nv,
            bands,
            includes_cosine,
            provenance: provenance.into(),
            coeffs,
            basis: None,
            band_threshold: DEFAULT_BAND_THRESHOLD,
            coeff_lookup: Lookup::Nearest,
            basis_lookup: Lookup::Nearest,
            isotropic: false,
        })
    }

    /// An all-zero data set (same errors as [`ShDataset::new`]).
    pub fn zeros(
        nu: usize,
        nv: usize,
        bands: usize,
        includes_cosine: bool,
        provenance: impl Into<String>,
    ) -> Result<Self, ShDataError> {
        check_grid(nu, nv, bands)?;
        let n = nu * nv * 3 * num_terms(bands);
        Self::new(nu, nv, bands, includes_cosine, provenance, vec![0.0; n])
    }

    /// The same data set keeping only the first `bands` bands (terms `l < bands`): the
    /// truncated SH expansion, as a lower-order acquisition would store it. A basis table is
    /// truncated to the same bands ([`ShBasisTable::truncated`]; it plays no part in
    /// rendering, see the module doc); lookups and provenance are kept, the provenance
    /// noting the truncation. Err (`Bands`) unless `1 <= bands <= self.bands()`.
    pub fn truncated(&self, bands: usize) -> Result<Self, ShDataError> {
        if bands == 0 || bands > self.bands {
            return Err(ShDataError::Bands(bands));
        }
        let (old, new) = (num_terms(self.bands), num_terms(bands));
        let mut coeffs = Vec::with_capacity(self.nu * self.nv * 3 * new);
        for block in self.coeffs.chunks_exact(old) {
            coeffs.extend_from_slice(&block[..new]);
        }
        let mut out = Self::new(
            self.nu,
            self.nv,
            bands,
            self.includes_cosine,
            format!("{} (truncated to {} bands)", self.provenance, bands),
            coeffs,
        )?;
        out.coeff_lookup = self.coeff_lookup;
        out.basis_lookup = self.basis_lookup;
        out.isotropic = self.isotropic;
        out.band_threshold = self.band_threshold;
        out.basis = self
            .basis
            .as_ref()
            .map(|tb| tb.truncated(bands))
            .transpose()?;
        Ok(out)
    }

    /// `(nu, nv)` of the coefficient grid.
    pub fn grid(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// Number of bands L (terms `L^2`).
    pub fn bands(&self) -> usize {
        self.bands
    }

    /// Whether the coefficients represent `f_r cos(polar_i)` rather than `f_r`.
    pub fn cosine_included(&self) -> bool {
        self.includes_cosine
    }

    /// Free-text provenance (source data, fitting method).
    pub fn provenance(&self) -> &str {
        &self.provenance
    }

    /// Raw coefficients (layout in the module doc).
    pub fn coeffs(&self) -> &[f32] {
        &self.coeffs
    }

    /// The `T` coefficients of colour `c` (0..3) at view texel `(i, j)`. Panics if out of
    /// range.
    #[inline]
    pub fn texel(&self, i: usize, j: usize, c: usize) -> &[f32] {
        let t = num_terms(self.bands);
        assert!(c < 3);
        let o = ((j * self.nu + i) * 3 + c) * t;
        &self.coeffs[o..o + t]
    }

    /// The `3 T` coefficients of view texel `(i, j)`, `[R.., G.., B..]` (contiguous: the
    /// kernel reads a pixel's colours as one block). Panics if out of range.
    #[inline]
    pub fn texel_rgb(&self, i: usize, j: usize) -> &[f32] {
        let t = 3 * num_terms(self.bands);
        let o = (j * self.nu + i) * t;
        &self.coeffs[o..o + t]
    }

    /// Mutable twin of [`ShDataset::texel`]; setting a non-finite value is the caller's
    /// responsibility (file writing rejects it).
    #[inline]
    pub fn texel_mut(&mut self, i: usize, j: usize, c: usize) -> &mut [f32] {
        let t = num_terms(self.bands);
        assert!(c < 3);
        let o = ((j * self.nu + i) * 3 + c) * t;
        &mut self.coeffs[o..o + t]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truncation_keeps_leading_terms_and_rejects_bad_counts() {
        let (nu, nv, l) = (3, 2, 4);
        let t = num_terms(l);
        let coeffs: Vec<f32> = (0..nu * nv * 3 * t).map(|i| i as f32).collect();
        let ds = ShDataset::new(nu, nv, l, true, "test", coeffs).unwrap();
        let tr = ds.truncated(2).unwrap();
        assert_eq!(tr.bands(), 2);
        for j in 0..nv {
            for i in 0..nu {
                for c in 0..3 {
                    assert_eq!(tr.texel(i, j, c), &ds.texel(i, j, c)[..4]);
                }
            }
        }
        assert_eq!(ds.truncated(l).unwrap().coeffs(), ds.coeffs());
        assert!(ds.truncated(0).is_err());
        assert!(ds.truncated(l + 1).is_err());
    }

    #[test]
    fn constructor_rejects_bad_input() {
        assert_eq!(
            ShDataset::new(2, 2, 1, false, "", vec![0.0; 11]),
            Err(ShDataError::Size {
                got: 11,
                expected: 12
            })
        );
        assert!(matches!(
            ShDataset::new(2, 2, 1, false, "", vec![f32::NAN; 12]),
            Err(ShDataError::NonFinite(0))
        ));
        assert!(ShDataset::zeros(2, 2, 0, false, "").is_err());
        assert!(ShDataset::zeros(2, 2, MAX_BANDS + 1, false, "").is_err());
        assert!(ShDataset::zeros(0, 2, 2, false, "").is_err());
    }
}
