//! SH BRDF data sets: coefficient tables `c_lm(view texel)` and optional basis tables
//! `Y_lm(light texel)` on hemispherical grids (thesis 2.3.3-2.3.4 Def. 12, 3.1.3-3.1.5).
//!
//! Design rule: the CPU lookups reproduce the GPU's texture filtering exactly (the texel
//! arithmetic lives in [`crate::conventions`]: [`hemi_nearest_texel`] for `GL_NEAREST`,
//! [`hemi_bilinear_texels`] for `GL_LINEAR`), so this module can serve as an oracle for a
//! GPU build that stores the tables as 3D textures.
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
//!   2.3.3 and its reference \[7\]), and [`crate::acquire`] projects with [`eval_sh_f64`] at
//!   quadrature nodes. The function the coefficients describe is `sum_k c_k Y_k` with the
//!   analytic `Y_k`;
//! - the thesis stores the basis in a texture only because its fragment shader cannot
//!   evaluate it (3.1.4: "the fourth component stores the basis value for the spherical
//!   harmonics function", sampled with `GL_NEAREST` on its hardware). A table is the same
//!   functions sampled at texel centres; a nearest or bilinear lookup between centres is a
//!   discretisation error of that GPU build (at 8 bands on a 16 x 8 grid, far larger than
//!   any rounding), which an oracle must expose, not reproduce;
//! - one definition is what makes every light kind agree: a directional light and the same
//!   light as a distant point light must give the same image, whichever kernel path, the
//!   scalar oracle or the f64 reference shades it, with or without the band skip
//!   (tests/sh_basis.rs). Earlier versions used the table for point lights only and so
//!   rendered the two differently (FLIP mean 0.053).
//!
//! So [`ShDataset::reconstruct`], [`Brdf::eval`], [`Brdf::eval_f64`] and the kernels all use
//! the analytic basis. The table is kept (files round-trip it, [`ShDataset::truncated`]
//! truncates it with the coefficients) for GPU builds to upload, and
//! [`ShDataset::set_basis_table`] accepts only a table that *is* this basis at its texel
//! centres (within [`BASIS_TABLE_TOLERANCE`]), so a file cannot carry a table in another
//! convention that the CPU would silently disagree with. What a GPU build computes with its
//! table is [`ShDataset::reconstruct_tabulated`], for measuring that build's discretisation
//! error; nothing in the renderer calls it.

use super::basis::{eval_sh_f32, eval_sh_f64, num_terms};
use crate::brdf::Brdf;
use crate::conventions::{
    hemi_bilinear_texels, hemi_nearest_texel, hemi_texcoord, hemi_texel_angles_f64, local_angles,
    local_direction_f64,
};
use glam::Vec3;

/// Largest number of bands a data set may have (all l < 32, 1024 terms): evaluation uses a
/// fixed stack buffer of this many terms, and file readers reject larger counts as absurd.
pub const MAX_BANDS: usize = 32;

/// Band energy threshold of a data set that declares none (in memory or in a file without
/// `brdfkit.band_threshold`): 0, every stored band is shaded, so files written before the
/// attribute existed render exactly as before.
pub const DEFAULT_BAND_THRESHOLD: f32 = 0.0;

/// Largest absolute difference between a basis table value and the analytic basis
/// ([`eval_sh_f64`]) at the texel's centre that [`ShDataset::set_basis_table`] accepts:
/// 1e-4. Basis values are O(1) (band peaks 0.28 at l = 0 to about 2.2 at l = 31); a table
/// tabulated in f64 and stored as f32 is within 1.2e-7 of it, one evaluated by the f32
/// recurrence within about 5e-6 for l < 10 (`sh::basis` tests); a table in another
/// convention (Condon-Shortley phase, another normalisation or ordering, another frame)
/// differs by O(0.1) or more.
pub const BASIS_TABLE_TOLERANCE: f32 = 1e-4;

