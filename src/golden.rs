//! The golden-image oracle: reference renders stored in `golden/`, re-rendered and compared.
//!
//! Design rule: golden files change only through `brdfkit golden bless` (the [`bless`]
//! function); checking never writes under `golden/`. A failing check leaves, under
//! `target/golden-failures/`, an `expected | difference | actual` PNG strip and a JSON
//! report for whoever investigates. Tolerances are the named constants of this module
//! ([`TOLERANCES`]), each with the reason for its size.
//!
//! `golden/manifest.toml` lists the entries:
//! ```toml
//! [[entry]]
//! name = "fig3-3-view-polar"  # also the stem of golden/<name>.exr and .png
//! figure = "3.3 (left)"       # the thesis figure it reproduces ("" for none)
//! shows = "..."               # one line: what the image shows
//! scene = "fig3-3-view-polar.toml"   # relative to golden/
//! aov = "view-polar"          # optional: a debug output instead of the shaded image
//! tolerance = "cross-platform"       # a name in TOLERANCES
//! flip = { mean = 0.01, percentile = 0.99, at_percentile = 0.1 }  # optional: overrides the
//!                             # tolerance's FLIP bounds for `brdfkit compare --entry`
//! # written by `golden bless`, never by hand:
//! config = "..."              # summary of the scene's configuration (checked for staleness)
//! hash = "fnv1a64:..."        # of the EXR's pixel values
//! blessed_on = "x86_64-linux/avx2"   # the platform and kernel path that rendered it
//! fast_vs_reference = { max_abs = .., rel_rmse = .., flip_mean = .. }   # see [`Bound`]
//! fast_vs_reference_small = { .. }   # the same at 1/BOUND_CHECK_SCALE of the size
//! ```
//!
//! The check re-renders each entry and compares it with its stored render. On the
//! platform and kernel path that blessed the entry ([`Entry::blessed_on`], [`blessing_path`])
//! every bit must agree: the render is deterministic there, so any change at all (a
//! constant off by 0.05%, one texel, one dropped light) fails. On another platform or path
//! the entry's tolerance applies. The two kernel paths give the same bits by construction
//! ([`crate::kernel::lanes`]), which `tests/golden.rs` checks over the whole set, so in
//! practice the tolerance serves only other platforms (another libm, another instruction
//! set) and GPU builds.
//!
//! The slow reference render ([`measure`]) is run by `bless`, which records the measured
//! fast-vs-reference bound at full size and at 1/[`BOUND_CHECK_SCALE`] of it; `golden check
//! --bounds` ([`check_bounds`]) re-measures the small one and holds it to the stored value
//! within [`BOUND_MARGIN`], so a change of the sampler, the reference path or the light
//! set that makes the fast path drift from the converged reference is caught in CI.

use crate::aov::Aov;
use crate::compare::{self, Loaded, Thresholds};
use crate::env::prepare::SamplerKind;
use crate::error::{Error, Result};
use crate::image_io::{self, Image};
use crate::kernel::lanes::{Dispatch, KernelPath};
use crate::render;
use crate::scene::{LightSpec, MaterialSpec, Precision, Scene, SceneFile};
use crate::sh::dataset::Lookup;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A per-pixel tolerance for the golden check, plus the FLIP bounds `brdfkit compare
/// --manifest --entry` applies to a GPU build's image of the entry.
///
/// Per channel: `|actual - expected| <= abs + rel * max(|expected|, peak_floor * peak)`,
/// `peak` being the largest channel value of the expected image. `peak_floor` keeps the
/// relative bound meaningful where a sum of large terms of both signs cancels to a value
/// far below its terms (SH ringing; thesis 2.3.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    pub abs: f32,
    pub rel: f32,
    pub peak_floor: f32,
    /// FLIP bounds for another implementation's image of the entry (see [`Thresholds`]).
    pub flip: Thresholds,
}

