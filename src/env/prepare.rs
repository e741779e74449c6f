//! Environment light preparation for a scene: probe file + sampler settings in, a light set
//! out, optionally cached on disk so a re-render skips decoding and sampling.
//!
//! Design rule: preprocessing runs only when a scene has an environment light, and its
//! result is keyed by *what determines it*: the probe file's bytes, the rotation, the
//! loader options, the sampler configuration, the crate version and
//! [`LIGHT_SET_ALGORITHM_VERSION`] (FNV-1a, [`super::Fnv1a`]; [`file_cache_key`]). A cache
//! hit reads one JSON file and never decodes the probe. Every entry is validated on read
//! ([`read_cache_entry`]): its format tag, crate version, algorithm version and key must
//! match, its lights must pass [`validate`] and hash to the FNV-1a checksum stored with
//! them. An entry that fails any of this (truncated, edited, from another version) is
//! ignored and rewritten, never trusted ([`Prepared::cache_rejected`] says why).
//!
//! # Which directory
//! Nothing here reads the environment to find a cache: the caller passes a [`CacheDir`].
//! The library's default ([`crate::scene::Scene::resolve`]) is [`CacheDir::None`], so
//! `cargo test`, `brdfkit golden check|bless` and `brdfkit sweep` never read or write a
//! light-set cache. Only `brdfkit render` uses one ([`CacheDir::user`]):
//! `$BRDFKIT_CACHE_DIR`, else `$XDG_CACHE_HOME/brdfkit`, else `$HOME/.cache/brdfkit`
//! (with none of them set, nothing is cached); `render --no-cache` uses none. Entries are
//! `lights-<key>.json`, `<key>` the 16 hex digits of [`file_cache_key`].

use super::lightset_io::{validate, write_atomic, LightSetHeader, MAX_LIGHTSET_BYTES};
use super::{Fnv1a, LightSet, LoadOptions, LoadReport, Probe, SamplerConfig};
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Largest probe file read for hashing (bytes).
pub const MAX_PROBE_FILE_BYTES: u64 = 1 << 30;

/// The sampler names a scene or the command line may use.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, serde::Serialize, clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum SamplerKind {
    /// Uniform random directions, each carrying its Voronoi cell's power.
    Uniform,
    /// Thesis Algorithm 1: importance sampling by luminance x solid angle.
    Importance,
    /// Algorithm 1 fed stratified (Latin hypercube) numbers.
    Stratified,
    /// Thesis Algorithm 2 / Debevec 2005, cuts measured in solid angle; the `lights` command's default.
    MedianCut,
    /// Median cut relaxed by weighted spherical k-means (lower error at equal N); the default for rendering.
    //
    // Why the default (`[env]`, `render --env`): with 128 lights it lies on the
    // run-time-against-error Pareto front of `brdfkit sweep`, where median cut with 128
    // lights is dominated (README, "Run time against error"). Its preparation is slower
    // (hundreds of milliseconds to seconds, once: light sets are cached on disk).
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

/// Largest light count a scene may ask for.
pub const MAX_LIGHTS: usize = 1 << 16;

/// The `[env]` table of a scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvSpec {
    /// Equirectangular probe, `.exr` or `.hdr` (relative to the scene file).
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
        }
    }

    /// Checks the fields; errors name them (`env.count`, ...).
    pub fn check(&self) -> Result<()> {
        if self.count == 0 || self.count > MAX_LIGHTS {
            return Err(Error::field(
                "env.count",
                format!("{} is out of range (1 to {MAX_LIGHTS})", self.count),
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

    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            rotation: self.rotation.to_radians(),
            zero_non_finite: self.zero_non_finite,
            ..LoadOptions::default()
        }
    }
}

/// What [`prepare`] did.
#[derive(Clone, Debug, Default)]
pub struct Prepared {
    pub lights: LightSet,
    /// True when the light set came from the cache (the probe was not decoded).
    pub cache_hit: bool,
    /// Loader report (cleaning counts) when the probe was decoded.
    pub report: Option<LoadReport>,
    /// The cache file used, if any.
    pub cache_file: Option<PathBuf>,
    /// Why an existing cache entry was not used (corrupt, another version, ...); `None`
    /// when there was no entry, no cache, or the entry was used.
    pub cache_rejected: Option<String>,
}

/// Version of the algorithm that turns probe bytes and settings into a light set: probe
/// decoding, cleaning and rotation ([`Probe::load`]), every sampler
/// ([`SamplerConfig::run`], [`super::sampling`]) and the full-probe set. Part of every
/// light-set cache key ([`file_cache_key`]) and stored in each entry.
///
/// Bump when the output of `Probe::load` or of any sampler changes (a different light,
/// power or order for the same inputs), so no cache entry written by older code is read.
pub const LIGHT_SET_ALGORITHM_VERSION: u32 = 1;

/// The crate version, part of every cache key (a cache never outlives a release).
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Format tag of a light-set cache entry.
pub const CACHE_FORMAT: &str = "brdfkit-lightset-cache";

/// Where [`prepare`] (and [`crate::scene::Scene::resolve_with_cache`]) caches light sets.
/// There is no implicit default: the caller says which.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum CacheDir {
    /// No disk cache: every light set is computed. The library's default, used by tests,
    /// `golden check|bless` and `sweep`.
    #[default]
    None,
    /// Read and write entries in this directory (created on first write).
    At(PathBuf),
}

