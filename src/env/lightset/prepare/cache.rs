//! The light-set cache of [`super::prepare`]: keys, entries, validation, and the choice of
//! directory.
//!
//! # Key
//! The crate's stable hash ([`crate::hash`], XXH3-64) of the probe file's bytes, the
//! rotation and loader options, the sampler configuration, the crate version and
//! [`LIGHT_SET_ALGORITHM_VERSION`] ([`file_cache_key`]). Entries are
//! `<dir>/lights-<key>.json`, `<key>` 16 hex digits ([`cache_file_name`]).
//!
//! # Validation
//! A hit reads one JSON file ([`CacheEntry`]) and never decodes the probe. Every read is
//! checked ([`read_cache_entry`]): format tag, crate version, algorithm version and key must
//! be this build's (the check every environment cache shares, [`crate::env::cache_entry`]), the lights must pass [`validate`], match the header's count and hash to
//! the stored checksum ([`lights_checksum`]). An entry that fails any of this (truncated,
//! edited, from another version) is ignored and rewritten, never trusted
//! ([`super::Prepared::cache_rejected`] says why).
//!
//! # Which directory
//! Nothing reads the environment to find a cache except [`CacheDir::user`], which only the
//! command line calls. The library's default ([`crate::scene::Scene::resolve`]) is
//! [`CacheDir::None`], so `cargo test`, `brdfkit golden check|bless` and `brdfkit sweep`
//! never read or write a light-set cache. `brdfkit render` and `brdfkit view` use
//! [`CacheDir::user`]: `$BRDFKIT_CACHE_DIR`, else `$XDG_CACHE_HOME/brdfkit`, else
//! `$HOME/.cache/brdfkit` (with none of them set, nothing is cached); `--no-cache` uses none.

use crate::env::cache_entry::{check_checksum, key_hasher, read_entry_bytes, EntryKind, Stamp};
use crate::env::lightset::file::{validate, LightSetHeader, MAX_LIGHTSET_BYTES};
use crate::env::{LightSet, LoadOptions, LoadReport, SamplerConfig};
use crate::hash::{self, StableHasher};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Version of the algorithm that turns probe bytes and settings into a light set: probe
/// decoding, cleaning and rotation ([`crate::env::Probe::load`]), every sampler
/// ([`SamplerConfig::run`], [`crate::env::lightset::samplers`]) and the full-probe set. Part of every
/// light-set cache key ([`file_cache_key`]) and stored in each entry.
///
/// Bump when the output of `Probe::load` or of any sampler changes (a different light,
/// irradiance or order for the same inputs), so no cache entry written by older code is read.
/// 2: negative texels keep the signed integral (their mass moved into nearby positive
/// texels) instead of being clamped to 0. 3: Lloyd relaxes a probe wider than
/// [`crate::env::lightset::samplers::RELAXATION_WIDTH`] on a downsampled copy.
pub const LIGHT_SET_ALGORITHM_VERSION: u32 = 3;

pub use crate::env::cache_entry::CRATE_VERSION;

/// Format tag of a light-set cache entry (`-v2`: the checksum is XXH3-64 in
/// [`hash::tagged`] form and the lights' fields are `irradiance_*`).
pub const CACHE_FORMAT: &str = "brdfkit-lightset-cache-v3";

/// A light-set cache entry as this build writes it ([`crate::env::cache_entry`]).
const ENTRY: EntryKind = EntryKind {
    format: CACHE_FORMAT,
    algorithm: "light-set algorithm version",
    algorithm_version: LIGHT_SET_ALGORITHM_VERSION,
    file: ("lights", "json"),
};

/// Where [`super::prepare`] (and [`crate::scene::Scene::resolve_with_cache`]) caches light
/// sets. No code path picks the user's directory by itself: the caller passes one
/// ([`CacheDir::user`]) or gets none (`Default`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum CacheDir {
    /// No disk cache: every light set is computed. The library's default, used by tests,
    /// `golden check|bless` and `sweep`.
    #[default]
    None,
    /// Read and write entries in `dir` (created on first write), its cache files kept to at
    /// most `max_bytes` in all by evicting the least recently used ([`super::cap`],
    /// [`CacheDir::record_use`]).
    At { dir: PathBuf, max_bytes: u64 },
}

