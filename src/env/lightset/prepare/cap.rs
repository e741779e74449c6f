//! The size cap of the user's cache directory (light sets, transfer and reflection tables): least
//! recently used entries are evicted when a new entry would take the directory past the cap.
//!
//! Design rule: only the caches' own files count and only they are ever deleted
//! ([`is_cache_file`]: `lights-<16 hex>.json`, `transfer-<16 hex>.bin`,
//! `reflection-<16 hex>.bin`, and the sweep's
//! `reference-<16 hex>.exr[.xxh3|.fnv1a]`, which `brdfkit cache clean` also removes); "used"
//! is the file's modification time, which a cache hit refreshes ([`touch`]), so the order
//! is least recently *used*, not least recently written. Eviction never fails a render: a
//! file that cannot be listed, dated or removed is left alone. Ties in time are broken by
//! name, so the same directory state evicts the same files.
//!
//! The cap is [`DEFAULT_CACHE_MAX_BYTES`] unless `$BRDFKIT_CACHE_MAX_MB` says otherwise
//! (read by [`super::CacheDir::user`], with the directory). The sweep's reference cache
//! (`target/brdfkit-cache`) is not capped: a reference costs minutes to render, it lives
//! under `target/`, and `cargo clean` or `brdfkit cache clean` removes it.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// The default cap of the user's cache directory: 500 MB (about 50 full-probe light sets of
/// a 512x256 probe, or 75 transfer tables of the default grid).
pub const DEFAULT_CACHE_MAX_BYTES: u64 = 500_000_000;

/// Whether `name` is a file one of the caches writes (see the module doc).
pub fn is_cache_file(name: &str) -> bool {
    let hex16 = |s: &str| s.len() == 16 && s.bytes().all(|b| b.is_ascii_hexdigit());
    if let Some(k) = name
        .strip_prefix("lights-")
        .and_then(|r| r.strip_suffix(".json"))
    {
        return hex16(k);
    }
    if let Some(k) = name
        .strip_prefix("transfer-")
        .or_else(|| name.strip_prefix("reflection-"))
        .and_then(|r| r.strip_suffix(".bin"))
    {
        return hex16(k);
    }
    if let Some(r) = name.strip_prefix("reference-") {
        let k = r
            .strip_suffix(".exr.xxh3")
            .or_else(|| r.strip_suffix(".exr.fnv1a"))
            .or_else(|| r.strip_suffix(".exr"));
        return k.is_some_and(hex16);
    }
    false
}

/// A cache file: path, size in bytes and last use (modification time).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CacheFile {
    pub path: PathBuf,
    pub bytes: u64,
    pub used: SystemTime,
}

/// The cache files directly in `dir`, sorted by path (none when `dir` is missing). Fails
/// only when the directory exists and cannot be listed; an entry that vanishes while it is
/// listed is skipped.
pub fn cache_files(dir: &Path) -> std::io::Result<Vec<CacheFile>> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e),
    };
    let mut out = Vec::new();
    for e in entries {
        let e = e?;
        let name = e.file_name().to_string_lossy().into_owned();
        let Ok(meta) = e.metadata() else { continue };
        if meta.is_file() && is_cache_file(&name) {
            out.push(CacheFile {
                path: e.path(),
                bytes: meta.len(),
                used: meta.modified().unwrap_or(SystemTime::UNIX_EPOCH),
            });
        }
    }
    out.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(out)
}

/// Marks a cache entry as used now (its modification time), so eviction keeps it longer.
/// Errors are ignored: a read-only cache still serves hits.
pub fn touch(path: &Path) {
    if let Ok(f) = std::fs::File::options().write(true).open(path) {
        let _ = f.set_modified(SystemTime::now());
    }
}

