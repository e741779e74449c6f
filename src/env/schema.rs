//! The `[env]` table of a scene file, for every environment method: [`EnvSpec`] (its
//! fields, defaults and checks), [`EnvMethod`] (how the environment is shaded) and
//! [`SamplerKind`] (how `method = "lights"` collapses the probe). What each method prepares
//! from it lives beside the method: light sets [`super::lightset::prepare`], transfer
//! tables [`super::transfer::prepare_transfer`], light trees
//! [`super::lightcuts::prepare_lightcuts`].
//!
//! Why the file stays whole past 400 lines: it is one table of the scene format, and every
//! field's default, range check and error message sits beside the field it guards; split,
//! a new field's check would live in a different file from its declaration.

use super::{LightSet, LoadOptions, SamplerConfig};
use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::PathBuf;

/// The sampler names a scene or the command line may use.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, serde::Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum SamplerKind {
    /// Uniform random directions, each carrying its Voronoi cell's irradiance.
    Uniform,
    /// Thesis Algorithm 1: importance sampling by luminance x solid angle.
    Importance,
    /// Algorithm 1 fed stratified (Latin hypercube) numbers.
    Stratified,
    /// Thesis Algorithm 2 / Debevec 2005, cuts measured in solid angle; the `lights` command's default.
    MedianCut,
    /// Median cut relaxed by weighted spherical k-means (lower error at equal N); the default for rendering.
    //
    // Why the default (of `[env] method = "lights"`, as `render --lights` or `--sampler`
    // give): among light sets it is the cheapest way to about 1% relative RMSE in
    // `brdfkit sweep`; at 128 lights median cut is about as fast with four times the error
    // (docs/sweeps.md, "The default scene"; both are dominated by transfer tables there).
    // Its preparation is slower (hundreds of milliseconds to seconds, once: light sets are
    // cached on disk).
    #[default]
    Lloyd,
    /// Every texel a light: the converged reference.
    Full,
}

/// Default number of Lloyd iterations.
pub const LLOYD_ITERATIONS: usize = 16;

impl SamplerKind {
    /// The sampler configuration for `n` lights and `seed`.
    pub fn config(self, n: usize, seed: u64) -> SamplerConfig {
        match self {
            SamplerKind::Uniform => SamplerConfig::Uniform { n, seed },
            SamplerKind::Importance => SamplerConfig::Importance { n, seed },
            SamplerKind::Stratified => SamplerConfig::Stratified { n, seed },
            SamplerKind::MedianCut => SamplerConfig::MedianCut { n },
            SamplerKind::Lloyd => SamplerConfig::Lloyd {
                n,
                iterations: LLOYD_ITERATIONS,
            },
            SamplerKind::Full => SamplerConfig::Full,
        }
    }
}

/// How an environment is shaded (`[env] method`): the choice of `auto` is
/// [`crate::scene::env_method`]'s (from the sweep), the transfer table
/// [`crate::env::transfer`], the light cuts [`crate::env::lightcuts`]. The variants' docs
/// are the `--env-method` help text (plain text: clap prints them).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, serde::Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum EnvMethod {
    /// Chosen per material (the default): `transfer` for Lambert and SH data sets,
    /// `lightcuts` for analytic lobes and D-BRDFs, `lights` for MERL and RGL tables; `lights` when
    /// the `[env]` table states `sampler` or `count` or names a light set file (`lights`).
    #[default]
    Auto,
    /// The probe collapsed into delta lights by `sampler`.
    Lights,
    /// A transfer table over normals from the full probe plus the `exact_lights`
    /// brightest texels as delta lights; SH data sets and Lambert only.
    Transfer,
    /// Every texel a light in a light tree, a cut refined per pixel to `cut_error`;
    /// analytic models and D-BRDFs (not SH data sets, MERL or RGL tables).
    Lightcuts,
    /// A reflection-space radiance table (over reflected direction, view angle and a
    /// Fourier series about it) baked from the material's own BRDF under the probe, plus
    /// the `exact_lights` brightest texels as delta lights; isotropic materials.
    Reflection,
}

