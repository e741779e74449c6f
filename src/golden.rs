//! The golden-image oracle: reference renders stored in `golden/`, re-rendered and compared.
//!
//! Design rule: golden files change only through `brdfkit golden bless` (the [`bless`]
//! function); checking never writes under `golden/`. A failing check leaves, under
//! `target/golden-failures/`, an `expected | difference | actual` PNG strip and a JSON
//! report for whoever investigates. Tolerances are the named constants of this module.
//!
//! `golden/manifest.toml` lists the entries:
//! ```toml
//! [[entry]]
//! name = "default"            # also the stem of golden/<name>.exr
//! scene = "default.toml"      # relative to golden/
//! tolerance = "cross-platform"
//! hash = "fnv1a64:..."        # of the EXR's pixel values, written by bless
//! ```

use crate::error::{Error, Result};
use crate::image_io::{self, Image};
use crate::render;
use crate::scene::{Scene, SceneFile};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A per-pixel tolerance: `|actual - expected| <= abs + rel * |expected|` on every channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    pub abs: f32,
    pub rel: f32,
}

/// For renders that must agree across machines and compilers: the f32 results may differ
/// by a few ulps where `powf`, `acos` and `sin` come from another libm, never by a
/// shading or coverage change (a covered pixel's value moves by far more than 1e-4).
pub const CROSS_PLATFORM: Tolerance = Tolerance {
    abs: 1e-5,
    rel: 1e-4,
};

/// Looks up a tolerance by its manifest name.
pub fn tolerance_named(name: &str) -> Option<Tolerance> {
    match name {
        "cross-platform" => Some(CROSS_PLATFORM),
        _ => None,
    }
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    #[serde(rename = "entry")]
    pub entries: Vec<Entry>,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    pub name: String,
    pub scene: String,
    pub tolerance: String,
    #[serde(default)]
    pub hash: String,
}

/// The outcome of comparing one entry.
#[derive(Debug, Serialize)]
pub struct Outcome {
    pub name: String,
    pub passed: bool,
    pub max_abs_error: f32,
    pub pixels_over_tolerance: usize,
    pub message: String,
}

/// FNV-1a 64-bit hash of the little-endian bytes of every channel value.
pub fn content_hash(img: &Image) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in &img.pixels {
        for c in p.to_array() {
            for byte in c.to_le_bytes() {
                h ^= byte as u64;
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
    format!("fnv1a64:{h:016x}")
}

/// Reads `dir/manifest.toml`.
pub fn load_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join("manifest.toml");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Error::io(&path, "cannot read golden manifest", e))?;
    toml::from_str(&text).map_err(|e| Error::format(&path, e.message().trim().replace('\n', " ")))
}

/// Renders an entry's scene (threads: all cores; the result does not depend on it).
pub fn render_entry(dir: &Path, entry: &Entry) -> Result<Image> {
    let scene_path = dir.join(&entry.scene);
    let file = SceneFile::load(&scene_path)?;
    let scene =
        Scene::resolve(&file, dir).map_err(|e| Error::format(&scene_path, e.to_string()))?;
    Ok(render::render(&scene, None))
}

/// Compares two images with a tolerance; `None` if their sizes differ.
pub fn compare(expected: &Image, actual: &Image, tol: Tolerance) -> Option<(f32, usize)> {
    if expected.width != actual.width || expected.height != actual.height {
        return None;
    }
    let mut max_abs = 0.0f32;
    let mut over = 0;
    for (e, a) in expected.pixels.iter().zip(&actual.pixels) {
        let d = (*a - *e).abs();
        let lim = Vec3::splat(tol.abs) + e.abs() * tol.rel;
        // NaN in either image fails.
        if !(d.cmple(lim).all()) {
            over += 1;
        }
        max_abs = max_abs.max(if d.is_nan() {
            f32::INFINITY
        } else {
            d.max_element()
        });
    }
    Some((max_abs, over))
}

