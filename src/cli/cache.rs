//! `brdfkit cache [show|clean]`: where the caches are (light sets, transfer and reflection
//! tables, in one directory, and sweep references), how much they hold, the cap, and a way
//! to empty them.
//!
//! Design rule: `clean` deletes only files whose names the caches write themselves
//! (`lights-<16 hex>.json`, `transfer-<16 hex>.bin` and `reflection-<16 hex>.bin`, the
//! tables of [`crate::env::transfer::cache`] and [`crate::env::reflection::cache`], in the
//! light-set cache, `reference-<16 hex>.exr` and its
//! `.exr.xxh3` checksum in the sweep's reference cache; also the `.exr.fnv1a` checksums
//! that builds before the XXH3 hash wrote), never a directory or any other
//! file, so pointing `BRDFKIT_CACHE_DIR` at a directory that holds other things is safe.

use crate::env::lightset::prepare::cap::{cache_files, DEFAULT_CACHE_MAX_BYTES};
use crate::env::lightset::prepare::CacheDir;
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
    let user = CacheDir::user()?;
    let sweep = a
        .sweep_cache
        .clone()
        .unwrap_or_else(|| PathBuf::from("target").join("brdfkit-cache"));
    let cap = match user.max_bytes() {
        Some(b) => format!(
            "; cap {} ($BRDFKIT_CACHE_MAX_MB, default {}), least recently used evicted",
            human(b),
            human(DEFAULT_CACHE_MAX_BYTES)
        ),
        None => String::new(),
    };
    let dirs: Vec<(&str, Option<PathBuf>, String)> = vec![
        (
            "light sets, transfer and reflection tables (brdfkit render, view)",
            user.path().map(Path::to_path_buf),
            cap,
        ),
        (
            "sweep references (brdfkit sweep)",
            Some(sweep),
            "; not capped".to_string(),
        ),
    ];
    for (what, dir, cap) in dirs {
        let Some(dir) = dir else {
            println!("{what}: no directory ($BRDFKIT_CACHE_DIR, $XDG_CACHE_HOME and $HOME unset)");
            continue;
        };
        let files =
            cache_files(&dir).map_err(|e| Error::io(&dir, "cannot list cache directory", e))?;
        let total: u64 = files.iter().map(|f| f.bytes).sum();
        match a.action.unwrap_or(CacheAction::Show) {
            CacheAction::Show => println!(
                "{what}: {}: {} files, {}{cap}",
                dir.display(),
                files.len(),
                human(total)
            ),
            CacheAction::Clean => {
                for f in &files {
                    std::fs::remove_file(&f.path)
                        .map_err(|e| Error::io(&f.path, "cannot remove", e))?;
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
