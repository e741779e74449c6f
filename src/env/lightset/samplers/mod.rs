//! Samplers that collapse a [`Probe`](crate::env::Probe) into a
//! [`LightSet`](crate::env::LightSet) (thesis 3.2.2-3.2.3).
//!
//! Design rule: a sampler decides *where* lights go; the energy is always the probe's.
//! Every sampler returns lights whose powers sum to
//! [`Probe::total_power`](crate::env::Probe::total_power) (to f32 rounding, far below 1e-5
//! relative), either because each light carries the exact summed power of a set of texels
//! that tile the probe (uniform, median cut, Lloyd, full), or, for the Monte Carlo samplers
//! (importance, stratified), because the estimator's per-channel sums are rescaled to the
//! exact totals (see [`importance()`]).
//!
//! Per-texel weight (the "monochrome map" of Algorithms 1 and 2) is
//! `luminance(RGB) x exact solid angle` ([`crate::env::luminance`],
//! [`crate::conventions::probe_texel_solid_angle`]); light positions are texel centres or
//! energy centroids, never image corners, so there is no half-texel offset.
//!
//! A black probe (zero total weight) yields an empty light set from every sampler: it
//! has no energy to carry.
//!
//! **Changing a sampler's output** (a different light, power or order for the same probe
//! and [`SamplerConfig`]) requires bumping
//! [`LIGHT_SET_ALGORITHM_VERSION`](crate::env::lightset::prepare::LIGHT_SET_ALGORITHM_VERSION), so no
//! light-set cache entry written by older code is read; a refactor that keeps every bit
//! does not.
//!
//! # Layout
//! One file per light-set builder, each a function of the probe and [`SamplerConfig`]'s
//! parameters:
//! - `uniform.rs`: [`uniform()`], uniform random directions carrying their Voronoi cells,
//!   with the sphere map, its inverse and pdf ([`uniform_direction`], [`uniform_inverse`],
//!   [`uniform_pdf`]).
//! - `importance.rs`: [`importance()`], thesis Algorithm 1; [`ImportanceSampler`] (the
//!   distribution over texels with its pdf in 1/sr and inverse) and [`rescale_to_total`].
//! - `stratified.rs`: [`importance_stratified`], Algorithm 1 fed a Latin hypercube
//!   ([`stratified_uniforms`]).
//! - `median_cut.rs`: [`median_cut()`], thesis Algorithm 2 / Debevec 2005, with its
//!   [`MedianCut`] result ([`Region`], [`Cut`], [`CutAxis`]).
//! - `lloyd.rs`: [`lloyd()`], median cut relaxed by weighted spherical k-means.
//! - `full.rs`: [`full_probe`], every lit texel a light (the converged reference).
//!
//! Shared pieces, each in its own file:
//! - `config.rs`: [`SamplerConfig`], which sampler with which parameters, and its stable
//!   hash.
//! - [`crate::env::probe::ProbeTables`] (beside the probe): the per-texel weight, power and
//!   direction every sampler reads.
//! - `distribution2d.rs`: [`Distribution2D`], the discrete 2-D distribution of Algorithm 1
//!   with its probability and inverse.
//! - `summed_area.rs`: the summed-area table behind median cut's O(1) rectangle sums
//!   (crate-private).
//! - `voronoi.rs`: [`nearest_light_cells`], the texel -> nearest light assignment of the
//!   uniform and Lloyd samplers, and the lights that carry their cells.
//! - `tests.rs`: tests across samplers against independent references; the utilities'
//!   own tests sit in their files.
//!
//! Every item is re-exported here: `crate::env::lightset::samplers::X`.

mod config;
mod distribution2d;
mod full;
mod importance;
mod lloyd;
mod median_cut;
mod stratified;
mod summed_area;
#[cfg(test)]
mod tests;
mod uniform;
mod voronoi;

pub use config::SamplerConfig;
pub use distribution2d::Distribution2D;
pub use full::full_probe;
pub use importance::{importance, rescale_to_total, ImportanceSampler};
pub use lloyd::{lloyd, lloyd_with_progress, RELAXATION_WIDTH};
pub use median_cut::{median_cut, median_cut_with_progress, Cut, CutAxis, MedianCut, Region};
pub use stratified::{importance_stratified, stratified_uniforms};
pub use uniform::{uniform, uniform_direction, uniform_inverse, uniform_pdf};
pub use voronoi::nearest_light_cells;