/// Removes the least recently used cache files of `dir` until their total size is at most
/// `max_bytes`, never `keep` (the entry just written, which may alone exceed the cap).
/// Returns the files removed. Errors are ignored (module doc).
pub fn enforce_cap(dir: &Path, max_bytes: u64, keep: &Path) -> Vec<PathBuf> {
    let Ok(mut files) = cache_files(dir) else {
        return Vec::new();
    };
    let mut total: u64 = files.iter().map(|f| f.bytes).sum();
    files.sort_by(|a, b| a.used.cmp(&b.used).then_with(|| a.path.cmp(&b.path)));
    let mut removed = Vec::new();
    for f in files {
        if total <= max_bytes {
            break;
        }
        if f.path == keep {
            continue;
        }
        if std::fs::remove_file(&f.path).is_ok() {
            total -= f.bytes;
            removed.push(f.path);
        }
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn only_the_caches_own_file_names_count() {
        assert!(is_cache_file("lights-0123456789abcdef.json"));
        assert!(is_cache_file("transfer-0123456789abcdef.bin"));
        // The names the table caches write themselves.
        let dir = Path::new("cache");
        for written in [
            crate::env::reflection::cache::table_file_name(dir, 0x0123_4567_89ab_cdef),
            crate::env::transfer::cache::table_file_name(dir, 0x0123_4567_89ab_cdef),
        ] {
            let name = written.file_name().unwrap().to_string_lossy().into_owned();
            assert!(is_cache_file(&name), "{name}");
        }
        assert!(is_cache_file("reference-0123456789ABCDEF.exr"));
        assert!(is_cache_file("reference-0123456789abcdef.exr.xxh3"));
        // Written by builds before the XXH3 hash: still cleaned.
        assert!(is_cache_file("reference-0123456789abcdef.exr.fnv1a"));
        for other in [
            "lights-0123.json",
            "transfer-0123.bin",
            "transfer-0123456789abcdef.bin.tmp",
            "transfer-0123456789abcdef.json",
            "reflection-0123.bin",
            "reflection-0123456789abcdef.bin.tmp",
            "lights-0123456789abcdef.json.tmp",
            "reference-0123456789abcdeg.exr",
            "notes.txt",
            "lights-.json",
            ".lights-0123456789abcdef.json",
        ] {
            assert!(!is_cache_file(other), "{other}");
        }
    }

    /// Three entries of 100 bytes used at t = 1, 3, 2 s and a foreign file; a cap of 150
    /// bytes keeping the newest-written one removes the least recently used first and
    /// stops when under the cap; the foreign file stays.
    #[test]
    fn eviction_removes_the_least_recently_used_first() {
        let tmp = tempfile::tempdir().unwrap();
        let d = tmp.path();
        let name = |k: u8| d.join(format!("lights-{:016x}.json", k));
        let t0 = SystemTime::UNIX_EPOCH + Duration::from_secs(1_000_000);
        for (k, secs) in [(1u8, 1u64), (2, 3), (3, 2)] {
            std::fs::write(name(k), [0u8; 100]).unwrap();
            let f = std::fs::File::options().write(true).open(name(k)).unwrap();
            f.set_modified(t0 + Duration::from_secs(secs)).unwrap();
        }
        std::fs::write(d.join("notes.txt"), [0u8; 1000]).unwrap();
        std::fs::write(d.join("transfer-00000000000000ff.bin"), [0u8; 100]).unwrap();
        let keep = d.join("transfer-00000000000000ff.bin");
        let f = std::fs::File::options().write(true).open(&keep).unwrap();
        f.set_modified(t0 + Duration::from_secs(5)).unwrap();
        let removed = enforce_cap(d, 150, &keep);
        // 400 bytes of entries: remove k=1 (t=1), k=3 (t=2), k=2 (t=3) -> 100 left (keep).
        assert_eq!(removed, vec![name(1), name(3), name(2)]);
        assert!(keep.exists() && d.join("notes.txt").exists());
        // Under the cap, nothing goes.
        assert!(enforce_cap(d, 150, &keep).is_empty());
        // A touched entry is the most recently used.
        std::fs::write(name(4), [0u8; 100]).unwrap();
        let f = std::fs::File::options().write(true).open(name(4)).unwrap();
        f.set_modified(t0).unwrap();
        touch(&name(4));
        let removed = enforce_cap(d, 100, &name(9));
        assert_eq!(
            removed,
            vec![keep.clone()],
            "the untouched, older entry goes first"
        );
    }
}