impl EnvMethod {
    /// The name, as `[env] method` and `--env-method` spell it (`auto`, `lights`, ...).
    pub fn name(self) -> &'static str {
        match self {
            EnvMethod::Auto => "auto",
            EnvMethod::Lights => "lights",
            EnvMethod::Transfer => "transfer",
            EnvMethod::Lightcuts => "lightcuts",
            EnvMethod::Reflection => "reflection",
        }
    }
}

/// Default azimuth nodes of a transfer table.
pub const DEFAULT_TRANSFER_AZIMUTH: usize = 128;
/// Default polar nodes of a transfer table (both poles included).
pub const DEFAULT_TRANSFER_POLAR: usize = 65;
/// Default number of brightest texels summed exactly beside a transfer table. Why 64, not
/// 16: under the studio probe (a few bright lamps) the table alone misses every horizon
/// crossing of a lamp between its nodes; with 16 exact lights the 128 x 65 table gives
/// teal-paint (SH, 8 bands) 0.62% relative RMSE but a 99th percentile of 27% (Lambert:
/// 0.11%, 8.8%), with 64 it gives 0.13% and 6.2% (Lambert 0.03%, 2.0%); city and sky are
/// within 0.05% and 0.4% either way (`brdfkit sweep --class sh-glossy --probe studio`).
pub const DEFAULT_EXACT_LIGHTS: usize = 64;

/// Default `cut_error` of light cuts: a cluster's error bound at most 1% of the pixel's
/// estimate (the environment methods' accuracy target is 1% relative RMSE,
/// [`crate::sweep::ERROR_BOUND`]).
pub const DEFAULT_CUT_ERROR: f32 = 0.01;
/// Default `cut_max` of light cuts. Why 1000: at the default `cut_error` (1%), Blinn-Phong
/// exponent 200 and the library D-BRDF under the shipped probes need mean cuts of 230-380
/// clusters and at most ~550 (`examples/lightcuts_error.rs`, 48 x 48), so the cap stops no
/// pixel there; it bounds the cost of a pixel whose bound stays loose (about 4x the mean),
/// and at `cut_error = 0.003` it starts to stop a few pixels (studio: 20 of ~1,400).
pub const DEFAULT_CUT_MAX: usize = 1000;

/// Default cells per side of a reflection table's octahedral grid of reflected directions
/// (65 x 65 nodes). Why 64: in the accuracy study of the parameterisation
/// ([`crate::env::reflection`]) it was the smallest grid that met 1% relative RMSE and 10% at
/// the 99th percentile for Blinn-Phong 200 and 500 under city and sky (RMSE falls about 3x
/// per halving of the spacing).
pub const DEFAULT_REFLECTION_GRID: usize = 64;
/// Default uniform view slices of a reflection table over 0-85 degrees (the horizon slice
/// is one more). Why 13: 7 left about 20% at the 99th percentile in the accuracy study, 13
/// met the bound below 70 degrees, 25 changed little.
pub const DEFAULT_REFLECTION_SLICES: usize = 13;
/// Default largest width of the residual probe a reflection table is baked from. Why 256:
/// its own error floor (against the full-resolution residual) was at most 1.1% at the 99th
/// percentile with 64 exact texels; 128 cost up to 7%.
pub const DEFAULT_REFLECTION_RESIDUAL: usize = 256;
/// Default order of a reflection table's Fourier series in psi, the normal's angle about the
/// reflected direction (`2 order + 1` coefficients per node, slice and colour, from
/// [`crate::env::reflection::table::psi_samples`] samples; [`crate::env::reflection`], "Order of the series in psi"). Why 2: in
/// the accuracy study it was the knee under city and sky (order 1 left 33% at the 99th
/// percentile, order 2 4.5%, order 3 4.0%), and every table, cache entry and golden image
/// made before the order was a parameter is of order 2. Under studio's bright lamps the
/// glossy class needs more: order 6 with `reflection_grid = 128` (2.6 times the default
/// table's bytes per grid node) is what meets 10% at the 99th percentile for Blinn-Phong
/// 50, 200 and 500 and gold-dust-paint. Memory grows as `2 order + 1`: at the default grid
/// and slices 2.2 MB at order 1, 3.6 at 2, 6.4 at 4, 9.3 at 6, 12.1 at 8.
pub const DEFAULT_REFLECTION_ORDER: usize = 2;
/// Default half vectors per pixel of filtered importance sampling, the reflection method's
/// path for anisotropic D-BRDFs ([`crate::env::reflection::filtered`]). Why 128: for
/// lindt-paper against the converged reference (`examples/reflection_error.rs`, 96 x 96)
/// it is the smallest power of two with relative RMSE below 1% under city, studio and sky
/// (0.52%, 0.77%, 0.23%; 64 gave 1.40%, 1.21%, 0.41%); p99 2.6%, 14.9%, 2.3%.
pub const DEFAULT_REFLECTION_SAMPLES: usize = 128;
/// Largest `reflection_samples`.
pub const MAX_REFLECTION_SAMPLES: usize = 4096;