/// For values that must agree across machines and compilers bit for bit up to libm: the
/// debug outputs (angles through `acos`/`atan2`, depths, normals, integer coverage) and the
/// f64 path (rounded to f32 once per pixel). Another libm moves an f32 result by a few
/// ulps (about 1e-7 relative) and an f64 one by far less; never by a shading or coverage
/// change (a covered pixel moves by far more than 1e-4, an angle AOV at a texel seam by
/// 1e-2 and more).
pub const CROSS_PLATFORM: Tolerance = Tolerance {
    abs: 1e-5,
    rel: 1e-4,
    peak_floor: 0.0,
    flip: Thresholds::DEFAULT,
};

/// For shaded images of the f32 fast path checked off the platform and kernel path that
/// blessed them (on it, every bit must agree: see the module doc): another platform's libm,
/// another instruction set, or a GPU build sums the same terms in another order, and each
/// kernel is held within [`crate::kernel::SH_KERNEL_TOLERANCE`] (relative to the pixel or
/// to 1% of the image's peak) of the scalar oracle. The scalar oracle, another summation
/// order, passes every shaded f32 entry at this tolerance (tests/golden.rs,
/// `the_scalar_oracle_passes_every_shaded_f32_entry`, which prints the share used). The
/// faults of tests/perturbation.rs (half-texel lookup shift, wrong cosine factor, flipped
/// azimuth) move pixels by 1e-2 and more, and tests/golden.rs shows a lookup-mode change,
/// an environment turned by 2 degrees and a 1% pixel change are each caught at it.
pub const KERNEL_DISPATCH: Tolerance = Tolerance {
    abs: 1e-6,
    rel: crate::kernel::SH_KERNEL_TOLERANCE,
    peak_floor: 0.01,
    flip: Thresholds::DEFAULT,
};

/// Every tolerance with its manifest name.
pub const TOLERANCES: [(&str, Tolerance); 2] = [
    ("cross-platform", CROSS_PLATFORM),
    ("kernel-dispatch", KERNEL_DISPATCH),
];

/// Looks up a tolerance by its manifest name.
pub fn tolerance_named(name: &str) -> Option<Tolerance> {
    TOLERANCES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

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

/// The measured difference between an entry's render and its reference render
/// ([`crate::render::render_reference`]: f64, every light of the full probe, no light
/// culling), over all pixels and channels of the linear images.
/// Each value is rounded *up* to three significant digits, so it stays a bound.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Bound {
    /// Largest absolute channel difference (radiance units).
    pub max_abs: f64,
    /// `sqrt(sum (fast - ref)^2 / sum ref^2)`: the error relative to the image's energy.
    pub rel_rmse: f64,
    /// Mean FLIP of the two images' displays (exposure 0, ACES, sRGB).
    pub flip_mean: f64,
}

