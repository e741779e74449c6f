//! The band skip policy: a data set's declared band energy threshold and the bands shading
//! needs under it ([`ShDataset::effective_bands`]), with the per-band energies and texel
//! norms the kernel's error bound uses ([`crate::kernel::skip`]).
//!
//! Design rule: the policy is data, declared by the data set (in files:
//! `brdfkit.band_threshold`, [`crate::sh::file`]); the default [`DEFAULT_BAND_THRESHOLD`] = 0
//! keeps every band, so a data set that declares nothing renders with all its bands.

use super::{ShDataError, ShDataset};
use crate::sh::basis::num_terms;
use glam::Vec3;

/// Band energy threshold of a data set that declares none (in memory or in a file without
/// `brdfkit.band_threshold`): 0, every stored band is shaded, so files written before the
/// attribute existed render exactly as before.
pub const DEFAULT_BAND_THRESHOLD: f32 = 0.0;

impl ShDataset {
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
}
