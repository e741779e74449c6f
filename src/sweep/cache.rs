//! The sweep's reference cache ([`super`], "The reference"): `reference-<key>.exr` and its
//! checksum file `reference-<key>.exr.xxh3` in the `--cache` directory, keyed by
//! [`reference_key`] (which includes the crate version, [`REFERENCE_ALGORITHM_VERSION`] and
//! [`crate::env::lightset::prepare::LIGHT_SET_ALGORITHM_VERSION`]) and checked on read
//! ([`read_cached_reference`]).

use crate::error::{Error, Result};
use crate::hash::{self, StableHasher};
use crate::image_io::{self, Image};
use crate::scene::{MaterialSpec, SceneFile};
use std::path::{Path, PathBuf};

/// Version of the algorithm behind a cached reference render:
/// [`crate::render::RenderOptions::converged_reference`] (rasterization, the f64 shading path, [`crate::brdf::Brdf::eval_f64`] of every model,
/// the SH and D-BRDF evaluation). Part of [`reference_key`].
///
/// Bump when the output of the converged reference changes for the same scene, so no reference
/// rendered by older code is read. (Light-set changes are covered by
/// [`crate::env::lightset::prepare::LIGHT_SET_ALGORITHM_VERSION`], also in the key.)
/// 2: negative probe texels keep the signed integral (the reference's full probe changed);
/// the UV sphere is shaded at the exact sphere seen through each pixel.
pub const REFERENCE_ALGORITHM_VERSION: u32 = 2;

/// Cache key of a reference render: [`StableHasher`] (XXH3-64) of a key tag, the crate version,
/// [`REFERENCE_ALGORITHM_VERSION`], [`crate::env::lightset::prepare::LIGHT_SET_ALGORITHM_VERSION`],
/// the scene description (as parsed, with the output section and thread count cleared, and
/// the environment's sampler set to `full`), the base directory, and the bytes of the probe
/// and of a material file.
pub fn reference_key(file: &SceneFile, base: &Path) -> Result<u64> {
    let mut h = StableHasher::new();
    // v3: XXH3-64 instead of FNV-1a (a v2 key names an FNV-1a hash).
    h.write(b"brdfkit-sweep-reference-v3");
    h.write_str(env!("CARGO_PKG_VERSION"));
    h.write_u64(REFERENCE_ALGORITHM_VERSION as u64);
    h.write_u64(crate::env::lightset::prepare::LIGHT_SET_ALGORITHM_VERSION as u64);
    h.write(format!("{file:?}").as_bytes());
    h.write(base.to_string_lossy().as_bytes());
    let mut files = Vec::new();
    if let Some(env) = &file.env {
        files.push(base.join(&env.file));
    }
    match &file.material {
        MaterialSpec::ShFile { path, .. }
        | MaterialSpec::DbrdfFile { path }
        | MaterialSpec::MerlFile { path }
        | MaterialSpec::RglFile { path } => files.push(base.join(path)),
        MaterialSpec::Lambert { .. }
        | MaterialSpec::BlinnPhong { .. }
        | MaterialSpec::Library { .. } => {}
    }
    for f in files {
        let bytes = std::fs::read(&f).map_err(|e| Error::io(&f, "cannot read", e))?;
        h.write_u64(bytes.len() as u64);
        h.write(&bytes);
    }
    Ok(h.finish())
}

/// Checksum ([`StableHasher`]) of an image: width, height, then every pixel's RGB f32 bits
/// (little-endian, row-major). Written beside a cached reference in [`hash::tagged`] form
/// and checked on read.
pub fn image_checksum(img: &Image) -> u64 {
    let mut h = StableHasher::new();
    h.write_u64(img.width as u64);
    h.write_u64(img.height as u64);
    h.write_f32s(img.pixels.iter().flat_map(|p| p.to_array()));
    h.finish()
}

/// Extension of a cached reference's checksum file (after `.exr`).
pub const CHECKSUM_EXTENSION: &str = "xxh3";

/// The checksum file of a cached reference: `<file>.xxh3`. (Entries written before the
/// hash was XXH3 have only a `.fnv1a` file, so they are refused and re-rendered.)
fn checksum_path(file: &Path) -> PathBuf {
    let mut name = file.as_os_str().to_owned();
    name.push(".");
    name.push(CHECKSUM_EXTENSION);
    PathBuf::from(name)
}

/// Reads the cached reference `file` of a `width` x `height` scene if it is usable (module
/// doc): `Ok(None)` when absent, `Err(why)` when present but not used.
pub fn read_cached_reference(
    file: &Path,
    width: u32,
    height: u32,
) -> std::result::Result<Option<Image>, String> {
    if !file.exists() {
        return Ok(None);
    }
    let img = image_io::read_exr(file).map_err(|e| e.to_string())?;
    if (img.width, img.height) != (width, height) {
        return Err(format!(
            "{}x{}, the scene is {width}x{height}",
            img.width, img.height
        ));
    }
    // Only finiteness: an SH material's truncated expansion can shade below zero.
    if let Some(p) = img.pixels.iter().find(|p| !p.is_finite()) {
        return Err(format!("pixel {p} is not finite"));
    }
    let sum_file = checksum_path(file);
    let stored =
        std::fs::read_to_string(&sum_file).map_err(|e| format!("{}: {e}", sum_file.display()))?;
    let sum = hash::tagged(image_checksum(&img));
    if stored.trim() != sum {
        return Err(format!(
            "checksum {} does not match its pixels ({sum}): edited or damaged",
            stored.trim()
        ));
    }
    Ok(Some(img))
}

/// Writes a reference and its checksum file (each atomically; the EXR first, so a crash
/// between leaves an entry [`read_cached_reference`] refuses).
pub(super) fn write_cached_reference(file: &Path, img: &Image) -> Result<()> {
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::io(dir, "cannot create cache directory", e))?;
    }
    image_io::write_exr(file, img)?;
    let sum_file = checksum_path(file);
    let text = format!("{}\n", hash::tagged(image_checksum(img)));
    image_io::write_atomically(&sum_file, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| Error::io(&sum_file, "cannot write", e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A reference whose checksum file is the FNV-1a era's `.fnv1a` (no `.xxh3`), or holds
    /// an FNV-1a-style string, is refused; this build's entry is read.
    #[test]
    fn only_this_builds_checksum_is_trusted() {
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("reference-0123456789abcdef.exr");
        let img = Image {
            width: 2,
            height: 1,
            pixels: vec![Vec3::new(0.5, 1.0, 2.0), Vec3::ZERO],
        };
        write_cached_reference(&file, &img).unwrap();
        assert_eq!(
            read_cached_reference(&file, 2, 1).unwrap(),
            Some(img.clone())
        );
        let sum = checksum_path(&file);
        assert!(sum.to_string_lossy().ends_with(".exr.xxh3"));
        let text = std::fs::read_to_string(&sum).unwrap();
        assert!(text.starts_with("xxh3-64:"), "{text}");

        std::fs::write(&sum, "fnv1a64:0123456789abcdef\n").unwrap();
        let why = read_cached_reference(&file, 2, 1).unwrap_err();
        assert!(why.contains("does not match"), "{why}");

        std::fs::remove_file(&sum).unwrap();
        std::fs::write(file.with_extension("exr.fnv1a"), text).unwrap();
        assert!(read_cached_reference(&file, 2, 1).is_err());
    }
}