/// `x` rounded up to three significant digits (0 stays 0).
fn round_up_3(x: f64) -> f64 {
    if !(x > 0.0 && x.is_finite()) {
        return x;
    }
    let text = format!("{x:.2e}");
    let (m, e) = text.split_once('e').expect("exponent form");
    let (m, e): (f64, i32) = (m.parse().expect("mantissa"), e.parse().expect("exponent"));
    let r: f64 = text.parse().expect("number");
    if r >= x {
        r
    } else {
        format!("{:.2}e{e}", m + 0.01).parse().expect("number")
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
    pub fast_vs_reference: Option<Bound>,
    /// [`measure`] at 1/[`BOUND_CHECK_SCALE`] of the entry's size, written by bless and
    /// re-measured by [`check_bounds`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fast_vs_reference_small: Option<Bound>,
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

/// The platform this binary runs on, as recorded in [`Entry::blessed_on`]:
/// `<arch>-<os>` (the libm that the angles, probe directions and f64 path go through comes
/// with the OS).
pub fn platform() -> String {
    format!("{}-{}", std::env::consts::ARCH, std::env::consts::OS)
}

/// Whether an entry's image goes through the f32 shading kernels (a shaded f32 entry), so
/// its bits may depend on the kernel path; debug outputs and the f64 path do not.
pub fn uses_kernel(entry: &Entry, scene: &Scene) -> bool {
    entry.aov.is_none() && scene.render.precision == Precision::F32
}

/// Where an entry is rendered: [`platform`], plus `/<kernel path>` when the image goes
/// through the kernels ([`uses_kernel`]), e.g. `x86_64-linux/avx2`.
pub fn blessing_path(entry: &Entry, scene: &Scene) -> String {
    if uses_kernel(entry, scene) {
        let d = Dispatch::choose(scene.render.kernel).expect("checked by Scene::resolve");
        format!("{}/{}", platform(), d.path().name())
    } else {
        platform()
    }
}

/// Options of [`check`] and [`bless`].
#[derive(Clone, Copy, Debug, Default)]
pub struct CheckOptions {
    /// The kernel path every entry is rendered on (`--kernel`); a path this CPU lacks is
    /// an error.
    pub kernel: KernelPath,
}

/// The outcome of comparing one entry.
#[derive(Debug, Serialize)]
pub struct Outcome {
    pub name: String,
    pub passed: bool,
    pub max_abs_error: f32,
    pub pixels_over_tolerance: usize,
    /// Pixels whose bits differ from the stored image (any channel).
    pub pixels_differing: usize,
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
    let m: Manifest = toml::from_str(text).map_err(|e| {
        let msg = e.message().trim().replace('\n', " ");
        match e.span() {
            Some(span) => {
                let line = text[..span.start].matches('\n').count() + 1;
                format!("line {line}: {msg}")
            }
            None => msg,
        }
    })?;
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

/// Loads and resolves an entry's scene file on the kernel path `kernel`; errors name the
/// scene file.
fn load_scene(dir: &Path, entry: &Entry, kernel: KernelPath) -> Result<(SceneFile, Scene)> {
    let scene_path = dir.join(&entry.scene);
    let mut file = SceneFile::load(&scene_path)?;
    file.render.kernel = kernel;
    let scene = resolve_named(&file, dir, &scene_path)?;
    Ok((file, scene))
}

fn resolve_named(file: &SceneFile, dir: &Path, scene_path: &Path) -> Result<Scene> {
    Scene::resolve(file, dir).map_err(|e| match e {
        Error::Field { .. } => Error::format(scene_path, e.to_string()),
        other => other,
    })
}

/// Renders an entry: its AOV, or its shaded image at the scene's precision (threads: all
/// cores; the result does not depend on it).
pub fn render_entry(dir: &Path, entry: &Entry) -> Result<Image> {
    let (_, scene) = load_scene(dir, entry, KernelPath::Auto)?;
    Ok(render::render(&scene, entry.aov))
}

/// The configuration summary of an entry's scene: mesh, size, material (with its
/// representation, SH bands and lookup), lights, environment sampler, precision, AOV.
pub fn summarize(file: &SceneFile, scene: &Scene, aov: Option<Aov>) -> String {
    let mut parts = vec![format!(
        "{}/{} {}x{}",
        file.mesh.source, file.mesh.segments, scene.render.width, scene.render.height
    )];
    let representation = match scene.material.as_sh() {
        Some(ds) => format!(
            " (SH {} bands, {} lookup)",
            ds.bands(),
            match ds.coeff_lookup {
                Lookup::Nearest => "nearest",
                Lookup::Bilinear => "bilinear",
            }
        ),
        None => match &file.material {
            MaterialSpec::Library { .. } => format!(" ({})", scene.material.name()),
            _ => String::new(),
        },
    };
    let file_name = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    parts.push(match &file.material {
        MaterialSpec::Lambert { .. } => "lambert".to_string(),
        MaterialSpec::BlinnPhong { .. } => "blinn-phong".to_string(),
        MaterialSpec::Library { name, .. } => format!("library {name}{representation}"),
        MaterialSpec::ShFile { path, .. } => format!("sh-file {}{representation}", file_name(path)),
        MaterialSpec::DbrdfFile { path } => format!("dbrdf-file {}", file_name(path)),
    });
    let specs = match (&file.lights, &file.env) {
        (Some(l), _) => l.clone(),
        (None, Some(_)) => Vec::new(),
        (None, None) => crate::scene::default_lights(),
    };
    let count = |point: bool| {
        specs
            .iter()
            .filter(|l| matches!(l, LightSpec::Point { .. }) == point)
            .count()
    };
    for (n, kind) in [(count(true), "point"), (count(false), "directional")] {
        if n > 0 {
            parts.push(format!("{n} {kind}"));
        }
    }
    if let Some(env) = &file.env {
        use clap::ValueEnum;
        let sampler = env
            .sampler
            .to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default();
        let lights = scene.env.as_ref().map_or(0, |e| e.lights);
        parts.push(match env.sampler {
            SamplerKind::Full => format!("env {} full ({lights} lights)", file_name(&env.file)),
            _ => format!("env {} {sampler} {lights}", file_name(&env.file)),
        });
    }
    if scene.render.cull == crate::raster::Cull::Back {
        parts.push("back-face culling".into());
    }
    parts.push(match aov {
        Some(a) => {
            use clap::ValueEnum;
            format!(
                "aov {}",
                a.to_possible_value()
                    .map(|v| v.get_name().to_string())
                    .unwrap_or_default()
            )
        }
        None => match scene.render.precision {
            Precision::F32 => "f32".into(),
            Precision::F64 => "f64".into(),
        },
    });
    parts.join(", ")
}

/// Divisor of the width and height at which [`check_bounds`] re-measures the
/// fast-vs-reference bound: an environment entry's reference shades every probe texel
/// (131,072 lights for a 512x256 probe) at every pixel, about a minute at 64x48 on two
/// cores, a few seconds at 1/4 of each side.
pub const BOUND_CHECK_SCALE: u32 = 4;

/// How far a re-measured bound may exceed the stored one: `stored * (1 + rel) + abs` per
/// metric. On the platform that blessed the set both sides are deterministic and the
/// measurement repeats exactly; the margin admits another platform's rounding (another
/// libm moves light directions by ulps, which moves a sampler's error by far less than
/// 10%), not a change of the light set or of either render path.
pub const BOUND_MARGIN: (f64, f64) = (0.1, 1e-6);

/// Measures the fast path against the converged reference on an entry's scene, with both
/// images at 1/`scale` of the entry's width and height (at least 1 pixel each): the fast
/// side is the f32 kernel render of the scene (for an f64 entry too, so it is never its own
/// reference), the reference the same scene with the environment (if any) as the full
/// probe, through [`render::render_reference`] (f64, every light, no culling). `None` for
/// debug outputs (nothing is shaded). Slow with an environment at full size (every probe
/// texel is a light).
pub fn measure(dir: &Path, entry: &Entry, scale: u32) -> Result<Option<Bound>> {
    if entry.aov.is_some() {
        return Ok(None);
    }
    let scene_path = dir.join(&entry.scene);
    let mut file = SceneFile::load(&scene_path)?;
    file.render.width = (file.render.width / scale.max(1)).max(1);
    file.render.height = (file.render.height / scale.max(1)).max(1);
    file.render.precision = Precision::F32;
    let fast = render::render(&resolve_named(&file, dir, &scene_path)?, None);
    if let Some(env) = file.env.as_mut() {
        env.sampler = SamplerKind::Full;
    }
    let scene = resolve_named(&file, dir, &scene_path)?;
    let reference = render::render_reference(&scene);
    Ok(Some(bound(&fast, &reference)?))
}

/// Whether a re-measured bound stays within the stored one ([`BOUND_MARGIN`]), per metric.
pub fn within_bound(measured: &Bound, stored: &Bound) -> bool {
    let (rel, abs) = BOUND_MARGIN;
    let ok = |m: f64, s: f64| m <= s * (1.0 + rel) + abs;
    ok(measured.max_abs, stored.max_abs)
        && ok(measured.rel_rmse, stored.rel_rmse)
        && ok(measured.flip_mean, stored.flip_mean)
}

/// The outcome of re-measuring one entry's small fast-vs-reference bound.
#[derive(Debug, Serialize)]
pub struct BoundOutcome {
    pub name: String,
    pub passed: bool,
    pub stored: Bound,
    pub measured: Bound,
}

/// Re-measures [`Entry::fast_vs_reference_small`] of the named shaded entries (all if
/// `names` is empty; debug outputs have none) at 1/[`BOUND_CHECK_SCALE`] of their size and
/// holds each to the stored bound within [`BOUND_MARGIN`]. A shaded entry without a stored
/// small bound is an error (run `golden bless`).
pub fn check_bounds(dir: &Path, names: &[String]) -> Result<Vec<BoundOutcome>> {
    let manifest = load_manifest(dir)?;
    for n in names {
        Entry::find(&manifest, &manifest_path(dir), n)?;
    }
    let mut out = Vec::new();
    for entry in &manifest.entries {
        if entry.aov.is_some() || (!names.is_empty() && !names.contains(&entry.name)) {
            continue;
        }
        let Some(stored) = entry.fast_vs_reference_small else {
            return Err(Error::format(
                manifest_path(dir),
                format!(
                    "entry '{}' has no fast_vs_reference_small: run `brdfkit golden bless {}`",
                    entry.name, entry.name
                ),
            ));
        };
        let measured = measure(dir, entry, BOUND_CHECK_SCALE)?.expect("a shaded entry");
        out.push(BoundOutcome {
            name: entry.name.clone(),
            passed: within_bound(&measured, &stored),
            stored,
            measured,
        });
    }
    Ok(out)
}

/// The [`Bound`] between two images of one size (a size difference is an error).
pub fn bound(fast: &Image, reference: &Image) -> Result<Bound> {
    let (mut max_abs, mut num, mut den) = (0.0f32, 0.0f64, 0.0f64);
    for (f, r) in fast.pixels.iter().zip(&reference.pixels) {
        let d = *f - *r;
        max_abs = max_abs.max(d.abs().max_element());
        num += d.as_dvec3().length_squared();
        den += r.as_dvec3().length_squared();
    }
    let (m, _) = compare::compare(
        &Loaded::from_linear(reference.clone()),
        &Loaded::from_linear(fast.clone()),
        &Thresholds::DEFAULT,
    )?;
    Ok(Bound {
        max_abs: round_up_3(max_abs as f64),
        rel_rmse: round_up_3(if den > 0.0 { (num / den).sqrt() } else { 0.0 }),
        flip_mean: round_up_3(m.flip_mean as f64),
    })
}

/// Compares two images with a tolerance: `(largest absolute error, pixels over the
/// tolerance)`; `None` if their sizes differ. A NaN in either image fails its pixel.
pub fn compare(expected: &Image, actual: &Image, tol: Tolerance) -> Option<(f32, usize)> {
    if expected.width != actual.width || expected.height != actual.height {
        return None;
    }
    let peak = expected
        .pixels
        .iter()
        .map(|p| p.abs().max_element())
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    let floor = Vec3::splat(tol.peak_floor * peak);
    let mut max_abs = 0.0f32;
    let mut over = 0;
    for (e, a) in expected.pixels.iter().zip(&actual.pixels) {
        let d = (*a - *e).abs();
        let lim = Vec3::splat(tol.abs) + e.abs().max(floor) * tol.rel;
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

/// Judges one entry's render `actual` against its stored image `expected` (whose content
/// hash is `expected_hash`): identical bits when `rendered_on` is the entry's
/// [`Entry::blessed_on`], else the entry's tolerance; `config` is the summary of the scene
/// as it resolves now (a stale manifest fails).
pub fn judge(
    entry: &Entry,
    expected: &Image,
    expected_hash: &str,
    actual: &Image,
    config: &str,
    rendered_on: &str,
) -> Outcome {
    let tol = tolerance_named(&entry.tolerance).expect("checked by parse_manifest");
    let hash_ok = entry.hash == expected_hash;
    let exact = !entry.blessed_on.is_empty() && entry.blessed_on == rendered_on;
    let Some((max_abs, over)) = compare(expected, actual, tol) else {
        return Outcome {
            name: entry.name.clone(),
            passed: false,
            max_abs_error: f32::INFINITY,
            pixels_over_tolerance: usize::MAX,
            pixels_differing: usize::MAX,
            message: format!(
                "size differs: golden {}x{}, render {}x{}",
                expected.width, expected.height, actual.width, actual.height
            ),
        };
    };
    let differing = expected
        .pixels
        .iter()
        .zip(&actual.pixels)
        .filter(|(e, a)| e.to_array().map(f32::to_bits) != a.to_array().map(f32::to_bits))
        .count();
    let fail = |max_abs_error, pixels_over_tolerance, message| Outcome {
        name: entry.name.clone(),
        passed: false,
        max_abs_error,
        pixels_over_tolerance,
        pixels_differing: differing,
        message,
    };
    if exact && differing > 0 {
        return fail(
            max_abs,
            over,
            format!(
                "{differing} pixels differ from the stored bits on the path that blessed them \
                 ({rendered_on}; max abs error {max_abs:e})"
            ),
        );
    }
    if over > 0 {
        return fail(
            max_abs,
            over,
            format!(
                "{over} pixels over tolerance '{}' (max abs error {max_abs:e}; blessed on {}, \
                 rendered on {rendered_on})",
                entry.tolerance, entry.blessed_on
            ),
        );
    }
    if !hash_ok {
        return fail(
            max_abs,
            over,
            format!(
                "{}.exr does not match its manifest hash: edited outside `golden bless`?",
                entry.name
            ),
        );
    }
    if config != entry.config {
        return fail(
            max_abs,
            over,
            format!(
                "manifest config is stale (scene now gives '{config}'): run `brdfkit golden bless {}`",
                entry.name
            ),
        );
    }
    Outcome {
        name: entry.name.clone(),
        passed: true,
        max_abs_error: max_abs,
        pixels_over_tolerance: 0,
        pixels_differing: differing,
        message: if exact {
            format!("ok (identical bits, {rendered_on})")
        } else {
            format!(
                "ok (tolerance '{}': blessed on {}, rendered on {rendered_on}, {differing} pixels differ)",
                entry.tolerance, entry.blessed_on
            )
        },
    }
}

/// Checks the named entries of `dir` (all if `names` is empty; an unknown name is an
/// error): re-renders each on `opts.kernel`, and judges it against its stored EXR
/// ([`judge`]: identical bits on the path that blessed it, its tolerance elsewhere), the
/// stored EXR's hash and the manifest's configuration summary. Failures leave
/// `<name>.png` (expected | difference | actual) and `<name>.json` in `report_dir`.
/// Never writes under `dir`.
pub fn check(
    dir: &Path,
    report_dir: &Path,
    names: &[String],
    opts: &CheckOptions,
) -> Result<Vec<Outcome>> {
    let manifest = load_manifest(dir)?;
    for n in names {
        Entry::find(&manifest, &manifest_path(dir), n)?;
    }
    let mut out = Vec::new();
    for entry in &manifest.entries {
        if !names.is_empty() && !names.contains(&entry.name) {
            continue;
        }
        let image_path = dir.join(format!("{}.exr", entry.name));
        let expected = image_io::read_exr(&image_path)?;
        let (file, scene) = load_scene(dir, entry, opts.kernel)?;
        let actual = render::render(&scene, entry.aov);
        let config = summarize(&file, &scene, entry.aov);
        let outcome = judge(
            entry,
            &expected,
            &content_hash(&expected),
            &actual,
            &config,
            &blessing_path(entry, &scene),
        );
        if !outcome.passed {
            write_report(report_dir, &outcome, &expected, &actual)?;
        }
        out.push(outcome);
    }
    Ok(out)
}

/// Writes a failed entry's `expected | difference | actual` PNG and JSON report.
fn write_report(
    report_dir: &Path,
    outcome: &Outcome,
    expected: &Image,
    actual: &Image,
) -> Result<()> {
    std::fs::create_dir_all(report_dir)
        .map_err(|e| Error::io(report_dir, "cannot create report directory", e))?;
    write_triptych(
        &report_dir.join(format!("{}.png", outcome.name)),
        expected,
        actual,
    )?;
    let json = serde_json::to_string_pretty(outcome).expect("serialisable");
    let jp = report_dir.join(format!("{}.json", outcome.name));
    image_io::write_atomically(&jp, |tmp| {
        std::fs::write(tmp, &json).map_err(|e| Error::io(&jp, "cannot write report", e))
    })
}

/// Re-renders and rewrites the named entries (all if `names` is empty): EXR, PNG preview
/// (AOVs in their linear encoding, [`crate::aov::png_bytes`]), hash, configuration summary
/// the platform and kernel path ([`Entry::blessed_on`]) and the measured fast-vs-reference
/// bounds ([`measure`], full size and 1/[`BOUND_CHECK_SCALE`]); then the manifest and the
/// table in `README.md` ([`readme_table`]). Every entry is rendered before anything is
/// written, so a failing entry leaves golden/ as it was.
pub fn bless(dir: &Path, names: &[String], opts: &CheckOptions) -> Result<Vec<PathBuf>> {
    let mut manifest = load_manifest(dir)?;
    for n in names {
        Entry::find(&manifest, &manifest_path(dir), n)?;
    }
    let mut rendered = Vec::new();
    for (i, entry) in manifest.entries.iter_mut().enumerate() {
        if !names.is_empty() && !names.contains(&entry.name) {
            continue;
        }
        let (file, scene) = load_scene(dir, entry, opts.kernel)?;
        let img = render::render(&scene, entry.aov);
        entry.config = summarize(&file, &scene, entry.aov);
        entry.blessed_on = blessing_path(entry, &scene);
        entry.fast_vs_reference = measure(dir, entry, 1)?;
        entry.fast_vs_reference_small = measure(dir, entry, BOUND_CHECK_SCALE)?;
        rendered.push((i, img));
    }
    let mut written = Vec::new();
    for (i, img) in rendered {
        let entry = &mut manifest.entries[i];
        let path = dir.join(format!("{}.exr", entry.name));
        image_io::write_exr(&path, &img)?;
        let png = dir.join(format!("{}.png", entry.name));
        match entry.aov {
            None => image_io::write_png(&png, &img, 0.0, image_io::Tonemap::Aces)?,
            Some(a) => image_io::write_png_bytes(
                &png,
                img.width,
                img.height,
                crate::aov::png_bytes(&img, a),
            )?,
        }
        entry.hash = content_hash(&image_io::read_exr(&path)?);
        written.push(path);
    }
    let mpath = manifest_path(dir);
    let text = format!(
        "# Golden images: see README.md. config, hash, blessed_on and fast_vs_reference(_small)\n\
         # are written by `brdfkit golden bless`; everything else by hand.\n\n{}",
        toml::to_string_pretty(&manifest).expect("serialisable")
    );
    image_io::write_atomically(&mpath, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| Error::io(&mpath, "cannot write manifest", e))
    })?;
    let readme = dir.join("README.md");
    if let Ok(old) = std::fs::read_to_string(&readme) {
        if let Some(new) = with_readme_table(&old, &manifest) {
            image_io::write_atomically(&readme, |tmp| {
                std::fs::write(tmp, &new).map_err(|e| Error::io(&readme, "cannot write", e))
            })?;
        }
    }
    Ok(written)
}

/// Marks the start of the generated table in golden/README.md.
pub const README_BEGIN: &str = "<!-- golden-table: generated by `brdfkit golden bless` -->";
/// Marks its end.
pub const README_END: &str = "<!-- golden-table end -->";

/// The Markdown table of the set: entry, thesis figure, configuration, tolerance, measured
/// fast-vs-reference bound, what it shows.
pub fn readme_table(manifest: &Manifest) -> String {
    let mut t = String::from(
        "| entry | figure | configuration | tolerance | fast vs reference: max abs / rel RMSE / FLIP mean | shows |\n\
         |---|---|---|---|---|---|\n",
    );
    for e in &manifest.entries {
        let bound = match e.fast_vs_reference {
            Some(b) => format!(
                "{:.2e} / {:.2e} / {:.4}",
                b.max_abs, b.rel_rmse, b.flip_mean
            ),
            None => "n/a (debug output)".into(),
        };
        let fig = if e.figure.is_empty() { "-" } else { &e.figure };
        t += &format!(
            "| `{}` | {} | {} | `{}` | {} | {} |\n",
            e.name, fig, e.config, e.tolerance, bound, e.shows
        );
    }
    t
}

/// `readme` with the text between [`README_BEGIN`] and [`README_END`] replaced by
/// [`readme_table`]; `None` when the markers are missing.
pub fn with_readme_table(readme: &str, manifest: &Manifest) -> Option<String> {
    let a = readme.find(README_BEGIN)? + README_BEGIN.len();
    let b = readme[a..].find(README_END)? + a;
    Some(format!(
        "{}\n\n{}\n{}",
        &readme[..a],
        readme_table(manifest),
        &readme[b..]
    ))
}
