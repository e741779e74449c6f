//! Image comparison: the measurements `brdfkit compare` reports and the pass/fail rule a
//! GPU build's CI relies on. The pixel measures are [`crate::metrics`]'s; FLIP is here.
//!
//! Design rule: like is compared with like. Two EXR files are compared as linear floats;
//! two PNG files as their 8-bit sRGB values scaled to [0, 1]. A size, colour-layout
//! (RGB against L) or kind mismatch is *unusable input*, never a silent conversion. An
//! alpha channel (RGBA EXR or PNG, what most GPU read-backs produce) is ignored by default
//! ([`AlphaMode::Ignore`]): RGBA is compared with RGB on its colour channels, never
//! premultiplied. [`AlphaMode::Compare`] compares it as a fourth channel, an image without
//! one counting as opaque (alpha 1). FLIP (NVIDIA's perceptual
//! difference, through the `nv-flip` crate) is computed on what a person sees: PNGs as they
//! are, EXRs after [`crate::image_io::display_u8`] (exposure 0, ACES, sRGB).
//!
//! Thresholds follow wgpu's image tests: a FLIP mean and a FLIP value at a high percentile,
//! each with a reason (see [`Thresholds::DEFAULT`]).

mod alpha;

pub use alpha::AlphaMetrics;

use crate::error::{Error, Result};
use crate::image_io::{self, Image, Tonemap};
use glam::Vec3;
use std::path::Path;

/// What kind of file an image came from, with its channel layout.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// "EXR" or "PNG".
    pub kind: &'static str,
    /// Channel names, e.g. "RGB", "RGBA", "L".
    pub channels: String,
}

impl Layout {
    /// The colour channels without a trailing alpha: "RGB" for "RGB" and "RGBA", "L" for
    /// "L" and "LA".
    pub fn colour(&self) -> &str {
        self.channels
            .strip_suffix('A')
            .filter(|c| !c.is_empty())
            .unwrap_or(&self.channels)
    }
}

/// What `compare` does with an alpha channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum AlphaMode {
    /// Colour channels only; an RGBA image compares with an RGB one.
    #[default]
    Ignore,
    /// Alpha as a fourth channel (an image without alpha counts as opaque, alpha 1): its
    /// largest absolute difference is reported, and its FLIP (alpha as a grey image,
    /// 8-bit, no tone map) must pass the same bounds as the colour's.
    Compare,
}

/// A loaded image for comparison: RGB values (linear for EXR, encoded/255 for PNG) and,
/// for FLIP, 8-bit display bytes.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub image: Image,
    pub display: Vec<u8>,
    pub layout: Layout,
    /// Alpha per pixel (row-major; linear for EXR, value/255 for PNG), when the file has
    /// an alpha channel.
    pub alpha: Option<Vec<f32>>,
}

impl Loaded {
    /// A linear image as if loaded from an EXR (display bytes through the same encoding).
    pub fn from_linear(image: Image) -> Loaded {
        let display = image
            .pixels
            .iter()
            .flat_map(|p| {
                p.to_array()
                    .map(|c| image_io::display_u8(c, 0.0, Tonemap::Aces))
            })
            .collect();
        Loaded {
            image,
            display,
            layout: Layout {
                kind: "EXR",
                channels: "RGB".into(),
            },
            alpha: None,
        }
    }
}

/// Largest image side accepted for comparison.
pub const MAX_SIDE: u32 = 1 << 15;

/// Bytes a PNG's decoder may allocate per byte of file (deflate's worst ratio, 1032:1,
/// rounded up).
pub const PNG_MAX_EXPANSION: u64 = 1100;
/// Bytes a PNG's decoder may allocate whatever the file's length.
pub const PNG_ALLOC_SLACK: u64 = 16 << 20;