/// Writes `expected | difference | actual` side by side as a PNG (difference: absolute
/// error scaled so the largest is white).
pub fn write_triptych(path: &Path, expected: &Image, actual: &Image) -> Result<()> {
    let (w, h) = (
        expected.width.max(actual.width),
        expected.height.max(actual.height),
    );
    let mut bytes = vec![0u8; (3 * w * h * 3) as usize];
    let get = |img: &Image, x: u32, y: u32| {
        if x < img.width && y < img.height {
            img.get(x, y)
        } else {
            Vec3::ZERO
        }
    };
    let mut max_d = f32::MIN_POSITIVE;
    for y in 0..h {
        for x in 0..w {
            max_d = max_d.max(
                (get(expected, x, y) - get(actual, x, y))
                    .abs()
                    .max_element(),
            );
        }
    }
    for y in 0..h {
        for x in 0..w {
            let e = get(expected, x, y);
            let a = get(actual, x, y);
            let d = Vec3::splat((e - a).abs().max_element() / max_d);
            for (k, v) in [e, d, a].into_iter().enumerate() {
                let px = ((y * 3 * w + k as u32 * w + x) * 3) as usize;
                let c = if k == 1 {
                    v.to_array().map(image_io::to_u8)
                } else {
                    v.to_array()
                        .map(|c| image_io::display_u8(c, 0.0, image_io::Tonemap::Aces))
                };
                bytes[px..px + 3].copy_from_slice(&c);
            }
        }
    }
    image_io::write_png_bytes(path, 3 * w, h, bytes)
}

/// Checks every entry of `dir`; failures leave artefacts in `report_dir`.
pub fn check(dir: &Path, report_dir: &Path) -> Result<Vec<Outcome>> {
    let manifest = load_manifest(dir)?;
    let mut out = Vec::new();
    for entry in &manifest.entries {
        let tol = tolerance_named(&entry.tolerance).ok_or_else(|| {
            Error::format(
                dir.join("manifest.toml"),
                format!(
                    "entry '{}': unknown tolerance '{}'",
                    entry.name, entry.tolerance
                ),
            )
        })?;
        let image_path = dir.join(format!("{}.exr", entry.name));
        let expected = image_io::read_exr(&image_path)?;
        let actual = render_entry(dir, entry)?;
        let hash_ok = entry.hash == content_hash(&expected);
        let outcome = match compare(&expected, &actual, tol) {
            None => Outcome {
                name: entry.name.clone(),
                passed: false,
                max_abs_error: f32::INFINITY,
                pixels_over_tolerance: usize::MAX,
                message: format!(
                    "size differs: golden {}x{}, render {}x{}",
                    expected.width, expected.height, actual.width, actual.height
                ),
            },
            Some((max_abs, over)) => Outcome {
                name: entry.name.clone(),
                passed: over == 0 && hash_ok,
                max_abs_error: max_abs,
                pixels_over_tolerance: over,
                message: if !hash_ok {
                    format!(
                        "{} does not match its manifest hash: edited outside `golden bless`?",
                        image_path.display()
                    )
                } else if over > 0 {
                    format!(
                        "{over} pixels over tolerance '{}' (max abs error {max_abs:e})",
                        entry.tolerance
                    )
                } else {
                    "ok".into()
                },
            },
        };
        if !outcome.passed {
            std::fs::create_dir_all(report_dir)
                .map_err(|e| Error::io(report_dir, "cannot create report directory", e))?;
            write_triptych(
                &report_dir.join(format!("{}.png", entry.name)),
                &expected,
                &actual,
            )?;
            let json = serde_json::to_string_pretty(&outcome).expect("serialisable");
            let jp = report_dir.join(format!("{}.json", entry.name));
            image_io::write_atomically(&jp, |tmp| {
                std::fs::write(tmp, &json).map_err(|e| Error::io(&jp, "cannot write report", e))
            })?;
        }
        out.push(outcome);
    }
    Ok(out)
}

/// Re-renders and rewrites the named entries (all if `names` is empty) and their hashes.
pub fn bless(dir: &Path, names: &[String]) -> Result<Vec<PathBuf>> {
    let mut manifest = load_manifest(dir)?;
    for n in names {
        if !manifest.entries.iter().any(|e| &e.name == n) {
            return Err(Error::field(
                "golden bless",
                format!(
                    "no entry named '{n}' in {}",
                    dir.join("manifest.toml").display()
                ),
            ));
        }
    }
    let mut written = Vec::new();
    for entry in manifest.entries.iter_mut() {
        if !names.is_empty() && !names.contains(&entry.name) {
            continue;
        }
        let img = render_entry(dir, entry)?;
        let path = dir.join(format!("{}.exr", entry.name));
        image_io::write_exr(&path, &img)?;
        let png = dir.join(format!("{}.png", entry.name));
        image_io::write_png(&png, &img, 0.0, image_io::Tonemap::Aces)?;
        entry.hash = content_hash(&image_io::read_exr(&path)?);
        written.push(path);
    }
    let mpath = dir.join("manifest.toml");
    let text = toml::to_string_pretty(&manifest).expect("serialisable");
    image_io::write_atomically(&mpath, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| Error::io(&mpath, "cannot write manifest", e))
    })?;
    Ok(written)
}
