//! Importance sampling, thesis Algorithm 1 ([`importance()`]): [`ImportanceSampler`] is
//! the probe's [`Distribution2D`] of `luminance x solid angle` with texel directions, its
//! density over directions and its inverse; [`rescale_to_total`] makes the Monte Carlo
//! powers carry the probe's exact total.
//!
//! Design rule: a sample of texel `t` becomes a light at the texel centre with the
//! estimator's power `L_t / (n pdf_t)`; the per-channel sums are then rescaled to the
//! probe's exact totals, so Monte Carlo noise moves energy between lights but never
//! changes the total.

use super::Distribution2D;
use crate::env::probe::ProbeTables;
use crate::env::{LightSet, Probe};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::ops::Range;

/// Thesis Algorithm 1 as a reusable 2D distribution over texels: the marginal row CDF is
/// built from row sums of `luminance x solid angle` (the solid angle replaces the thesis's
/// `cos(linspace)` factor), the conditional column CDFs from each row's weights; a pair
/// of numbers in `[0,1)^2` picks a row and then a column by binary search
/// ([`Distribution2D`]).
///
/// The discrete texel probability is `p_t = weight_t / total`; as a density over
/// directions (texel centres standing for their texel) it is `p_t / Omega_t` in 1/sr
/// ([`ImportanceSampler::pdf`]). The inverse map direction -> texel -> rectangle of
/// `[0,1)^2` is [`ImportanceSampler::invert`].
#[derive(Clone, Debug)]
pub struct ImportanceSampler {
    tables: ProbeTables,
    /// The CDFs of `tables.weight`.
    dist: Distribution2D,
    rotation: f64,
}

impl ImportanceSampler {
    /// Builds the CDFs (O(texels)). Returns `None` for a black probe.
    pub fn new(probe: &Probe) -> Option<Self> {
        let tables = ProbeTables::new(probe);
        if tables.total_weight <= 0.0 {
            return None;
        }
        let dist = Distribution2D::new(&tables.weight, tables.width, tables.height)?;
        Some(ImportanceSampler {
            tables,
            dist,
            rotation: probe.rotation(),
        })
    }

    /// The texel `(row, col)` that `(xi_1, xi_2)` in `[0,1)^2` selects: the first row whose
    /// CDF exceeds `xi_1`, then the first column of that row whose CDF exceeds `xi_2`
    /// (binary search; zero-weight texels are never selected). [`Distribution2D::sample`].
    pub fn sample_texel(&self, xi1: f64, xi2: f64) -> (usize, usize) {
        self.dist.sample(xi1, xi2)
    }

    /// Discrete probability of texel `(row, col)`: `weight / total`.
    pub fn texel_probability(&self, row: usize, col: usize) -> f64 {
        self.tables.weight[row * self.tables.width + col] / self.tables.total_weight
    }

    /// Texel containing world direction `d` (the inverse of [`Self::direction`]).
    pub fn texel_of(&self, d: DVec3) -> (usize, usize) {
        let (u, v) =
            crate::conventions::probe_uv(crate::conventions::rotate_about_up(d, -self.rotation));
        crate::conventions::probe_texel(u, v, self.tables.width, self.tables.height)
    }

    /// Direction of the light a sample of texel `(row, col)` produces: its centre.
    pub fn direction(&self, row: usize, col: usize) -> DVec3 {
        self.tables.dir[row * self.tables.width + col]
    }

    /// Density over directions in 1/sr: `p_texel / Omega_texel` of the texel containing
    /// `d` (piecewise constant; integrates to 1 over the sphere).
    pub fn pdf(&self, d: DVec3) -> f64 {
        let (row, col) = self.texel_of(d);
        self.texel_probability(row, col)
            / crate::conventions::probe_texel_solid_angle(
                row,
                self.tables.width,
                self.tables.height,
            )
    }

    /// The inverse of sampling: `[xi_1 range, xi_2 range]`, the half-open rectangle of
    /// `[0,1)^2` whose points [`Self::sample_texel`] maps onto the texel containing `d`
    /// ([`Self::texel_of`], then [`Distribution2D::invert`]); `None` when that texel is
    /// never sampled (zero weight).
    pub fn invert(&self, d: DVec3) -> Option<[Range<f64>; 2]> {
        let (row, col) = self.texel_of(d);
        self.dist.invert(row, col)
    }

    /// Lights from a list of uniform pairs: each sample of texel `t` becomes a light at
    /// its centre with power `L_t / (n pdf_t) = L_t Omega_t / (n p_t)` (so every light
    /// carries luminance power `total / n`); then each RGB channel is scaled by
    /// `exact total / estimated total` ([`rescale_to_total`]). Because the pdf is
    /// proportional to luminance, the luminance total is already exact and the scale only
    /// corrects colour noise.
    pub fn lights_from_uniforms(&self, xis: &[(f64, f64)]) -> LightSet {
        let n = xis.len() as f64;
        let mut ls = LightSet::with_capacity(xis.len());
        let mut lum = Vec::with_capacity(xis.len());
        for &(a, b) in xis {
            let (row, col) = self.sample_texel(a, b);
            let i = row * self.tables.width + col;
            let p = self.tables.weight[i] / self.tables.total_weight;
            ls.push(self.tables.dir[i], self.tables.power[i] / (n * p));
            lum.push(self.tables.total_weight / n);
        }
        rescale_to_total(&mut ls, self.tables.total_power, &lum);
        ls
    }
}

/// Scales each RGB channel of the powers so the channel totals equal `target` (f64).
/// If a channel sums to zero but its target is not (possible with few samples of a
/// coloured probe), that channel's target is spread over the lights in proportion to
/// `fallback` (their luminance power).
pub fn rescale_to_total(ls: &mut LightSet, target: DVec3, fallback: &[f64]) {
    let fb_total: f64 = fallback.iter().sum();
    for (ch, t) in [
        (&mut ls.irradiance_r, target.x),
        (&mut ls.irradiance_g, target.y),
        (&mut ls.irradiance_b, target.z),
    ] {
        let s: f64 = ch.iter().map(|&p| p as f64).sum();
        if s > 0.0 {
            let k = t / s;
            for p in ch.iter_mut() {
                *p = (*p as f64 * k) as f32;
            }
        } else if t > 0.0 && fb_total > 0.0 {
            for (p, f) in ch.iter_mut().zip(fallback) {
                *p = (t * f / fb_total) as f32;
            }
        }
    }
}

/// Importance sampling, thesis Algorithm 1: `n` i.i.d. pairs from `Pcg64` seeded with
/// `seed` fed to [`ImportanceSampler`]; see [`ImportanceSampler::lights_from_uniforms`]
/// for the powers. Deterministic per seed; empty for `n == 0` or a black probe.
pub fn importance(probe: &Probe, n: usize, seed: u64) -> LightSet {
    let Some(s) = ImportanceSampler::new(probe) else {
        return LightSet::default();
    };
    let mut rng = Pcg64::seed_from_u64(seed);
    let xis: Vec<(f64, f64)> = (0..n).map(|_| (rng.gen(), rng.gen())).collect();
    s.lights_from_uniforms(&xis)
}