/// Largest light count a scene may ask for.
pub const MAX_LIGHTS: usize = 1 << 16;

/// The `[env]` table of a scene file.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct EnvSpec {
    /// Equirectangular probe, `.exr` or `.hdr` (relative to the scene file). May be left
    /// out when `lights` is given (then it is only named, never read).
    #[serde(default)]
    pub file: PathBuf,
    #[serde(default)]
    pub sampler: SamplerKind,
    /// Number of lights (ignored by `full`).
    #[serde(default = "default_count")]
    pub count: usize,
    /// Seed of the random samplers.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Rotation of the environment about +y, degrees (right-handed).
    #[serde(default)]
    pub rotation: f64,
    /// Scale applied to the probe's radiance.
    #[serde(default = "default_intensity")]
    pub intensity: f32,
    /// Load probes with NaN/Inf texels by setting those texels to black.
    #[serde(default)]
    pub zero_non_finite: bool,
    /// How the environment is shaded: `auto` (the default: chosen per material,
    /// [`crate::scene::env_method`]), `lights` (the sampler's delta lights), `transfer` ([`crate::env::transfer`]; `sampler`, `count` and `seed` unused), or
    /// `lightcuts` ([`crate::env::lightcuts`]; the same three unused) or `reflection`
    /// ([`crate::env::reflection`]; the same three unused).
    #[serde(default)]
    pub method: EnvMethod,
    /// Transfer table: azimuth nodes (must divide the probe's width).
    #[serde(default = "default_transfer_azimuth")]
    pub transfer_azimuth: usize,
    /// Transfer table: polar nodes, both poles included.
    #[serde(default = "default_transfer_polar")]
    pub transfer_polar: usize,
    /// Transfer and reflection: the brightest texels (luminance x solid angle) summed exactly as
    /// directional lights instead of through the table (0 to [`MAX_LIGHTS`]).
    #[serde(default = "default_exact_lights")]
    pub exact_lights: usize,
    /// Reflection table: cells per side of the octahedral grid of reflected directions.
    #[serde(default = "default_reflection_grid")]
    pub reflection_grid: usize,
    /// Reflection table: uniform view slices over 0-85 degrees (plus a horizon slice).
    #[serde(default = "default_reflection_slices")]
    pub reflection_slices: usize,
    /// Reflection table: largest width of the residual probe baked (must divide the
    /// probe's width when smaller).
    #[serde(default = "default_reflection_residual")]
    pub reflection_residual: usize,
    /// Reflection table: order of the Fourier series in psi (1 to 8;
    /// [`DEFAULT_REFLECTION_ORDER`]).
    #[serde(default = "default_reflection_order")]
    pub reflection_order: usize,
    /// Reflection, anisotropic D-BRDFs: half vectors per pixel of filtered importance
    /// sampling (1 to [`MAX_REFLECTION_SAMPLES`]; [`crate::env::reflection::filtered`]).
    #[serde(default = "default_reflection_samples")]
    pub reflection_samples: usize,
    /// Light cuts: largest error bound of a cluster relative to the pixel's estimate
    /// (luminance), in (0, 1].
    #[serde(default = "default_cut_error")]
    pub cut_error: f32,
    /// Light cuts: largest cut per pixel (clusters), 1 to [`MAX_LIGHTS`].
    #[serde(default = "default_cut_max")]
    pub cut_max: usize,
    /// A light set file (`.json` or `.csv`, as `brdfkit lights -o` writes it; relative to
    /// the scene file) used instead of sampling the probe: its directions are world
    /// directions as written (`rotation` must be 0; rotate with `lights --rotation`),
    /// its irradiances are scaled by `intensity`; `sampler`, `count` and `seed` are unused.
    /// `method = "lights"` only ([`super::lightset::file::read_by_extension`]).
    #[serde(default)]
    pub lights: Option<PathBuf>,
}