/// Texture filter used for a table lookup. In scene files: `"nearest"` or `"bilinear"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Lookup {
    /// `GL_NEAREST`: the texel containing `(s, t)`.
    Nearest,
    /// `GL_LINEAR`: bilinear blend of the four nearest texel centres.
    Bilinear,
}

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

/// Table of SH basis values `Y_k` at the texel centres of an `nu x nv` light hemisphere
/// grid (layout in the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct ShBasisTable {
    nu: usize,
    nv: usize,
    bands: usize,
    values: Vec<f32>,
}

impl ShBasisTable {
    /// Tabulates the basis at the texel centres (computed in f64, stored as f32).
    /// Fails (Err) on a band count outside `1..=MAX_BANDS` or an empty grid.
    pub fn tabulate(nu: usize, nv: usize, bands: usize) -> Result<Self, ShDataError> {
        check_grid(nu, nv, bands)?;
        let t = num_terms(bands);
        let mut values = vec![0.0f32; nu * nv * t];
        let mut y = vec![0.0f64; t];
        for j in 0..nv {
            for i in 0..nu {
                let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
                eval_sh_f64(local_direction_f64(p, a), &mut y);
                let o = (j * nu + i) * t;
                for k in 0..t {
                    values[o + k] = y[k] as f32;
                }
            }
        }
        Ok(ShBasisTable {
            nu,
            nv,
            bands,
            values,
        })
    }

    /// Builds a table from raw values (layout in the module doc). Err on a size mismatch,
    /// a bad band count, an empty grid or a non-finite value.
    pub fn from_raw(
        nu: usize,
        nv: usize,
        bands: usize,
        values: Vec<f32>,
    ) -> Result<Self, ShDataError> {
        check_grid(nu, nv, bands)?;
        let expected = nu * nv * num_terms(bands);
        if values.len() != expected {
            return Err(ShDataError::Size {
                got: values.len(),
                expected,
            });
        }
        if let Some(p) = values.iter().position(|v| !v.is_finite()) {
            return Err(ShDataError::NonFinite(p));
        }
        Ok(ShBasisTable {
            nu,
            nv,
            bands,
            values,
        })
    }