impl CacheDir {
    /// The user's cache directory: `$BRDFKIT_CACHE_DIR`, else `$XDG_CACHE_HOME/brdfkit`,
    /// else `$HOME/.cache/brdfkit` (empty variables count as unset); [`CacheDir::None`]
    /// with none of them set. The only place the crate reads these variables; only the
    /// command line (`brdfkit render`) calls it.
    pub fn user() -> CacheDir {
        let var = |k: &str| {
            std::env::var_os(k)
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
        };
        var("BRDFKIT_CACHE_DIR")
            .or_else(|| var("XDG_CACHE_HOME").map(|p| p.join("brdfkit")))
            .or_else(|| var("HOME").map(|p| p.join(".cache").join("brdfkit")))
            .map_or(CacheDir::None, CacheDir::At)
    }

    /// The directory, if any.
    pub fn path(&self) -> Option<&Path> {
        match self {
            CacheDir::None => None,
            CacheDir::At(p) => Some(p),
        }
    }
}

/// Cache key of a light set: FNV-1a of a format tag, the crate version,
/// [`LIGHT_SET_ALGORITHM_VERSION`], the probe file's bytes, the loader options and the
/// sampler configuration ([`SamplerConfig::hash_into`]). The probe's name is not hashed:
/// two files with the same bytes share entries.
pub fn file_cache_key(bytes: &[u8], opts: &LoadOptions, config: &SamplerConfig) -> u64 {
    versioned_key(
        CRATE_VERSION,
        LIGHT_SET_ALGORITHM_VERSION,
        bytes,
        opts,
        config,
    )
}

/// [`file_cache_key`] with explicit versions (so a test can show that each one changes it).
fn versioned_key(
    crate_version: &str,
    algorithm_version: u32,
    bytes: &[u8],
    opts: &LoadOptions,
    config: &SamplerConfig,
) -> u64 {
    let mut h = Fnv1a::default();
    h.write(b"brdfkit-env-file-v2");
    h.write_u64(crate_version.len() as u64);
    h.write(crate_version.as_bytes());
    h.write_u64(algorithm_version as u64);
    h.write_u64(bytes.len() as u64);
    h.write(bytes);
    h.write_u64(opts.rotation.to_bits());
    h.write_u64(opts.zero_non_finite as u64);
    h.write_u64(opts.max_texels as u64);
    config.hash_into(&mut h);
    h.finish()
}

/// FNV-1a checksum of a light set's contents: its length, then the little-endian bits of
/// `dir_x`, `dir_y`, `dir_z`, `power_r`, `power_g`, `power_b` in that order. Stored in each
/// cache entry and recomputed on read, so an edited number is never trusted.
pub fn lights_checksum(ls: &LightSet) -> u64 {
    let mut h = Fnv1a::default();
    h.write_u64(ls.len() as u64);
    for a in [
        &ls.dir_x,
        &ls.dir_y,
        &ls.dir_z,
        &ls.power_r,
        &ls.power_g,
        &ls.power_b,
    ] {
        for v in a {
            h.write(&v.to_le_bytes());
        }
    }
    h.finish()
}

