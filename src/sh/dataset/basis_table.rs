//! The basis table: SH basis values `Y_k` tabulated at the texel centres of a light grid
//! ([`ShBasisTable`], the `shTexture` of thesis Code 4, 3.1.4-3.1.5), and how a data set
//! accepts one ([`ShDataset::set_basis_table`]).
//!
//! Design rule: a table is a copy of the analytic basis of [`crate::sh::basis`] for GPU builds
//! to upload, never a definition: a data set accepts only a table within
//! [`BASIS_TABLE_TOLERANCE`] of the analytic basis at every texel centre, and no renderer path
//! reads it (see the parent module doc).

use super::{check_grid, Lookup, ShDataError, ShDataset};
use crate::conventions::{
    hemi_bilinear_texels, hemi_nearest_texel, hemi_texel_angles_f64, local_direction_f64,
};
use crate::sh::basis::{eval_sh_f64, num_terms};

/// Largest absolute difference between a basis table value and the analytic basis
/// ([`eval_sh_f64`]) at the texel's centre that [`ShDataset::set_basis_table`] accepts:
/// 1e-4. Basis values are O(1) (band peaks 0.28 at l = 0 to about 2.2 at l = 31); a table
/// tabulated in f64 and stored as f32 is within 1.2e-7 of it, one evaluated by the f32
/// recurrence within about 5e-6 for l < 10 (`sh::basis` tests); a table in another
/// convention (Condon-Shortley phase, another normalisation or ordering, another frame)
/// differs by O(0.1) or more.
pub const BASIS_TABLE_TOLERANCE: f32 = 1e-4;

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

impl ShDataset {
    /// Attaches a basis table for GPU builds to upload (thesis 3.1.4-3.1.5); rendering keeps
    /// the analytic basis (module doc). Err (`Bands`) if its band count differs from the
    /// data set's, (`BasisTable`) if it is not the analytic basis at its texel centres
    /// ([`ShBasisTable::check_is_analytic_basis`]).
    pub fn set_basis_table(&mut self, table: Option<ShBasisTable>) -> Result<(), ShDataError> {
        if let Some(tb) = &table {
            if tb.bands() != self.bands {
                return Err(ShDataError::Bands(tb.bands()));
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
}

#[cfg(test)]
mod tests {
    use super::super::gl_reference::{gl_linear_ref, random_dataset, sample_coords, texel};
    use super::*;

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
}
