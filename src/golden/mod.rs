//! The golden-image oracle: reference renders stored in `golden/`, re-rendered and compared.
//!
//! (Past 400 lines because it holds the oracle's contract: the entry rendering, the
//! judgement and the bless that are the only writers of `golden/`, in one place with the
//! design rule; manifests, bounds, reports and shards are submodules.)
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
//! hash = "xxh3-64:..."        # of the EXR's pixel values
//! blessed_on = "x86_64-linux-glibc2.36/avx2"   # the platform (libm included) and kernel path
//! fast_vs_reference = { max_abs = .., rel_rmse = .., flip_mean = .. }   # see [`MeasuredBound`]
//! fast_vs_reference_small = { .. }   # the same at 1/BOUND_CHECK_SCALE of the size
//! ```
//!
//! The check re-renders each entry and compares it with its stored render. On the
//! platform and kernel path that blessed the entry ([`Entry::blessed_on`], [`blessing_path`])
//! every bit must agree: the render is deterministic there, so any change at all (a
//! constant off by 0.05%, one texel, one dropped light) fails. On another platform or path
//! the entry's tolerance applies. The two kernel paths give the same bits by construction
//! ([`crate::lanes`]), which `tests/integration/golden.rs` checks over the whole set, so in
//! practice the tolerance serves only other platforms (another libm, another instruction
//! set) and GPU builds.
//!
//! The slow reference render ([`measure`]) is run by `bless`, which records the measured
//! fast-vs-reference bound at full size and at 1/[`BOUND_CHECK_SCALE`] of it; `golden check
//! --bounds` ([`check_bounds`]) re-measures the small one and holds it to the stored value
//! within [`BOUND_MARGIN`], so a change of the sampler, the reference path or the light
//! set that makes the fast path drift from the converged reference is caught in CI.

mod bounds;
mod gpu_bounds;
#[cfg(feature = "gpu")]
mod gpu_check;
mod list;
mod manifest;
mod report;
pub mod shard;
mod summary;
mod tolerance;

pub use bounds::*;
pub use gpu_bounds::*;
#[cfg(feature = "gpu")]
pub use gpu_check::*;
pub use list::*;
pub use manifest::*;
pub use report::*;
pub use summary::*;
pub use tolerance::*;

use crate::aov::Aov;
use crate::compare::{self, Loaded, RadiometricBounds, Thresholds};
use crate::error::{Error, Result};
use crate::image_io::{self, Image};
use crate::lanes::{Dispatch, KernelPath};
use crate::render::{self, RenderOptions};
use crate::scene::{LightSpec, MaterialSpec, Precision, Scene, SceneFile};
use crate::sh::dataset::Lookup;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The platform this binary runs on, as recorded in [`Entry::blessed_on`]:
/// `<arch>-<os>-<libm>`, e.g. `x86_64-linux-glibc2.36`. The libm is part of the key because
/// bits that pass through it (`powf`, `exp`, the camera's and the probe directions'
/// trigonometry, the f64 path) may differ between C library versions on the same
/// architecture and OS: glibc names its version ([`libm`]), so exactness is promised only
/// where the blessing's C library is the one running; elsewhere the entry's tolerance
/// applies.
pub fn platform() -> String {
    format!(
        "{}-{}-{}",
        std::env::consts::ARCH,
        std::env::consts::OS,
        libm()
    )
}

/// The C library whose libm this binary calls: `glibc<version>` from
/// `gnu_get_libc_version` on GNU targets (the library loaded at run time, not the one
/// linked against), else the target's C library name (`musl`, `msvc`, ...) or `libc`
/// where the target names none. Never fails.
pub fn libm() -> String {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: gnu_get_libc_version returns a pointer to a static NUL-terminated string.
        let v = unsafe { std::ffi::CStr::from_ptr(libc::gnu_get_libc_version()) };
        format!("glibc{}", v.to_string_lossy())
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        let env = if cfg!(target_env = "musl") {
            "musl"
        } else if cfg!(target_env = "msvc") {
            "msvc"
        } else {
            "libc"
        };
        env.to_string()
    }
}

/// The platform part of a [`blessing_path`] (`x86_64-linux-glibc2.36/avx2` ->
/// `x86_64-linux-glibc2.36`): where the check demands identical bits, whatever the kernel
/// path.
pub fn platform_of(blessing_path: &str) -> &str {
    blessing_path.split('/').next().unwrap_or("")
}

/// Whether `entry` was blessed on the platform this binary runs on ([`platform`]), where
/// [`judge`] demands identical bits.
pub fn blessed_here(entry: &Entry) -> bool {
    platform_of(&entry.blessed_on) == platform()
}

