//! Stratified importance sampling ([`importance_stratified`]): Algorithm 1 fed a Latin
//! hypercube of `[0,1)^2` ([`stratified_uniforms`]) instead of i.i.d. numbers.
//!
//! Design rule: only the uniform numbers change; the distribution, the light positions
//! and the powers are [`super::ImportanceSampler`]'s, so the two samplers differ in
//! clumping and never in energy.

use super::ImportanceSampler;
use crate::env::{LightSet, Probe};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// `n` stratified pairs in `[0,1)^2` (Latin hypercube): `xi_1 = (i + u_i)/n` in order,
/// `xi_2 = (pi(i) + v_i)/n` for a random permutation `pi`, so each marginal has exactly
/// one sample per `1/n` stratum. Works for any `n` (a square jittered grid would not).
pub fn stratified_uniforms(n: usize, seed: u64) -> Vec<(f64, f64)> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut perm: Vec<usize> = (0..n).collect();
    perm.shuffle(&mut rng);
    (0..n)
        .map(|i| {
            let a = (i as f64 + rng.gen::<f64>()) / n as f64;
            let b = (perm[i] as f64 + rng.gen::<f64>()) / n as f64;
            // (i + u)/n can round to 1.0 for u close to 1; keep it in [0,1).
            (a.min(1.0 - f64::EPSILON), b.min(1.0 - f64::EPSILON))
        })
        .collect()
}

/// Importance sampling (Algorithm 1) fed [`stratified_uniforms`]: the row choice is
/// stratified along the marginal CDF, which removes most clumping.
pub fn importance_stratified(probe: &Probe, n: usize, seed: u64) -> LightSet {
    let Some(s) = ImportanceSampler::new(probe) else {
        return LightSet::default();
    };
    s.lights_from_uniforms(&stratified_uniforms(n, seed))
}