/// Loads an EXR (R, G, B, optional A) or PNG (any 8/16-bit colour type, alpha kept in
/// [`Loaded::alpha`]). Errors name the
/// file: not a regular file or over [`crate::image_io::MAX_EXR_FILE_BYTES`], unreadable, unknown extension, undecodable or truncated, over [`MAX_SIDE`] per
/// side, missing R/G/B (EXR), or a PNG whose declared size needs more memory than
/// [`PNG_MAX_EXPANSION`] x its length + [`PNG_ALLOC_SLACK`].
pub fn load(path: &Path) -> Result<Loaded> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if matches!(ext.as_deref(), Some("exr" | "png")) {
        crate::image_io::check_regular_file(path, crate::image_io::MAX_EXR_FILE_BYTES, "image")?;
    }
    match ext.as_deref() {
        Some("exr") => {
            let meta = exr::meta::MetaData::read_from_file(path, false)
                .map_err(|e| Error::format(path, format!("cannot read EXR: {e}")))?;
            let header = meta
                .headers
                .first()
                .ok_or_else(|| Error::format(path, "EXR has no layers"))?;
            let names: Vec<String> = header
                .channels
                .list
                .iter()
                .map(|c| c.name.to_string())
                .collect();
            let size = header.layer_size;
            if size.0 as u64 > MAX_SIDE as u64 || size.1 as u64 > MAX_SIDE as u64 {
                return Err(Error::format(
                    path,
                    format!(
                        "EXR is {}x{}, larger than {MAX_SIDE} per side",
                        size.0, size.1
                    ),
                ));
            }
            for c in ["R", "G", "B"] {
                if !names.iter().any(|n| n == c) {
                    return Err(Error::format(
                        path,
                        format!("EXR has channels {names:?}: an R, G and B channel are needed"),
                    ));
                }
            }
            let has_alpha = names.iter().any(|n| n == "A");
            let (image, alpha) = image_io::read_exr_rgba(path)?;
            let mut loaded = Loaded::from_linear(image);
            if has_alpha {
                loaded.layout.channels = "RGBA".into();
                loaded.alpha = Some(alpha);
            }
            Ok(loaded)
        }
        Some("png") => {
            let reader = image::ImageReader::open(path)
                .map_err(|e| Error::io(path, "cannot read PNG", e))?;
            let mut reader = reader
                .with_guessed_format()
                .map_err(|e| Error::io(path, "cannot read PNG", e))?;
            let mut limits = image::Limits::default();
            // Decoded bytes are bounded by what the file's length can hold (deflate expands
            // at most 1032:1) plus a fixed slack, before the decoder allocates.
            let file_len = std::fs::metadata(path)
                .map_err(|e| Error::io(path, "cannot read PNG", e))?
                .len();
            limits.max_alloc = Some(
                file_len
                    .saturating_mul(PNG_MAX_EXPANSION)
                    .saturating_add(PNG_ALLOC_SLACK),
            );
            limits.max_image_width = Some(MAX_SIDE);
            limits.max_image_height = Some(MAX_SIDE);
            reader.limits(limits);
            let img = reader
                .decode()
                .map_err(|e| Error::format(path, format!("cannot decode PNG: {e}")))?;
            let channels = match img.color() {
                image::ColorType::L8 | image::ColorType::L16 => "L",
                image::ColorType::La8 | image::ColorType::La16 => "LA",
                image::ColorType::Rgb8 | image::ColorType::Rgb16 => "RGB",
                image::ColorType::Rgba8 | image::ColorType::Rgba16 => "RGBA",
                _ => "other",
            }
            .to_string();
            let alpha = img.color().has_alpha().then(|| {
                img.to_rgba8()
                    .pixels()
                    .map(|p| p[3] as f32 / 255.0)
                    .collect()
            });
            let rgb = img.to_rgb8();
            let (w, h) = rgb.dimensions();
            let display = rgb.into_raw();
            let pixels = display
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0)
                .collect();
            Ok(Loaded {
                image: Image {
                    width: w,
                    height: h,
                    pixels,
                },
                display,
                layout: Layout {
                    kind: "PNG",
                    channels,
                },
                alpha,
            })
        }
        _ => Err(Error::format(
            path,
            "unknown image format: compare reads .exr and .png",
        )),
    }
}

/// Pass thresholds: FLIP mean and the FLIP value at a percentile (both in [0, 1]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    pub flip_mean: f32,
    /// Percentile in (0, 1), e.g. 0.99.
    pub percentile: f32,
    pub flip_at_percentile: f32,
}

impl Thresholds {
    /// Defaults for a GPU build against this oracle, from tests/integration/perturbation.rs
    /// (blue silk and a 45-degree-turned anisotropic lobe, 160x120, city probe, 64 median-cut
    /// lights + a key light). Measured FLIP mean / 99th percentile of the seeded faults:
    /// half-texel lookup shift 0.032 / 0.36, wrong cosine factor 0.080 / 0.60, flipped azimuth
    /// 0.109 / 0.96; the unperturbed render 0 / 0, and our own f32 kernel against the scalar
    /// oracle differs by at most 1.3e-4 relative, which does not change an 8-bit display
    /// value. The mean bound (0.01) sits at a third of the smallest fault's mean, leaving room
    /// for a GPU port's legitimate differences (8-bit sub-texel filtering weights, fp32
    /// evaluation order; not measured here: this machine has no GPU). The 99th-percentile
    /// bound (0.1) keeps a small bad region (a seam, a few hundred wrong pixels) from hiding
    /// in a good mean; a one-pixel shift of the whole image fails it
    /// (tests/integration/compare.rs).
    pub const DEFAULT: Thresholds = Thresholds {
        flip_mean: 0.01,
        percentile: 0.99,
        flip_at_percentile: 0.1,
    };
}