impl CacheDir {
    /// The user's cache directory: `$BRDFKIT_CACHE_DIR`, else `$XDG_CACHE_HOME/brdfkit`,
    /// else `$HOME/.cache/brdfkit` (empty variables count as unset); [`CacheDir::None`]
    /// with none of them set. Its cap is `$BRDFKIT_CACHE_MAX_MB` megabytes (10^6 bytes),
    /// else [`super::cap::DEFAULT_CACHE_MAX_BYTES`]. The only place the crate reads these
    /// variables; only the command line (`brdfkit render`, `view`, `cache`) calls it.
    ///
    /// Fails when `$BRDFKIT_CACHE_MAX_MB` is set and is not a number of megabytes > 0.
    pub fn user() -> crate::error::Result<CacheDir> {
        let var = |k: &str| {
            std::env::var_os(k)
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
        };
        let max_bytes = match std::env::var_os("BRDFKIT_CACHE_MAX_MB").filter(|v| !v.is_empty()) {
            None => super::cap::DEFAULT_CACHE_MAX_BYTES,
            Some(v) => {
                let text = v.to_string_lossy();
                match text.trim().parse::<f64>() {
                    Ok(mb) if mb.is_finite() && mb > 0.0 => (mb * 1e6) as u64,
                    _ => {
                        return Err(crate::error::Error::field(
                            "BRDFKIT_CACHE_MAX_MB",
                            format!("\"{text}\" is not a number of megabytes > 0"),
                        ))
                    }
                }
            }
        };
        Ok(var("BRDFKIT_CACHE_DIR")
            .or_else(|| var("XDG_CACHE_HOME").map(|p| p.join("brdfkit")))
            .or_else(|| var("HOME").map(|p| p.join(".cache").join("brdfkit")))
            .map_or(CacheDir::None, |dir| CacheDir::At { dir, max_bytes }))
    }

    /// The directory, if any.
    pub fn path(&self) -> Option<&Path> {
        match self {
            CacheDir::None => None,
            CacheDir::At { dir, .. } => Some(dir),
        }
    }

    /// The size cap in bytes, if there is a directory.
    pub fn max_bytes(&self) -> Option<u64> {
        match self {
            CacheDir::None => None,
            CacheDir::At { max_bytes, .. } => Some(*max_bytes),
        }
    }

    /// Bookkeeping after an entry `file` of this directory was read (`hit`) or written:
    /// a hit marks it used ([`super::cap::touch`]); a write evicts the least recently used
    /// entries past the cap ([`super::cap::enforce_cap`]), never `file` itself. Nothing
    /// for [`CacheDir::None`] or without a file; never fails.
    pub fn record_use(&self, file: Option<&Path>, hit: bool) {
        let (CacheDir::At { dir, max_bytes }, Some(file)) = (self, file) else {
            return;
        };
        if hit {
            super::cap::touch(file);
        } else if file.exists() {
            super::cap::enforce_cap(dir, *max_bytes, file);
        }
    }
}

/// Cache key of a light set: [`StableHasher`] (XXH3-64) of a key tag, the crate version,
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
    // v3: XXH3-64 instead of FNV-1a (a v2 key names an FNV-1a hash).
    let mut h = key_hasher(
        b"brdfkit-env-file-v3",
        crate_version,
        algorithm_version,
        bytes,
    );
    h.write_u64(opts.rotation.to_bits());
    h.write_u64(opts.zero_non_finite as u64);
    h.write_u64(opts.max_texels as u64);
    config.hash_into(&mut h);
    h.finish()
}

