//! Light-set preparation for a scene (`[env] method = "lights"`): probe file + sampler
//! settings in ([`EnvSpec`]), a light set out, optionally cached on disk ([`cache`]) so a
//! re-render skips decoding and sampling.
//!
//! Design rule: preprocessing runs only when a scene has an environment light, and a cached
//! result is keyed by *what determines it*, versions of the code included
//! ([`file_cache_key`]), and validated on every read ([`read_cache_entry`]). Nothing here
//! reads the environment to find a cache: the caller passes the directory (or none); see
//! [`cache`] for which callers use which.

pub mod cache;
pub mod cap;

pub use cache::{
    cache_file_name, file_cache_key, lights_checksum, read_cache_entry, CacheDir, CacheEntry,
    CACHE_FORMAT, CRATE_VERSION, LIGHT_SET_ALGORITHM_VERSION,
};

use super::file::LightSetHeader;
use super::LightSet;
use crate::env::probe::MAX_PROBE_FILE_BYTES;
use crate::env::schema::EnvSpec;
use crate::env::{LoadReport, Probe};
use crate::error::{Error, Result};
use crate::image_io::write_atomic;
use crate::progress::Progress;
use std::path::{Path, PathBuf};

/// What [`prepare`] did.
#[derive(Clone, Debug, Default)]
pub struct Prepared {
    pub lights: LightSet,
    /// True when the light set came from the cache (the probe was not decoded).
    pub cache_hit: bool,
    /// Loader report (size, cleaning counts): from decoding the probe, or on a cache hit
    /// the one the cache entry recorded when it was made.
    pub report: Option<LoadReport>,
    /// The cache file used, if any.
    pub cache_file: Option<PathBuf>,
    /// Why an existing cache entry was not used (corrupt, another version, ...); `None`
    /// when there was no entry, no cache, or the entry was used.
    pub cache_rejected: Option<String>,
}

/// Loads (or fetches from `cache_dir`, none with `None`) the light set of an environment
/// spec ([`CacheDir::path`] gives the directory of a [`CacheDir`]); `base` is
/// the directory relative probe paths resolve against. Errors name the probe file: missing
/// or unreadable, not a regular file (a device such as `/dev/zero` never ends), over
/// [`MAX_PROBE_FILE_BYTES`],
/// undecodable (see [`Probe::load`]), or fields out of range ([`EnvSpec::check`]).
/// The light irradiances are scaled by `spec.intensity` ([`EnvSpec::scale_intensity`],
/// after the cache: entries hold the unscaled set).
pub fn prepare(spec: &EnvSpec, base: &Path, cache_dir: Option<&Path>) -> Result<Prepared> {
    prepare_with_progress(spec, base, cache_dir, &Progress::hidden())
}

/// [`prepare`], counting on `progress` what the sampler iterates when the light set is
/// computed ([`crate::env::SamplerConfig::run_with_progress`]; nothing on a cache hit). Counting does
/// not change the light set.
pub fn prepare_with_progress(
    spec: &EnvSpec,
    base: &Path,
    cache_dir: Option<&Path>,
    progress: &Progress,
) -> Result<Prepared> {
    spec.check()?;
    if let Some(file) = &spec.lights {
        let mut lights = super::file::read_by_extension(&base.join(file))
            .map_err(|e| Error::Message(format!("env.lights: {e}")))?;
        spec.scale_intensity(&mut lights);
        return Ok(Prepared {
            lights,
            ..Prepared::default()
        });
    }
    let path = base.join(&spec.file);
    // Not a regular file (a device such as /dev/zero, a FIFO) or over the limit: refused
    // before it is read.
    let bytes = crate::image_io::read_regular_file(&path, MAX_PROBE_FILE_BYTES, "light probe")?;
    let opts = spec.load_options();
    let config = spec.sampler_config();
    let key = file_cache_key(&bytes, &opts, &config);
    let cache_file = cache_dir.map(|d| cache_file_name(d, key));
    let mut lights = None;
    let mut report = None;
    let mut cache_rejected = None;
    if let Some(cf) = &cache_file {
        match read_cache_entry(cf, key) {
            Ok(Some((ls, rep))) => {
                lights = Some(ls);
                report = Some(rep);
            }
            Ok(None) => {}
            Err(why) => cache_rejected = Some(why),
        }
    }
    let cache_hit = lights.is_some();
    let mut lights = match lights {
        Some(ls) => ls,
        None => {
            drop(bytes);
            let (probe, rep) =
                Probe::load(&path, &opts).map_err(|e| Error::Message(e.to_string()))?;
            report = Some(rep);
            let ls = config.run_with_progress(&probe, progress);
            if let Some(cf) = &cache_file {
                // A cache that cannot be written only costs time: ignore the error.
                if std::fs::create_dir_all(cf.parent().unwrap_or(Path::new("."))).is_ok() {
                    let header = LightSetHeader::new(&config, path.to_str(), &ls);
                    let entry = CacheEntry::new(key, header, rep, ls.clone());
                    if let Ok(json) = serde_json::to_vec(&entry) {
                        let _ = write_atomic(cf, &json);
                    }
                }
            }
            ls
        }
    };
    spec.scale_intensity(&mut lights);
    Ok(Prepared {
        lights,
        cache_hit,
        report,
        cache_file,
        cache_rejected,
    })
}