fn default_reflection_grid() -> usize {
    DEFAULT_REFLECTION_GRID
}
fn default_reflection_slices() -> usize {
    DEFAULT_REFLECTION_SLICES
}
fn default_reflection_residual() -> usize {
    DEFAULT_REFLECTION_RESIDUAL
}
fn default_reflection_order() -> usize {
    DEFAULT_REFLECTION_ORDER
}
fn default_reflection_samples() -> usize {
    DEFAULT_REFLECTION_SAMPLES
}
fn default_cut_error() -> f32 {
    DEFAULT_CUT_ERROR
}
fn default_cut_max() -> usize {
    DEFAULT_CUT_MAX
}

fn default_transfer_azimuth() -> usize {
    DEFAULT_TRANSFER_AZIMUTH
}
fn default_transfer_polar() -> usize {
    DEFAULT_TRANSFER_POLAR
}
fn default_exact_lights() -> usize {
    DEFAULT_EXACT_LIGHTS
}

fn default_count() -> usize {
    128
}
fn default_seed() -> u64 {
    1
}
fn default_intensity() -> f32 {
    1.0
}

impl EnvSpec {
    /// Makes this environment the converged reference's: every probe texel a light
    /// (`sampler = "full"`) and no transfer table (`method = "lights"`), whatever the scene
    /// chose. Used by `render --reference` and the sweep's reference.
    pub fn use_full_probe(&mut self) {
        self.sampler = SamplerKind::Full;
        self.method = EnvMethod::Lights;
        self.lights = None;
    }

    /// An environment light from a probe file with default settings.
    pub fn new(file: PathBuf) -> EnvSpec {
        EnvSpec {
            file,
            sampler: SamplerKind::default(),
            count: default_count(),
            seed: default_seed(),
            rotation: 0.0,
            intensity: 1.0,
            zero_non_finite: false,
            method: EnvMethod::default(),
            transfer_azimuth: DEFAULT_TRANSFER_AZIMUTH,
            transfer_polar: DEFAULT_TRANSFER_POLAR,
            exact_lights: DEFAULT_EXACT_LIGHTS,
            reflection_grid: DEFAULT_REFLECTION_GRID,
            reflection_slices: DEFAULT_REFLECTION_SLICES,
            reflection_residual: DEFAULT_REFLECTION_RESIDUAL,
            reflection_order: DEFAULT_REFLECTION_ORDER,
            reflection_samples: DEFAULT_REFLECTION_SAMPLES,
            cut_error: DEFAULT_CUT_ERROR,
            cut_max: DEFAULT_CUT_MAX,
            lights: None,
        }
    }