    /// `(nu, nv)`.
    pub fn grid(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// Number of bands.
    pub fn bands(&self) -> usize {
        self.bands
    }

    /// The same table keeping the terms of the first `bands` bands. Err (`Bands`) unless
    /// `1 <= bands <= self.bands()`.
    pub fn truncated(&self, bands: usize) -> Result<Self, ShDataError> {
        if bands == 0 || bands > self.bands {
            return Err(ShDataError::Bands(bands));
        }
        let (old, new) = (num_terms(self.bands), num_terms(bands));
        let values = self
            .values
            .chunks_exact(old)
            .flat_map(|b| b[..new].iter().copied())
            .collect();
        Ok(ShBasisTable {
            nu: self.nu,
            nv: self.nv,
            bands,
            values,
        })
    }

    /// Ok if every value is the analytic basis ([`eval_sh_f64`]) at its texel centre within
    /// [`BASIS_TABLE_TOLERANCE`]; else the first texel and term that is not
    /// (`BasisTable`).
    pub fn check_is_analytic_basis(&self) -> Result<(), ShDataError> {
        let t = num_terms(self.bands);
        let mut y = vec![0.0f64; t];
        for j in 0..self.nv {
            for i in 0..self.nu {
                let (p, a) = hemi_texel_angles_f64(i, j, self.nu, self.nv);
                eval_sh_f64(local_direction_f64(p, a), &mut y);
                for (k, (&got, &expected)) in self.texel(i, j).iter().zip(&y).enumerate() {
                    if (got as f64 - expected).abs() > BASIS_TABLE_TOLERANCE as f64 {
                        return Err(ShDataError::BasisTable {
                            i,
                            j,
                            k,
                            got,
                            expected,
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// Raw values (layout in the module doc).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The `T` basis values of texel `(i, j)`. Panics if out of range.
    #[inline]
    pub fn texel(&self, i: usize, j: usize) -> &[f32] {
        let t = num_terms(self.bands);
        let o = (j * self.nu + i) * t;
        &self.values[o..o + t]
    }

    /// Filtered basis values at texture coordinates `(s, t)` written into `out`
    /// (`out.len()` must be `bands^2`, else panic).
    pub fn lookup(&self, s: f32, t: f32, mode: Lookup, out: &mut [f32]) {
        assert_eq!(out.len(), num_terms(self.bands), "basis output length");
        match mode {
            Lookup::Nearest => {
                let (i, j) = hemi_nearest_texel(s, t, self.nu, self.nv);
                out.copy_from_slice(self.texel(i, j));
            }
            Lookup::Bilinear => {
                out.fill(0.0);
                for (i, j, w) in hemi_bilinear_texels(s, t, self.nu, self.nv) {
                    for (o, v) in out.iter_mut().zip(self.texel(i, j)) {
                        *o += w * v;
                    }
                }
            }
        }
    }
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
        out.band_threshold = self.band_threshold;
        out.basis = self
            .basis
            .as_ref()
            .map(|tb| tb.truncated(bands))
            .transpose()?;
        Ok(out)
    }

    /// The declared band energy threshold: the largest fraction of the coefficient energy
    /// the renderer may drop by shading with fewer bands ([`ShDataset::effective_bands`]).
    /// 0 (the default, [`DEFAULT_BAND_THRESHOLD`]) keeps every band.
    pub fn band_threshold(&self) -> f32 {
        self.band_threshold
    }

    /// Declares the band energy threshold. Err (`BandThreshold`) unless
    /// `0 <= threshold < 1` (NaN is rejected).
    pub fn set_band_threshold(&mut self, threshold: f32) -> Result<(), ShDataError> {
        if !(0.0..1.0).contains(&threshold) {
            return Err(ShDataError::BandThreshold(threshold));
        }
        self.band_threshold = threshold;
        Ok(())
    }

    /// Coefficient energy per band, `E_l = sum over texels, colours and m of c_lm^2`
    /// (f64 sums in texel order), `bands()` values.
    pub fn band_energies(&self) -> Vec<f64> {
        let nt = num_terms(self.bands);
        let mut e = vec![0.0f64; self.bands];
        for block in self.coeffs.chunks_exact(nt) {
            for (l, el) in e.iter_mut().enumerate() {
                *el += block[l * l..(l + 1) * (l + 1)]
                    .iter()
                    .map(|&c| c as f64 * c as f64)
                    .sum::<f64>();
            }
        }
        e
    }

    /// The bands shading needs: the smallest `L >= 1` such that the energy of the dropped
    /// bands `l >= L` is at most `band_threshold() x` the total ([`ShDataset::band_energies`]).
    /// Equals `bands()` when the threshold is 0 or nothing can be dropped; an all-zero data
    /// set needs 1 band. The change this makes to a pixel is bounded in
    /// [`crate::kernel::skip`].
    pub fn effective_bands(&self) -> usize {
        if self.band_threshold <= 0.0 {
            return self.bands;
        }
        let e = self.band_energies();
        let total: f64 = e.iter().sum();
        let limit = self.band_threshold as f64 * total;
        let mut dropped = 0.0f64;
        let mut keep = self.bands;
        while keep > 1 && dropped + e[keep - 1] <= limit {
            dropped += e[keep - 1];
            keep -= 1;
        }
        keep
    }

    /// Largest Euclidean norm of one colour's coefficient vector over the view texels,
    /// per colour (RGB), restricted to the terms of bands `from..bands()`.
    pub fn max_texel_norm(&self, from: usize) -> Vec3 {
        let nt = num_terms(self.bands);
        let k0 = (from * from).min(nt);
        let mut m = [0.0f64; 3];
        for (b, block) in self.coeffs.chunks_exact(nt).enumerate() {
            let n2: f64 = block[k0..].iter().map(|&c| c as f64 * c as f64).sum();
            m[b % 3] = m[b % 3].max(n2.sqrt());
        }
        Vec3::new(m[0] as f32, m[1] as f32, m[2] as f32)
    }

    /// Attaches a basis table for GPU builds to upload (thesis 3.1.4-3.1.5); rendering keeps
    /// the analytic basis (module doc). Err (`Bands`) if its band count differs from the
    /// data set's, (`BasisTable`) if it is not the analytic basis at its texel centres
    /// ([`ShBasisTable::check_is_analytic_basis`]).
    pub fn set_basis_table(&mut self, table: Option<ShBasisTable>) -> Result<(), ShDataError> {
        if let Some(tb) = &table {
            if tb.bands != self.bands {
                return Err(ShDataError::Bands(tb.bands));
            }
            tb.check_is_analytic_basis()?;
        }
        self.basis = table;
        Ok(())
    }

    /// The basis table, if one is set (not used for rendering, see the module doc).
    pub fn basis_table(&self) -> Option<&ShBasisTable> {
        self.basis.as_ref()
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

    fn as_sh(&self) -> Option<&ShDataset> {
        Some(self)
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
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return glam::DVec3::ZERO;
        }
        let nt = num_terms(self.bands);
        let mut ybuf = [0.0f64; MAX_BANDS * MAX_BANDS];
        let y = &mut ybuf[..nt];
        eval_sh_f64(wi, y);
        let mut c = vec![0.0f32; 3 * nt];
        let (p, a) = local_angles(wo.as_vec3());
        let (s, t) = hemi_texcoord(p, a);
        self.lookup_coeffs(s, t, self.coeff_lookup, &mut c);
        let dot = |o: usize| -> f64 { (0..nt).map(|k| c[o + k] as f64 * y[k]).sum() };
        glam::DVec3::new(dot(0), dot(nt), dot(2 * nt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conventions::local_direction;
    use rand::{Rng, SeedableRng};

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

    /// Scalar GL reference written as a tent filter over *all* texels with periodic distance
    /// in s and a clamped coordinate in t (OpenGL 4.6 spec 8.14.2 restated), independent of
    /// the floor/fract arithmetic under test.
    fn gl_linear_ref(tab: &[f64], nu: usize, nv: usize, s: f64, t: f64) -> f64 {
        let u = s * nu as f64 - 0.5;
        let v = (t * nv as f64 - 0.5).clamp(0.0, (nv - 1) as f64);
        let mut acc = 0.0;
        for j in 0..nv {
            let wj = (1.0 - (v - j as f64).abs()).max(0.0);
            for i in 0..nu {
                let mut d = (u - i as f64).rem_euclid(nu as f64);
                if d > nu as f64 / 2.0 {
                    d -= nu as f64;
                }
                let wi = (1.0 - d.abs()).max(0.0);
                acc += wi * wj * tab[j * nu + i];
            }
        }
        acc
    }

    /// GL_NEAREST reference: the texel whose centre is nearest, ties resolved to the texel
    /// above the edge, periodic in s, clamped in t.
    fn gl_nearest_ref(tab: &[f64], nu: usize, nv: usize, s: f64, t: f64) -> f64 {
        let pick = |x: f64, n: usize, periodic: bool| -> usize {
            let mut best = 0;
            let mut bd = f64::INFINITY;
            for i in 0..n {
                let mut d = x * n as f64 - (i as f64 + 0.5);
                if periodic {
                    d = (d + n as f64 / 2.0).rem_euclid(n as f64) - n as f64 / 2.0;
                }
                // ties: prefer d = -0.5 (texel above the edge) over d = +0.5
                let key = if (-0.5..0.5).contains(&d) {
                    d.abs() - 1e-9
                } else {
                    d.abs()
                };
                if key < bd {
                    bd = key;
                    best = i;
                }
            }
            best
        };
        let i = pick(s, nu, true);
        let j = if t < 0.0 {
            0
        } else {
            pick(t.min(1.0 - 1e-12), nv, false)
        };
        tab[j * nu + i]
    }

    fn sample_coords() -> Vec<(f32, f32)> {
        let (nu, nv) = (8usize, 4usize);
        let mut v = vec![];
        // centres and edges (exact in f32 for power-of-two grids)
        for i in 0..=2 * nu {
            for j in 0..=2 * nv {
                v.push((i as f32 / (2 * nu) as f32, j as f32 / (2 * nv) as f32));
            }
        }
        // seam and clamp regions
        for &s in &[0.0f32, 1e-4, 0.01, 0.99, 0.9999, 1.0, -0.01, 1.01] {
            for &t in &[0.0f32, 0.01, 0.06, 0.5, 0.94, 0.99, 1.0] {
                v.push((s, t));
            }
        }
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        for _ in 0..500 {
            v.push((rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0)));
        }
        v
    }

    fn random_dataset(nu: usize, nv: usize, bands: usize, seed: u64) -> ShDataset {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
        let n = nu * nv * 3 * num_terms(bands);
        let c: Vec<f32> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
        ShDataset::new(nu, nv, bands, false, "random test data", c).unwrap()
    }

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

    #[test]
    fn basis_table_lookups_match_gl_reference_and_centres_are_exact() {
        let (nu, nv, bands) = (16, 8, 3);
        let tb = ShBasisTable::tabulate(nu, nv, bands).unwrap();
        let nt = num_terms(bands);
        let mut out = vec![0.0f32; nt];
        let mut y = vec![0.0f64; nt];
        for j in 0..nv {
            for i in 0..nu {
                let (s, t) = (texel(i, nu), texel(j, nv));
                tb.lookup(s, t, Lookup::Bilinear, &mut out);
                let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
                eval_sh_f64(local_direction_f64(p, a), &mut y);
                for k in 0..nt {
                    assert!((out[k] as f64 - y[k]).abs() < 1e-6);
                }
            }
        }
        for (s, t) in sample_coords() {
            tb.lookup(s, t, Lookup::Bilinear, &mut out);
            for (k, got) in out.iter().enumerate().take(nt) {
                let tab: Vec<f64> = (0..nv)
                    .flat_map(|j| (0..nu).map(move |i| (i, j)))
                    .map(|(i, j)| tb.texel(i, j)[k] as f64)
                    .collect();
                let r = gl_linear_ref(&tab, nu, nv, s as f64, t as f64);
                assert!((*got as f64 - r).abs() < 2e-6, "s={s} t={t} k={k}");
            }
        }
    }

    fn texel(i: usize, n: usize) -> f32 {
        crate::conventions::texel_center(i, n)
    }

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

    #[test]
    fn a_table_in_another_convention_is_rejected_and_truncation_keeps_the_table() {
        let bands = 4;
        let mut ds = random_dataset(8, 4, bands, 7);
        let tb = ShBasisTable::tabulate(10, 5, bands).unwrap();
        // Condon-Shortley phase: (-1)^m on every term with odd |m|.
        let t = num_terms(bands);
        let cs: Vec<f32> = tb
            .values()
            .iter()
            .enumerate()
            .map(|(n, &v)| {
                let (_, m) = crate::sh::basis::sh_lm(n % t);
                if m % 2 != 0 {
                    -v
                } else {
                    v
                }
            })
            .collect();
        let cs = ShBasisTable::from_raw(10, 5, bands, cs).unwrap();
        assert!(matches!(
            ds.set_basis_table(Some(cs)),
            Err(ShDataError::BasisTable { .. })
        ));
        assert!(ds.basis_table().is_none());
        ds.set_basis_table(Some(tb)).unwrap();
        let tr = ds.truncated(2).unwrap();
        assert_eq!(
            tr.basis_table(),
            Some(&ShBasisTable::tabulate(10, 5, 2).unwrap())
        );
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