/// Whether an entry's image goes through the f32 shading kernels (a shaded f32 entry), so
/// its bits may depend on the kernel path; debug outputs and the f64 path do not.
pub fn uses_kernel(entry: &Entry, scene: &Scene) -> bool {
    entry.aov.is_none() && scene.render.precision == Precision::F32
}

/// Where an entry is rendered: [`platform`], plus `/<kernel path>` when the image goes
/// through the kernels ([`uses_kernel`]), e.g. `x86_64-linux-glibc2.36/avx2`.
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
#[derive(Debug, Serialize, Deserialize)]
pub struct Outcome {
    pub name: String,
    pub passed: bool,
    pub max_abs_error: f32,
    pub pixels_over_tolerance: usize,
    /// Pixels whose bits differ from the stored image (any channel).
    pub pixels_differing: usize,
    pub message: String,
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

pub(crate) fn resolve_named(file: &SceneFile, dir: &Path, scene_path: &Path) -> Result<Scene> {
    Scene::resolve(file, dir).map_err(|e| match e {
        Error::Field { .. } => Error::format(scene_path, e.to_string()),
        other => other,
    })
}

/// Renders `scene` as a golden entry does: its AOV `aov`, or the shaded image at the
/// scene's precision and kernel (the default [`RenderOptions`]).
fn render_aov(scene: &Scene, aov: Option<Aov>) -> Image {
    render::render(
        scene,
        &RenderOptions {
            aov,
            ..RenderOptions::default()
        },
    )
    .image
}

/// Renders an entry: its AOV, or its shaded image at the scene's precision (threads: all
/// cores; the result does not depend on it).
pub fn render_entry(dir: &Path, entry: &Entry) -> Result<Image> {
    let (_, scene) = load_scene(dir, entry, KernelPath::Auto)?;
    Ok(render_aov(&scene, entry.aov))
}

/// Judges one entry's render `actual` against its stored image `expected` (whose content
/// hash is `expected_hash`): identical bits when `rendered_on` is on the platform of the
/// entry's [`Entry::blessed_on`] (any kernel path), else the entry's tolerance; `config` is the summary of the scene
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
    // Exact on the blessing platform whatever the kernel path: the paths (portable, avx2,
    // avx512) are built to give identical bits, and tests/integration/golden.rs demands it of each.
    let exact =
        !entry.blessed_on.is_empty() && platform_of(&entry.blessed_on) == platform_of(rendered_on);
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
        let actual = render_aov(&scene, entry.aov);
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

/// Re-renders and rewrites the named entries (all if `names` is empty): EXR, PNG preview
/// (AOVs in their linear encoding, [`crate::aov::png_bytes`]), hash, configuration summary
/// the platform and kernel path ([`Entry::blessed_on`]) and the measured fast-vs-reference
/// bounds ([`measure`], full size and 1/[`BOUND_CHECK_SCALE`]); then the manifest and the
/// table in the directory's `README.md` ([`readme_table`]). Every entry is rendered before
/// anything is written, so a failing entry leaves golden/ as it was.
pub fn bless(dir: &Path, names: &[String], opts: &CheckOptions) -> Result<Vec<PathBuf>> {
    let (manifest, written) = bless_images(dir, names, opts)?;
    write_manifest(dir, &manifest)?;
    Ok(written)
}

/// [`bless`] without writing the manifest and README: the named entries' images written,
/// and the manifest as it will be with their records updated (the sharded bless,
/// `shard.rs`, writes only its own entries' records).
pub fn bless_images(
    dir: &Path,
    names: &[String],
    opts: &CheckOptions,
) -> Result<(Manifest, Vec<PathBuf>)> {
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
        let img = render_aov(&scene, entry.aov);
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
    Ok((manifest, written))
}

/// Writes `manifest` to `dir`'s manifest.toml (with its header comment) and the table of
/// `dir`'s README.md, each atomically.
pub fn write_manifest(dir: &Path, manifest: &Manifest) -> Result<()> {
    let mpath = manifest_path(dir);
    let text = format!(
        "# Golden images: see README.md. config, hash, blessed_on and fast_vs_reference(_small)\n\
         # are written by `brdfkit golden bless`; everything else by hand.\n\n{}",
        toml::to_string_pretty(manifest).expect("serialisable")
    );
    image_io::write_atomically(&mpath, |tmp| {
        std::fs::write(tmp, &text).map_err(|e| Error::io(&mpath, "cannot write manifest", e))
    })?;
    let readme = dir.join("README.md");
    if let Ok(old) = std::fs::read_to_string(&readme) {
        if let Some(new) = with_readme_table(&old, manifest) {
            image_io::write_atomically(&readme, |tmp| {
                std::fs::write(tmp, &new).map_err(|e| Error::io(&readme, "cannot write", e))
            })?;
        }
    }
    Ok(())
}