/// One light-set cache entry on disk (JSON): what produced it and a checksum of its lights.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CacheEntry {
    /// [`CACHE_FORMAT`].
    pub format: String,
    /// [`CRATE_VERSION`] of the writer.
    pub crate_version: String,
    /// [`LIGHT_SET_ALGORITHM_VERSION`] of the writer.
    pub algorithm_version: u32,
    /// The entry's [`file_cache_key`], 16 hex digits (also its file name).
    pub key: String,
    /// [`lights_checksum`] of `lights`, 16 hex digits.
    pub lights_fnv1a: String,
    pub header: LightSetHeader,
    pub lights: LightSet,
}

impl CacheEntry {
    /// The entry for `lights` under `key`, written by this build.
    pub fn new(key: u64, header: LightSetHeader, lights: LightSet) -> CacheEntry {
        CacheEntry {
            format: CACHE_FORMAT.into(),
            crate_version: CRATE_VERSION.into(),
            algorithm_version: LIGHT_SET_ALGORITHM_VERSION,
            key: format!("{key:016x}"),
            lights_fnv1a: format!("{:016x}", lights_checksum(&lights)),
            header,
            lights,
        }
    }
}

/// The cache file of `key` in `dir`.
pub fn cache_file_name(dir: &Path, key: u64) -> PathBuf {
    dir.join(format!("lights-{key:016x}.json"))
}

/// Reads and validates the cache entry `path` for `key`: a regular file of at most
/// [`MAX_LIGHTSET_BYTES`], JSON of a [`CacheEntry`] whose format, crate version, algorithm
/// version and key are this build's and `key`, whose lights pass [`validate`], match the
/// header's count and hash to the stored checksum. `Ok(None)`: no entry; `Err`: an entry
/// that is not used, and why.
pub fn read_cache_entry(path: &Path, key: u64) -> std::result::Result<Option<LightSet>, String> {
    if !path.exists() {
        return Ok(None);
    }
    let bytes = crate::image_io::read_regular_file(path, MAX_LIGHTSET_BYTES, "light-set cache")
        .map_err(|e| e.to_string())?;
    let e: CacheEntry =
        serde_json::from_slice(&bytes).map_err(|e| format!("not a cache entry: {e}"))?;
    let expect = |what: &str, found: &dyn std::fmt::Display, wanted: &dyn std::fmt::Display| {
        format!("{what} {found}, this build writes {wanted}")
    };
    if e.format != CACHE_FORMAT {
        return Err(expect("format", &e.format, &CACHE_FORMAT));
    }
    if e.crate_version != CRATE_VERSION {
        return Err(expect("crate version", &e.crate_version, &CRATE_VERSION));
    }
    if e.algorithm_version != LIGHT_SET_ALGORITHM_VERSION {
        return Err(expect(
            "light-set algorithm version",
            &e.algorithm_version,
            &LIGHT_SET_ALGORITHM_VERSION,
        ));
    }
    let key = format!("{key:016x}");
    if e.key != key {
        return Err(expect("key", &e.key, &key));
    }
    validate(path, &e.lights).map_err(|e| e.to_string())?;
    if e.header.n != e.lights.len() {
        return Err(format!(
            "header says {} lights, the entry holds {}",
            e.header.n,
            e.lights.len()
        ));
    }
    let sum = format!("{:016x}", lights_checksum(&e.lights));
    if e.lights_fnv1a != sum {
        return Err(format!(
            "checksum {} does not match its lights ({sum}): edited or damaged",
            e.lights_fnv1a
        ));
    }
    Ok(Some(e.lights))
}

