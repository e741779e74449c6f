//! Environment lighting: a light probe (an equirectangular HDR image of the light
//! arriving from every direction, thesis 3.2.1) prepared for shading by one of the
//! `[env]` methods.
//!
//! One concept per module:
//! - [`probe`]: the probe read, cleaned and rotated, its texel directions and exact solid
//!   angles ([`crate::conventions::probe_texel_solid_angle`]; the thesis's `cos(linspace)`
//!   weight gives the pole rows zero weight, we use the true area) and its tables
//!   ([`probe::ProbeTables`]);
//! - [`schema`]: the `[env]` table of every method ([`EnvSpec`], [`EnvMethod`],
//!   [`SamplerKind`], the defaults and their checks); `auto`, the default, chooses a method
//!   per material ([`crate::scene::env_method`]);
//! - [`lightset`]: `method = "lights"`, the probe collapsed into a [`LightSet`] of
//!   directional lights (thesis 3.2: importance sampling 3.2.2 / Algorithm 1, median cut
//!   3.2.3 / Algorithm 2; Dirac-delta lights 2.3.2) by its [`lightset::samplers`], written
//!   and read by [`lightset::file`], prepared for a scene and cached by
//!   [`lightset::prepare`];
//! - [`transfer`]: `method = "transfer"`, the full probe tabulated over normals (looked up
//!   per pixel by [`crate::shade`]);
//! - [`reflection`]: `method = "reflection"`, the full probe tabulated over reflected
//!   directions, view angles and a Fourier series about the reflected direction, baked
//!   from an isotropic material's own BRDF (looked up per pixel by [`crate::shade`]);
//! - [`lightcuts`]: `method = "lightcuts"`, every texel a light in a light tree (cut per
//!   pixel by [`crate::shade`]);
//! - [`cache_entry`]: the one entry header and check the disk caches of light sets and
//!   transfer tables share.
//!
//! Design rule: every light set carries **exactly** the probe's energy. A light set is N
//! directional lights, each a unit direction towards the light and an RGB irradiance
//! `E_k` = radiance integrated over the light's solid angle (the irradiance it gives a
//! surface facing it, W/m^2 for a probe in W/(m^2 sr); the thesis calls it the light's
//! "power"), so the illumination integral becomes
//! `L_o = sum_k f_r(w_k, w_o) cos(polar_k) E_k` (thesis 2.3.2: each light is a Dirac
//! delta in direction). Every sampler's light irradiances sum to the probe's integral
//! `sum_texels RGB x solid angle` ([`Probe::total_power`]) to 1e-5 relative; the samplers
//! differ only in where they put the lights and how they split the energy. Everything reads
//! the probe through [`crate::conventions`].
//!
//! This module holds only what every concept shares: the luminance weights.

pub mod cache_entry;
pub mod lightcuts;
pub mod lightset;
pub mod probe;
pub mod reflection;
pub mod schema;
pub mod transfer;

pub use lightset::samplers::{MedianCut, Region, SamplerConfig};
pub use lightset::LightSet;
pub use probe::{LoadOptions, LoadReport, Probe, ProbeError};
pub use schema::{EnvMethod, EnvSpec, SamplerKind};

/// Rec. 709 / sRGB luminance weights `(R, G, B)`.
///
/// We use the values ITU-R BT.709 and IEC 61966-2-1 (sRGB) publish, 0.2126 / 0.7152 /
/// 0.0722, which are the Y row of the RGB-to-XYZ matrix of the 709 primaries with a D65
/// white and sum to exactly 1. The thesis's MATLAB code (3.2.2) uses 0.2125 / 0.7154 /
/// 0.0721, an older rounding (SMPTE 240M-era) that is labelled "BT.709" but is not what
/// the standard gives. Radiance `.hdr` and Poly Haven EXR probes are linear Rec. 709 /
/// sRGB primaries, so the standard weights are the right ones; the difference is below
/// 0.05% of any luminance and only moves sample positions, never total power.
pub const LUMINANCE_WEIGHTS: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Luminance of a linear RGB value with [`LUMINANCE_WEIGHTS`], channels clamped to
/// `>= 0` first (so a dirty texel can never give a negative weight).
#[inline]
pub fn luminance(rgb: [f32; 3]) -> f64 {
    LUMINANCE_WEIGHTS[0] * (rgb[0].max(0.0) as f64)
        + LUMINANCE_WEIGHTS[1] * (rgb[1].max(0.0) as f64)
        + LUMINANCE_WEIGHTS[2] * (rgb[2].max(0.0) as f64)
}