/// Checksum ([`StableHasher`]) of a light set's contents: its length, then the
/// little-endian bits of `dir_x`, `dir_y`, `dir_z`, `irradiance_r`, `irradiance_g`,
/// `irradiance_b` in that order. Stored in each cache entry and recomputed on read, so an
/// edited number is never trusted.
pub fn lights_checksum(ls: &LightSet) -> u64 {
    let mut h = StableHasher::new();
    h.write_u64(ls.len() as u64);
    for a in [
        &ls.dir_x,
        &ls.dir_y,
        &ls.dir_z,
        &ls.irradiance_r,
        &ls.irradiance_g,
        &ls.irradiance_b,
    ] {
        h.write_f32s(a.iter().copied());
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
    /// [`lights_checksum`] of `lights` in [`hash::tagged`] form (`xxh3-64:<16 hex>`).
    pub lights_checksum: String,
    pub header: LightSetHeader,
    /// What loading the probe found (size, cleaned texels), so a cache hit warns about
    /// the probe as a decode would (a probe that is not 2:1, negative texels).
    pub load_report: LoadReport,
    pub lights: LightSet,
}

impl CacheEntry {
    /// The entry for `lights` under `key`, written by this build.
    pub fn new(
        key: u64,
        header: LightSetHeader,
        load_report: LoadReport,
        lights: LightSet,
    ) -> CacheEntry {
        CacheEntry {
            format: CACHE_FORMAT.into(),
            crate_version: CRATE_VERSION.into(),
            algorithm_version: LIGHT_SET_ALGORITHM_VERSION,
            key: EntryKind::key_text(key),
            lights_checksum: hash::tagged(lights_checksum(&lights)),
            header,
            load_report,
            lights,
        }
    }
}

/// The cache file of `key` in `dir`.
pub fn cache_file_name(dir: &Path, key: u64) -> PathBuf {
    ENTRY.file_name(dir, key)
}

/// Reads and validates the cache entry `path` for `key`: a regular file of at most
/// [`MAX_LIGHTSET_BYTES`], JSON of a [`CacheEntry`] whose format, crate version, algorithm
/// version and key are this build's and `key`, whose lights pass [`validate`], match the
/// header's count and hash to the stored checksum. `Ok(None)`: no entry; `Err`: an entry
/// that is not used, and why.
pub fn read_cache_entry(
    path: &Path,
    key: u64,
) -> std::result::Result<Option<(LightSet, LoadReport)>, String> {
    let Some(bytes) = read_entry_bytes(path, MAX_LIGHTSET_BYTES, "light-set cache")? else {
        return Ok(None);
    };
    let e: CacheEntry =
        serde_json::from_slice(&bytes).map_err(|e| format!("not a cache entry: {e}"))?;
    let stamp = Stamp {
        format: &e.format,
        crate_version: &e.crate_version,
        algorithm_version: e.algorithm_version,
        key: &e.key,
    };
    ENTRY.check_stamp(stamp, key)?;
    validate(path, &e.lights).map_err(|e| e.to_string())?;
    if e.header.n != e.lights.len() {
        return Err(format!(
            "header says {} lights, the entry holds {}",
            e.header.n,
            e.lights.len()
        ));
    }
    check_checksum(&e.lights_checksum, lights_checksum(&e.lights), "lights")?;
    Ok(Some((e.lights, e.load_report)))
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
                &mut e.irradiance_r,
                &mut e.irradiance_g,
                &mut e.irradiance_b,
            ]
            .into_iter()
            .nth(field)
            .unwrap();
            a[1] = f32::from_bits(a[1].to_bits() ^ 1);
            assert_ne!(lights_checksum(&e), base, "field {field}");
        }
    }

    /// An entry written before the XXH3 hash (format tag without `-v2`, `lights_fnv1a`,
    /// `power_*`) under this build's key is refused, not read.
    #[test]
    fn an_fnv1a_era_entry_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let opts = LoadOptions::default();
        let cfg = SamplerConfig::MedianCut { n: 1 };
        let key = file_cache_key(b"probe bytes", &opts, &cfg);
        let path = cache_file_name(tmp.path(), key);
        let mut ls = LightSet::default();
        ls.push(glam::DVec3::Y, glam::DVec3::ONE);
        let header = crate::env::lightset::file::LightSetHeader::new(&cfg, None, &ls);
        let report = LoadReport {
            negative_texels: 3,
            non_finite_zeroed: 0,
            size: (16, 8),
            ..LoadReport::default()
        };
        let good =
            serde_json::to_string(&CacheEntry::new(key, header, report, ls.clone())).unwrap();
        std::fs::write(&path, &good).unwrap();
        assert_eq!(read_cache_entry(&path, key).unwrap(), Some((ls, report)));
        let old = good
            .replace(CACHE_FORMAT, "brdfkit-lightset-cache")
            .replace("\"lights_checksum\":\"xxh3-64:", "\"lights_fnv1a\":\"")
            .replace("irradiance_", "power_");
        assert_ne!(old, good);
        std::fs::write(&path, &old).unwrap();
        let why = read_cache_entry(&path, key).unwrap_err();
        assert!(why.contains("lights_fnv1a"), "{why}");
        // With the field name fixed up, the format tag still refuses it.
        std::fs::write(&path, old.replace("lights_fnv1a", "lights_checksum")).unwrap();
        let why = read_cache_entry(&path, key).unwrap_err();
        assert!(why.contains("format brdfkit-lightset-cache,"), "{why}");
    }
}