    /// Checks the fields; errors name them (`env.count`, ...).
    pub fn check(&self) -> Result<()> {
        if self.lights.is_none() && self.file.as_os_str().is_empty() {
            return Err(Error::field(
                "env.file",
                "missing: an [env] names a probe file (or a light set file in env.lights)",
            ));
        }
        if self.lights.is_some() {
            if matches!(
                self.method,
                EnvMethod::Transfer | EnvMethod::Lightcuts | EnvMethod::Reflection
            ) {
                return Err(Error::field(
                    "env.lights",
                    "a light set file is shaded with method = \"lights\" only",
                ));
            }
            if self.rotation != 0.0 {
                return Err(Error::field(
                    "env.rotation",
                    "must be 0 with env.lights: the file's directions are world directions \
                     (rotate them with `brdfkit lights --rotation`)",
                ));
            }
        }
        if self.count == 0 || self.count > MAX_LIGHTS {
            return Err(Error::field(
                "env.count",
                format!("{} is out of range (1 to {MAX_LIGHTS})", self.count),
            ));
        }
        if self.exact_lights > MAX_LIGHTS {
            return Err(Error::field(
                "env.exact_lights",
                format!("{} is out of range (0 to {MAX_LIGHTS})", self.exact_lights),
            ));
        }
        if self.reflection_samples == 0 || self.reflection_samples > MAX_REFLECTION_SAMPLES {
            return Err(Error::field(
                "env.reflection_samples",
                format!(
                    "{} is out of range (1 to {MAX_REFLECTION_SAMPLES})",
                    self.reflection_samples
                ),
            ));
        }
        if !(self.cut_error > 0.0 && self.cut_error <= 1.0) {
            return Err(Error::field(
                "env.cut_error",
                format!("{} is out of range (0 < fraction <= 1)", self.cut_error),
            ));
        }
        if self.cut_max == 0 || self.cut_max > MAX_LIGHTS {
            return Err(Error::field(
                "env.cut_max",
                format!("{} is out of range (1 to {MAX_LIGHTS})", self.cut_max),
            ));
        }
        if !self.rotation.is_finite() {
            return Err(Error::field(
                "env.rotation",
                "must be a finite number of degrees",
            ));
        }
        if !(self.intensity.is_finite() && self.intensity >= 0.0) {
            return Err(Error::field(
                "env.intensity",
                format!("{} must be a finite number >= 0", self.intensity),
            ));
        }
        Ok(())
    }

    pub fn sampler_config(&self) -> SamplerConfig {
        self.sampler.config(self.count, self.seed)
    }

    /// Applies `intensity` (the scale of the probe's radiance) to a light set made from
    /// the unscaled probe: every light's irradiance times `intensity`, one f32 product per
    /// channel value ([`LightSet::scale_irradiance`]). The one place the scene's `[env] intensity`
    /// reaches a light set: [`super::lightset::prepare`] (after its cache, whose entries hold the unscaled
    /// set) and the sweep's light sets both call it.
    pub fn scale_intensity(&self, lights: &mut LightSet) {
        if self.intensity != 1.0 {
            lights.scale_irradiance(self.intensity);
        }
    }

    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            rotation: self.rotation.to_radians(),
            zero_non_finite: self.zero_non_finite,
            ..LoadOptions::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn two_lights() -> LightSet {
        let mut ls = LightSet::default();
        ls.push(DVec3::Y, DVec3::new(1.0, 0.5, 0.25));
        ls.push(DVec3::Z, DVec3::new(3.0, 0.0, 0.75));
        ls
    }

    #[test]
    fn intensity_scales_every_irradiance_and_no_direction() {
        let mut spec = EnvSpec::new("probe.exr".into());
        let mut ls = two_lights();
        spec.scale_intensity(&mut ls);
        assert_eq!(ls, two_lights(), "intensity 1 changes nothing");
        spec.intensity = 2.5;
        spec.scale_intensity(&mut ls);
        let mut want = LightSet::default();
        want.push(DVec3::Y, DVec3::new(2.5, 1.25, 0.625));
        want.push(DVec3::Z, DVec3::new(7.5, 0.0, 1.875));
        assert_eq!(ls, want);
        spec.intensity = 0.0;
        spec.scale_intensity(&mut ls);
        assert_eq!(ls.total_irradiance(), DVec3::ZERO);
        assert_eq!(ls.direction(1), DVec3::Z);
    }
}
