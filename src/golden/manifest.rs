//! `golden/manifest.toml`: the entries, their parsing and checks, and the content hash of a
//! stored image.

use super::*;

/// FLIP bounds written in a manifest entry (override the tolerance's).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FlipSpec {
    /// Largest passing FLIP mean, in [0, 1].
    pub mean: f32,
    /// Percentile of the second bound, in (0, 1).
    pub percentile: f32,
    /// Largest passing FLIP value at `percentile`, in [0, 1].
    pub at_percentile: f32,
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
    /// The thesis figure the entry reproduces ("" for none).
    #[serde(default)]
    pub figure: String,
    /// What the image shows (one line, for golden/README.md).
    #[serde(default)]
    pub shows: String,
    pub scene: String,
    /// A debug output rendered instead of the shaded image.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aov: Option<Aov>,
    pub tolerance: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip: Option<FlipSpec>,
    /// Configuration summary ([`summarize`]), written by bless.
    #[serde(default)]
    pub config: String,
    #[serde(default)]
    pub hash: String,
    /// Where the stored image was rendered ([`blessing_path`]), written by bless: the check
    /// demands identical bits there and the tolerance elsewhere.
    #[serde(default)]
    pub blessed_on: String,
    /// Written by bless ([`measure`] at full size); absent for debug outputs (nothing is
    /// shaded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fast_vs_reference: Option<MeasuredBound>,
    /// [`measure`] at 1/[`BOUND_CHECK_SCALE`] of the entry's size, written by bless and
    /// re-measured by [`check_bounds`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fast_vs_reference_small: Option<MeasuredBound>,
}

impl Entry {
    /// The entry's FLIP bounds: its own `flip`, else its tolerance's.
    pub fn thresholds(&self) -> Option<Thresholds> {
        let tol = tolerance_named(&self.tolerance)?;
        Some(match self.flip {
            Some(f) => Thresholds {
                flip_mean: f.mean,
                percentile: f.percentile,
                flip_at_percentile: f.at_percentile,
                radiometric: RadiometricBounds::NONE,
            },
            None => tol.flip,
        })
    }

    /// The entry called `name` in `manifest`; the error names the manifest and lists the
    /// entries.
    pub fn find<'a>(manifest: &'a Manifest, path: &Path, name: &str) -> Result<&'a Entry> {
        manifest
            .entries
            .iter()
            .find(|e| e.name == name)
            .ok_or_else(|| {
                Error::format(
                    path,
                    format!(
                        "no entry named '{name}' (entries: {})",
                        manifest
                            .entries
                            .iter()
                            .map(|e| e.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                )
            })
    }
}

/// The stable hash ([`crate::hash`], XXH3-64) of the little-endian bytes of every channel
/// value (row-major, RGB), in [`crate::hash::tagged`] form: `"xxh3-64:<16 hex>"`.
pub fn content_hash(img: &Image) -> String {
    let mut h = crate::hash::StableHasher::new();
    h.write_f32s(img.pixels.iter().flat_map(|p| p.to_array()));
    crate::hash::tagged(h.finish())
}

/// Largest manifest read (bytes): a set of a few hundred entries is far below it.
pub const MAX_MANIFEST_BYTES: u64 = 1 << 20;

/// The manifest's path in `dir`.
pub fn manifest_path(dir: &Path) -> PathBuf {
    dir.join("manifest.toml")
}

/// Reads and checks `dir/manifest.toml` ([`parse_manifest`]).
pub fn load_manifest(dir: &Path) -> Result<Manifest> {
    let path = manifest_path(dir);
    load_manifest_file(&path)
}

/// Reads and checks a manifest file. Errors name the file and, for content errors, the
/// line or the entry and field. Not a regular file, or over [`MAX_MANIFEST_BYTES`]: refused
/// unread ([`crate::image_io::read_regular_file`]).
pub fn load_manifest_file(path: &Path) -> Result<Manifest> {
    let text = crate::image_io::read_regular_text(path, MAX_MANIFEST_BYTES, "golden manifest")?;
    parse_manifest(&text).map_err(|m| Error::format(path, m))
}

/// Parses manifest text and checks every entry: a name usable as a file stem
/// (`[a-z0-9._-]`, not starting with `.`), unique; a known tolerance; FLIP bounds in range.
/// The error is one line naming the entry and field (or the line, for TOML errors).
pub fn parse_manifest(text: &str) -> std::result::Result<Manifest, String> {
    let m: Manifest = toml::from_str(text).map_err(|e| crate::error::toml_message(text, &e))?;
    let mut seen = std::collections::HashSet::new();
    for (i, e) in m.entries.iter().enumerate() {
        let at = |field: &str| format!("entry[{i}] ('{}').{field}", e.name);
        let stem_ok = !e.name.is_empty()
            && !e.name.starts_with('.')
            && e.name
                .bytes()
                .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b"._-".contains(&b));
        if !stem_ok {
            return Err(format!(
                "{}: must be a file stem of a-z, 0-9, '.', '_', '-' (not starting with '.')",
                at("name")
            ));
        }
        if !seen.insert(e.name.as_str()) {
            return Err(format!("{}: duplicate entry name", at("name")));
        }
        if e.scene.is_empty() {
            return Err(format!("{}: must name a scene file", at("scene")));
        }
        // The golden set is self-contained: a scene lies in the manifest's directory or below
        // it, so checking never reads (and a report never names) a file outside the set.
        let inside = Path::new(&e.scene).components().all(|c| {
            matches!(
                c,
                std::path::Component::Normal(_) | std::path::Component::CurDir
            )
        });
        if !inside {
            return Err(format!(
                "{}: '{}' must be a relative path inside the golden directory (no '..', no root)",
                at("scene"),
                e.scene
            ));
        }
        if tolerance_named(&e.tolerance).is_none() {
            let known: Vec<&str> = TOLERANCES.iter().map(|(n, _)| *n).collect();
            return Err(format!(
                "{}: unknown tolerance '{}' (known: {})",
                at("tolerance"),
                e.tolerance,
                known.join(", ")
            ));
        }
        if let Some(f) = e.flip {
            let unit = |x: f32| (0.0..=1.0).contains(&x);
            if !(unit(f.mean) && unit(f.at_percentile) && f.percentile > 0.0 && f.percentile < 1.0)
            {
                return Err(format!(
                    "{}: mean and at_percentile must be in [0, 1], percentile in (0, 1)",
                    at("flip")
                ));
            }
        }
    }
    Ok(m)
}
