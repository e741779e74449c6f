//! `brdfkit cache [show|clean]`: where the two caches are, how much they hold, and a way to
//! empty them.
//!
//! Design rule: `clean` deletes only files whose names the caches write themselves
//! (`lights-<16 hex>.json` and `transfer-<16 hex>.bin`, the transfer tables of
//! [`crate::env::transfer::cache`], in the light-set cache, `reference-<16 hex>.exr` and its
//! `.exr.xxh3` checksum in the sweep's reference cache; also the `.exr.fnv1a` checksums
//! that builds before the XXH3 hash wrote), never a directory or any other
//! file, so pointing `BRDFKIT_CACHE_DIR` at a directory that holds other things is safe.

use crate::env::prepare::CacheDir;
use crate::error::{Error, Result};
use clap::Subcommand;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct CacheArgs {
    #[command(subcommand)]
    pub action: Option<CacheAction>,
    /// The sweep's reference cache directory, if not the default target/brdfkit-cache.
    #[arg(long, value_name = "DIR", global = true)]
    pub sweep_cache: Option<PathBuf>,
}

#[derive(Subcommand, Debug, Clone, Copy)]
pub enum CacheAction {
    /// Directory, number of entries and size of each cache (the default).
    Show,
    /// Delete every cache entry (only files the caches wrote; nothing else).
    Clean,
}

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

/// The cache files directly in `dir` with their sizes (none if the directory is missing).
fn cache_files(dir: &Path) -> Result<Vec<(PathBuf, u64)>> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(Error::io(dir, "cannot list cache directory", e)),
    };
    let mut out = Vec::new();
    for e in entries {
        let e = e.map_err(|err| Error::io(dir, "cannot list cache directory", err))?;
        let name = e.file_name().to_string_lossy().into_owned();
        let meta = e
            .metadata()
            .map_err(|err| Error::io(e.path(), "cannot stat", err))?;
        if meta.is_file() && is_cache_file(&name) {
            out.push((e.path(), meta.len()));
        }
    }
    out.sort();
    Ok(out)
}

/// A byte count for people: `12.3 MB`.
fn human(bytes: u64) -> String {
    let b = bytes as f64;
    match bytes {
        0..1_000 => format!("{bytes} B"),
        1_000..1_000_000 => format!("{:.1} kB", b / 1e3),
        1_000_000..1_000_000_000 => format!("{:.1} MB", b / 1e6),
        _ => format!("{:.2} GB", b / 1e9),
    }
}

pub fn run(a: CacheArgs) -> Result<()> {
    let user = CacheDir::user();
    let sweep = a
        .sweep_cache
        .clone()
        .unwrap_or_else(|| PathBuf::from("target").join("brdfkit-cache"));
    let dirs: Vec<(&str, Option<PathBuf>)> = vec![
        (
            "light sets and transfer tables (brdfkit render)",
            user.path().map(Path::to_path_buf),
        ),
        ("sweep references (brdfkit sweep)", Some(sweep)),
    ];
    for (what, dir) in dirs {
        let Some(dir) = dir else {
            println!("{what}: no directory ($BRDFKIT_CACHE_DIR, $XDG_CACHE_HOME and $HOME unset)");
            continue;
        };
        let files = cache_files(&dir)?;
        let total: u64 = files.iter().map(|(_, n)| n).sum();
        match a.action.unwrap_or(CacheAction::Show) {
            CacheAction::Show => println!(
                "{what}: {}: {} files, {}",
                dir.display(),
                files.len(),
                human(total)
            ),
            CacheAction::Clean => {
                for (p, _) in &files {
                    std::fs::remove_file(p).map_err(|e| Error::io(p, "cannot remove", e))?;
                }
                println!(
                    "{what}: {}: removed {} files, {}",
                    dir.display(),
                    files.len(),
                    human(total)
                );
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::is_cache_file;

    #[test]
    fn only_the_caches_own_file_names_count() {
        assert!(is_cache_file("lights-0123456789abcdef.json"));
        assert!(is_cache_file("transfer-0123456789abcdef.bin"));
        assert!(is_cache_file("reference-0123456789ABCDEF.exr"));
        assert!(is_cache_file("reference-0123456789abcdef.exr.xxh3"));
        // Written by builds before the XXH3 hash: still cleaned.
        assert!(is_cache_file("reference-0123456789abcdef.exr.fnv1a"));
        for other in [
            "lights-0123.json",
            "transfer-0123.bin",
            "transfer-0123456789abcdef.bin.tmp",
            "transfer-0123456789abcdef.json",
            "lights-0123456789abcdef.json.tmp",
            "reference-0123456789abcdeg.exr",
            "notes.txt",
            "lights-.json",
            ".lights-0123456789abcdef.json",
        ] {
            assert!(!is_cache_file(other), "{other}");
        }
    }
}
