//! Shared by the file-based targets: each input is written to a file the parser reads.

use std::path::PathBuf;

/// A per-process scratch file with extension `ext`, holding `data`.
pub fn scratch(ext: &str, data: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("brdfkit-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(format!("input.{ext}"));
    std::fs::write(&p, data).unwrap();
    p
}