/// The measurements of one comparison: the pixel differences of
/// [`crate::metrics::differences`] (see [`crate::metrics::Differences`] for each
/// definition) and the FLIP statistics.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Metrics {
    pub width: u32,
    pub height: u32,
    /// Largest absolute channel difference.
    pub max_abs: f32,
    /// Largest relative channel difference `|a - b| / max(|a|, 1e-3)`.
    pub max_rel: f32,
    /// Root mean square channel difference.
    pub rmse: f64,
    /// PSNR in dB against a peak of max(1, largest reference value); infinite if equal.
    pub psnr: f64,
    pub flip_mean: f32,
    /// FLIP at the 95th, 99th and 99.9th percentiles.
    pub flip_p95: f32,
    pub flip_p99: f32,
    pub flip_p999: f32,
    /// FLIP at the threshold's percentile.
    pub flip_at_percentile: f32,
    /// Pixels whose largest channel difference is non-zero.
    pub differing_pixels: usize,
    /// Histogram of the per-pixel largest absolute difference: `(upper bound, count)`,
    /// the first bucket holding exact zeros.
    pub histogram: Vec<(f32, usize)>,
    /// NaN or infinite values in either image.
    pub non_finite: usize,
    /// The alpha channel's measures under [`AlphaMode::Compare`].
    pub alpha: Option<AlphaMetrics>,
}

/// FLIP of `expected` against `actual` (8-bit RGB display bytes): the per-pixel error
/// and its pool.
fn flip_of(w: u32, h: u32, expected: &[u8], actual: &[u8]) -> (Vec<f32>, nv_flip::FlipPool) {
    let fe = nv_flip::FlipImageRgb8::with_data(w, h, expected);
    let fa = nv_flip::FlipImageRgb8::with_data(w, h, actual);
    let err = nv_flip::flip(fe, fa, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let pool = nv_flip::FlipPool::from_image(&err);
    (err.to_vec(), pool)
}

/// Compares `expected` with `actual` on their colour channels ([`AlphaMode::Ignore`]).
/// Fails (unusable input) when sizes, kinds or colour layouts differ.
pub fn compare(expected: &Loaded, actual: &Loaded, th: &Thresholds) -> Result<(Metrics, Vec<f32>)> {
    compare_with_alpha(expected, actual, th, AlphaMode::Ignore)
}

/// [`compare`], with the alpha channel ignored or compared ([`AlphaMode`]).
pub fn compare_with_alpha(
    expected: &Loaded,
    actual: &Loaded,
    th: &Thresholds,
    alpha: AlphaMode,
) -> Result<(Metrics, Vec<f32>)> {
    let (e, a) = (&expected.image, &actual.image);
    if (e.width, e.height) != (a.width, a.height) {
        return Err(Error::field(
            "images",
            format!(
                "sizes differ: expected {}x{}, actual {}x{}",
                e.width, e.height, a.width, a.height
            ),
        ));
    }
    if expected.layout.kind != actual.layout.kind
        || expected.layout.colour() != actual.layout.colour()
    {
        return Err(Error::field(
            "images",
            format!(
                "channel layouts differ: expected {} {}, actual {} {}",
                expected.layout.kind,
                expected.layout.channels,
                actual.layout.kind,
                actual.layout.channels
            ),
        ));
    }
    let d = crate::metrics::differences(e, a);
    let (flip, mut pool) = flip_of(e.width, e.height, &expected.display, &actual.display);
    let metrics = Metrics {
        width: e.width,
        height: e.height,
        max_abs: d.max_abs,
        max_rel: d.max_rel,
        rmse: d.rmse,
        psnr: d.psnr,
        flip_mean: pool.mean(),
        flip_p95: pool.get_percentile(0.95, false),
        flip_p99: pool.get_percentile(0.99, false),
        flip_p999: pool.get_percentile(0.999, false),
        flip_at_percentile: pool.get_percentile(th.percentile, false),
        differing_pixels: d.differing_pixels,
        histogram: d.histogram,
        non_finite: d.non_finite,
        alpha: (alpha == AlphaMode::Compare).then(|| alpha::measure(expected, actual, th)),
    };
    Ok((metrics, flip))
}

impl Metrics {
    /// Whether the comparison passes: no non-finite values, and both FLIP bounds hold (on
    /// the colour, and on the alpha when it is compared).
    pub fn passes(&self, th: &Thresholds) -> bool {
        self.non_finite == 0
            && self.flip_mean <= th.flip_mean
            && self.flip_at_percentile <= th.flip_at_percentile
            && self.alpha.as_ref().is_none_or(|a| {
                a.non_finite == 0
                    && a.flip_mean <= th.flip_mean
                    && a.flip_at_percentile <= th.flip_at_percentile
            })
    }
}

/// Writes `expected | FLIP heatmap (magma) | actual` side by side as a PNG.
pub fn write_report_image(
    path: &Path,
    expected: &Loaded,
    actual: &Loaded,
    flip: &[f32],
) -> Result<()> {
    let (w, h) = (expected.image.width, expected.image.height);
    let err = nv_flip::FlipImageFloat::with_data(w, h, flip);
    let heat = err.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    let mut bytes = vec![0u8; (3 * w * h * 3) as usize];
    for y in 0..h as usize {
        for (k, src) in [&expected.display, &heat, &actual.display]
            .into_iter()
            .enumerate()
        {
            let row = &src[y * w as usize * 3..(y + 1) * w as usize * 3];
            let start = (y * 3 * w as usize + k * w as usize) * 3;
            bytes[start..start + row.len()].copy_from_slice(row);
        }
    }
    image_io::write_png_bytes(path, 3 * w, h, bytes)
}