/// Loads (or fetches from `cache_dir`, none with `None`) the light set of an environment
/// spec ([`CacheDir::path`] gives the directory of a [`CacheDir`]); `base` is
/// the directory relative probe paths resolve against. Errors name the probe file: missing
/// or unreadable, not a regular file (a device such as `/dev/zero` never ends), over
/// [`MAX_PROBE_FILE_BYTES`],
/// undecodable (see [`Probe::load`]), or fields out of range ([`EnvSpec::check`]).
/// The light powers are scaled by `spec.intensity` (after the cache: entries hold the
/// unscaled set).
pub fn prepare(spec: &EnvSpec, base: &Path, cache_dir: Option<&Path>) -> Result<Prepared> {
    spec.check()?;
    let path = base.join(&spec.file);
    // Not a regular file (a device such as /dev/zero, a FIFO) or over the limit: refused
    // before it is read.
    let bytes = crate::image_io::read_regular_file(&path, MAX_PROBE_FILE_BYTES, "light probe")?;
    let opts = spec.load_options();
    let config = spec.sampler_config();
    let key = file_cache_key(&bytes, &opts, &config);
    let cache_file = cache_dir.map(|d| cache_file_name(d, key));
    let mut lights = None;
    let mut cache_rejected = None;
    if let Some(cf) = &cache_file {
        match read_cache_entry(cf, key) {
            Ok(ls) => lights = ls,
            Err(why) => cache_rejected = Some(why),
        }
    }
    let cache_hit = lights.is_some();
    let mut report = None;
    let mut lights = match lights {
        Some(ls) => ls,
        None => {
            drop(bytes);
            let (probe, rep) =
                Probe::load(&path, &opts).map_err(|e| Error::Message(e.to_string()))?;
            report = Some(rep);
            let ls = config.run(&probe);
            if let Some(cf) = &cache_file {
                // A cache that cannot be written only costs time: ignore the error.
                if std::fs::create_dir_all(cf.parent().unwrap_or(Path::new("."))).is_ok() {
                    let header = LightSetHeader::new(&config, path.to_str(), &ls);
                    let entry = CacheEntry::new(key, header, ls.clone());
                    if let Ok(json) = serde_json::to_vec(&entry) {
                        let _ = write_atomic(cf, &json);
                    }
                }
            }
            ls
        }
    };
    if spec.intensity != 1.0 {
        for p in lights
            .power_r
            .iter_mut()
            .chain(lights.power_g.iter_mut())
            .chain(lights.power_b.iter_mut())
        {
            *p *= spec.intensity;
        }
    }
    Ok(Prepared {
        lights,
        cache_hit,
        report,
        cache_file,
        cache_rejected,
    })
}

/// The light set as scene lights (directional, irradiance = power).
pub fn to_scene_lights(ls: &LightSet) -> Vec<crate::light::Light> {
    (0..ls.len())
        .map(|i| crate::light::Light::Directional {
            to_light: glam::Vec3::new(ls.dir_x[i], ls.dir_y[i], ls.dir_z[i]),
            irradiance: glam::Vec3::new(ls.power_r[i], ls.power_g[i], ls.power_b[i]),
        })
        .collect()
}

/// Loads a probe for tools (the `lights` command), mapping its errors.
pub fn load_probe(path: &Path, opts: &LoadOptions) -> Result<(Probe, LoadReport)> {
    Probe::load(path, opts).map_err(|e| Error::Message(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cache_key_includes_both_versions() {
        let opts = LoadOptions::default();
        let cfg = SamplerConfig::MedianCut { n: 8 };
        let k = |v: &str, a: u32| versioned_key(v, a, b"probe bytes", &opts, &cfg);
        let now = k(CRATE_VERSION, LIGHT_SET_ALGORITHM_VERSION);
        assert_eq!(now, file_cache_key(b"probe bytes", &opts, &cfg));
        assert_ne!(now, k("0.0.0-other", LIGHT_SET_ALGORITHM_VERSION));
        assert_ne!(now, k(CRATE_VERSION, LIGHT_SET_ALGORITHM_VERSION + 1));
        // The version string is length-prefixed: moving bytes between it and the
        // algorithm version cannot collide.
        assert_ne!(k("0.1", 1), k("0.10", 1));
    }

    #[test]
    fn checksum_sees_every_number() {
        let mut ls = LightSet::default();
        ls.push(glam::DVec3::Y, glam::DVec3::new(1.0, 2.0, 3.0));
        ls.push(glam::DVec3::X, glam::DVec3::new(0.5, 0.25, 0.125));
        let base = lights_checksum(&ls);
        for field in 0..6 {
            let mut e = ls.clone();
            let a = [
                &mut e.dir_x,
                &mut e.dir_y,
                &mut e.dir_z,
                &mut e.power_r,
                &mut e.power_g,
                &mut e.power_b,
            ]
            .into_iter()
            .nth(field)
            .unwrap();
            a[1] = f32::from_bits(a[1].to_bits() ^ 1);
            assert_ne!(lights_checksum(&e), base, "field {field}");
        }
    }
}
