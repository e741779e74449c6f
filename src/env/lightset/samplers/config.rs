//! [`SamplerConfig`]: which sampler and its parameters, the one value that names a light
//! set (cache keys, light-set file headers, scene files).
//!
//! Design rule: the configuration alone decides the light set of a given probe; its hash
//! ([`SamplerConfig::hash_into`]) is stable across runs and platforms and feeds every
//! light-set cache key. The hash says *which* light set was asked for, not *how* it is
//! computed: when a sampler's output changes for the same configuration, bump
//! [`crate::env::lightset::prepare::LIGHT_SET_ALGORITHM_VERSION`] instead.

use super::{full_probe, importance, importance_stratified, uniform};
use super::{lloyd_with_progress, median_cut_with_progress};
use crate::env::{LightSet, Probe};
use crate::hash::StableHasher;
use crate::progress::Progress;
use serde::{Deserialize, Serialize};

/// Which sampler and its parameters: the unit of caching ([`crate::env::lightset::prepare::file_cache_key`]) and
/// of light-set file headers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "sampler", rename_all = "kebab-case")]
pub enum SamplerConfig {
    /// [`uniform()`]: `n` uniform random directions, each carrying its Voronoi cell.
    Uniform { n: usize, seed: u64 },
    /// [`importance()`]: thesis Algorithm 1, i.i.d. uniform numbers.
    Importance { n: usize, seed: u64 },
    /// [`importance_stratified`]: Algorithm 1 fed stratified numbers.
    Stratified { n: usize, seed: u64 },
    /// [`median_cut()`](super::median_cut): thesis Algorithm 2 / Debevec 2005.
    MedianCut { n: usize },
    /// [`lloyd()`](super::lloyd): median cut relaxed by weighted spherical k-means.
    Lloyd { n: usize, iterations: usize },
    /// [`full_probe`]: every texel a light (the converged reference).
    Full,
}

impl SamplerConfig {
    /// Short name: `uniform`, `importance`, `stratified`, `median-cut`, `lloyd`, `full`.
    pub fn name(&self) -> &'static str {
        match self {
            SamplerConfig::Uniform { .. } => "uniform",
            SamplerConfig::Importance { .. } => "importance",
            SamplerConfig::Stratified { .. } => "stratified",
            SamplerConfig::MedianCut { .. } => "median-cut",
            SamplerConfig::Lloyd { .. } => "lloyd",
            SamplerConfig::Full => "full",
        }
    }

    /// Requested number of lights (`None` for the full probe).
    pub fn n(&self) -> Option<usize> {
        match *self {
            SamplerConfig::Uniform { n, .. }
            | SamplerConfig::Importance { n, .. }
            | SamplerConfig::Stratified { n, .. }
            | SamplerConfig::MedianCut { n }
            | SamplerConfig::Lloyd { n, .. } => Some(n),
            SamplerConfig::Full => None,
        }
    }

    /// Seed of the random samplers.
    pub fn seed(&self) -> Option<u64> {
        match *self {
            SamplerConfig::Uniform { seed, .. }
            | SamplerConfig::Importance { seed, .. }
            | SamplerConfig::Stratified { seed, .. } => Some(seed),
            SamplerConfig::MedianCut { .. } | SamplerConfig::Lloyd { .. } | SamplerConfig::Full => {
                None
            }
        }
    }

    /// Runs the sampler on a probe.
    pub fn run(&self, probe: &Probe) -> LightSet {
        self.run_with_progress(probe, &Progress::hidden())
    }

    /// [`SamplerConfig::run`], counting on `progress` what the sampler iterates (Lloyd
    /// rounds, median-cut levels; one step for the single-pass samplers), in the unit
    /// [`SamplerConfig::progress_unit`] names. Counting does not change the light set.
    pub fn run_with_progress(&self, probe: &Probe, progress: &Progress) -> LightSet {
        let single_pass = |f: &dyn Fn() -> LightSet| {
            progress.set_length(1);
            let ls = f();
            progress.inc(1);
            ls
        };
        match *self {
            SamplerConfig::Uniform { n, seed } => single_pass(&|| uniform(probe, n, seed)),
            SamplerConfig::Importance { n, seed } => single_pass(&|| importance(probe, n, seed)),
            SamplerConfig::Stratified { n, seed } => {
                single_pass(&|| importance_stratified(probe, n, seed))
            }
            SamplerConfig::MedianCut { n } => median_cut_with_progress(probe, n, progress).lights,
            SamplerConfig::Lloyd { n, iterations } => {
                lloyd_with_progress(probe, n, iterations, progress)
            }
            SamplerConfig::Full => single_pass(&|| full_probe(probe)),
        }
    }

    /// What [`SamplerConfig::run_with_progress`] counts: `iterations` (Lloyd: the
    /// median-cut seed, then each relaxation round), `levels` (median cut), `passes`.
    pub fn progress_unit(&self) -> &'static str {
        match self {
            SamplerConfig::Lloyd { .. } => "iterations",
            SamplerConfig::MedianCut { .. } => "levels",
            SamplerConfig::Uniform { .. }
            | SamplerConfig::Importance { .. }
            | SamplerConfig::Stratified { .. }
            | SamplerConfig::Full => "passes",
        }
    }

    /// Feeds the configuration into a stable hash: name, then each parameter as a u64
    /// (absent ones as `u64::MAX`).
    pub fn hash_into(&self, h: &mut StableHasher) {
        h.write(self.name().as_bytes());
        h.write(&[0]);
        h.write_u64(self.n().map_or(u64::MAX, |n| n as u64));
        h.write_u64(self.seed().unwrap_or(u64::MAX));
        let iters = match *self {
            SamplerConfig::Lloyd { iterations, .. } => iterations as u64,
            SamplerConfig::Uniform { .. }
            | SamplerConfig::Importance { .. }
            | SamplerConfig::Stratified { .. }
            | SamplerConfig::MedianCut { .. }
            | SamplerConfig::Full => u64::MAX,
        };
        h.write_u64(iters);
    }
}
