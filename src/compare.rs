//! Image comparison: the measurements `brdfkit compare` reports and the pass/fail rule a
//! GPU build's CI relies on. The pixel measures are [`crate::metrics`]'s; FLIP is here.
//!
//! Design rule: like is compared with like, and the object is measured, not the
//! background. Two EXR files are compared as linear floats; two PNG files as their 8-bit
//! sRGB values scaled to [0, 1]. A size, colour-layout (RGB against L) or kind mismatch is
//! *unusable input*, never a silent conversion. Every statistic (errors, RMSE, PSNR, FLIP
//! mean and percentiles, the histogram) is taken over the **covered pixels**
//! ([`coverage`]: non-black in either image; the renderer's background is exactly 0), so a
//! frame that is mostly background does not dilute an error on the object; [`Pixels::All`]
//! keeps the whole frame for the measurements recorded that way. A NaN or infinite value
//! fails the comparison before any statistic ([`Metrics::bounds`]). An alpha channel
//! (RGBA EXR or PNG, what most GPU read-backs produce) is ignored by default
//! ([`AlphaMode::Ignore`]): RGBA is compared with RGB on its colour channels, never
//! premultiplied. [`AlphaMode::Compare`] compares it as a fourth channel, an image without
//! one counting as opaque (alpha 1). FLIP (NVIDIA's perceptual
//! difference, through the `nv-flip` crate) is computed on what a person sees: PNGs as they
//! are, EXRs after [`crate::image_io::display_u8`] (exposure 0, ACES, sRGB), over the whole
//! frame (it filters across neighbours), then pooled over the covered pixels.
//!
//! Thresholds follow wgpu's image tests: a FLIP mean and a FLIP value at a high percentile,
//! each with a reason (see [`Thresholds::DEFAULT`]).

mod alpha;
pub mod coverage;
mod load;
mod verdict;

pub use crate::metrics::Radiometric;
pub use alpha::AlphaMetrics;
pub use coverage::Pixels;
pub use load::{load, Layout, Loaded, MAX_SIDE, PNG_ALLOC_SLACK, PNG_MAX_EXPANSION};
pub use verdict::{decimal, percentile_label, Bound};

use crate::error::{Error, Result};
use crate::image_io::{self, Image};
use glam::Vec3;
use std::path::Path;

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

/// Pass thresholds: FLIP mean and the FLIP value at a percentile (both in [0, 1]), and the
/// radiometric bounds where set ([`RadiometricBounds`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Thresholds {
    pub flip_mean: f32,
    /// Percentile in (0, 1), e.g. 0.99: of the FLIP bound and of the relative error's.
    pub percentile: f32,
    pub flip_at_percentile: f32,
    pub radiometric: RadiometricBounds,
}

/// Bounds on the radiometric measures ([`crate::metrics::Radiometric`], over the covered
/// pixels whose coverage agrees), each unset by default: FLIP measures what a person sees,
/// these what a numerical method's two implementations must agree to (a GPU build 0.5% too
/// bright passes FLIP and fails `mean_error`). `golden/gpu-bounds.toml` sets them per entry
/// from a measurement ([`crate::golden::GpuBound`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct RadiometricBounds {
    /// Largest `|mean ratio - 1|` of a channel.
    pub mean_error: Option<f32>,
    /// Largest relative RMSE.
    pub rel_rmse: Option<f32>,
    /// Largest per-pixel relative error at [`Thresholds::percentile`].
    pub rel_error_at_percentile: Option<f32>,
    /// Largest share of the covered pixels covered in one image only (the silhouette: a
    /// rasterizer's edge rule), which the radiometric measures leave out.
    pub coverage_mismatch: Option<f32>,
}

impl RadiometricBounds {
    /// No radiometric bound.
    pub const NONE: RadiometricBounds = RadiometricBounds {
        mean_error: None,
        rel_rmse: None,
        rel_error_at_percentile: None,
        coverage_mismatch: None,
    };
}

impl Thresholds {
    /// Defaults for a GPU build against this oracle, from tests/integration/perturbation.rs
    /// (blue silk and a 45-degree-turned anisotropic lobe, 160x120, city probe, 64 median-cut
    /// lights + a key light). Measured FLIP mean / 99th percentile of the seeded faults over
    /// the covered pixels (3,322 of 19,200), as `brdfkit compare` measures: half-texel lookup
    /// shift 0.156 / 0.48, wrong cosine factor 0.380 / 0.67, flipped azimuth 0.557 / 0.97
    /// (over the whole frame they were 0.032 / 0.36, 0.080 / 0.60 and 0.109 / 0.96: the
    /// background diluted the means); the unperturbed render 0 / 0, and our own f32 kernel
    /// against the scalar oracle differs by at most 1.3e-4 relative, which does not change an
    /// 8-bit display value. The mean bound (0.01) sits at a fifteenth of the smallest fault's
    /// mean (a third over the whole frame, where it was chosen), leaving room
    /// for a GPU port's legitimate differences (8-bit sub-texel filtering weights, fp32
    /// evaluation order; not measured here: this machine has no GPU). The 99th-percentile
    /// bound (0.1) keeps a small bad region (a seam, a few hundred wrong pixels) from hiding
    /// in a good mean; a one-pixel shift of the whole image fails it
    /// (tests/integration/compare.rs).
    pub const DEFAULT: Thresholds = Thresholds {
        flip_mean: 0.01,
        percentile: 0.99,
        flip_at_percentile: 0.1,
        radiometric: RadiometricBounds::NONE,
    };
}

/// The measurements of one comparison over the pixels of [`Metrics::pixels`]: the pixel
/// differences of [`crate::metrics::differences`] (see [`crate::metrics::Differences`] for
/// each definition) and the FLIP statistics, over the measured pixels (covered and
/// finite). Values are linear radiance for EXR, encoded/255 for PNG; FLIP is in [0, 1].
#[derive(Clone, Debug, serde::Serialize)]
pub struct Metrics {
    pub width: u32,
    pub height: u32,
    /// The pixel set the statistics are taken over.
    pub pixels: Pixels,
    /// Pixels in that set ([`coverage::covered`] for [`Pixels::Covered`], every pixel for
    /// [`Pixels::All`]).
    pub covered: usize,
    /// Covered pixels without a non-finite value: the ones the statistics are taken over.
    pub measured: usize,
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
    /// Pixels with a NaN or infinite value in either image (always covered, never
    /// measured): any fails the comparison.
    pub non_finite: usize,
    /// The first [`NON_FINITE_LISTED`] of them, row-major, as `[x, y]` (row 0 at the top).
    pub non_finite_at: Vec<[u32; 2]>,
    /// The alpha channel's measures under [`AlphaMode::Compare`].
    pub alpha: Option<AlphaMetrics>,
    /// Measured pixels covered in one image only (black in the other): silhouette pixels
    /// that one rasterizer covers and the other does not.
    pub coverage_mismatch: usize,
    /// The radiometric measures over the measured pixels non-black in both images.
    pub radiometric: crate::metrics::Radiometric,
}

impl Metrics {
    /// [`Metrics::coverage_mismatch`] as a share of the measured pixels (0 when none).
    pub fn coverage_mismatch_share(&self) -> f64 {
        self.coverage_mismatch as f64 / self.measured.max(1) as f64
    }
}

/// How many non-finite pixels [`Metrics::non_finite_at`] lists.
pub const NON_FINITE_LISTED: usize = 5;

/// FLIP of `expected` against `actual` (8-bit RGB display bytes): the per-pixel error
/// and its pool.
fn flip_of(w: u32, h: u32, expected: &[u8], actual: &[u8]) -> (Vec<f32>, nv_flip::FlipPool) {
    let fe = nv_flip::FlipImageRgb8::with_data(w, h, expected);
    let fa = nv_flip::FlipImageRgb8::with_data(w, h, actual);
    let err = nv_flip::flip(fe, fa, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let pool = nv_flip::FlipPool::from_image(&err);
    (err.to_vec(), pool)
}

/// FLIP statistics of a pool: mean, then the values at the 95th, 99th and 99.9th
/// percentiles and at the threshold's.
#[derive(Clone, Copy, Debug, Default)]
struct FlipStats {
    mean: f32,
    p95: f32,
    p99: f32,
    p999: f32,
    at_percentile: f32,
}

impl FlipStats {
    fn of(pool: &mut nv_flip::FlipPool, th: &Thresholds) -> FlipStats {
        FlipStats {
            mean: pool.mean(),
            p95: pool.get_percentile(0.95, false),
            p99: pool.get_percentile(0.99, false),
            p999: pool.get_percentile(0.999, false),
            at_percentile: pool.get_percentile(th.percentile, false),
        }
    }

    /// The statistics of the per-pixel FLIP values `flip` where `keep` is true (all zero
    /// when none is kept).
    fn masked(flip: &[f32], keep: &[bool], th: &Thresholds) -> FlipStats {
        let values: Vec<f32> = flip
            .iter()
            .zip(keep)
            .filter(|p| *p.1)
            .map(|(&v, _)| v)
            .collect();
        if values.is_empty() {
            return FlipStats::default();
        }
        let row = nv_flip::FlipImageFloat::with_data(values.len() as u32, 1, &values);
        FlipStats::of(&mut nv_flip::FlipPool::from_image(&row), th)
    }
}

/// Compares `expected` with `actual` on their colour channels ([`AlphaMode::Ignore`]) over
/// every pixel ([`Pixels::All`]: the sweep's and the golden fast-vs-reference bounds'
/// measurement). Fails (unusable input) when sizes, kinds or colour layouts differ.
pub fn compare(expected: &Loaded, actual: &Loaded, th: &Thresholds) -> Result<(Metrics, Vec<f32>)> {
    compare_with(expected, actual, th, AlphaMode::Ignore, Pixels::All)
}

/// Compares `expected` with `actual` over the pixel set `pixels` ([`Pixels::Covered`]: what
/// `brdfkit compare` and `golden check --device gpu` measure), with the alpha channel
/// ignored or compared ([`AlphaMode`]). Returns the metrics and the per-pixel FLIP of the
/// whole frame (row-major, for the heatmap). Fails (unusable input) when sizes, kinds or
/// colour layouts differ.
pub fn compare_with(
    expected: &Loaded,
    actual: &Loaded,
    th: &Thresholds,
    alpha: AlphaMode,
    pixels: Pixels,
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
    let bad: Vec<bool> = e
        .pixels
        .iter()
        .zip(&a.pixels)
        .map(|(&pe, &pa)| coverage::non_finite(pe, pa))
        .collect();
    let non_finite_at: Vec<[u32; 2]> = bad
        .iter()
        .enumerate()
        .filter(|p| *p.1)
        .take(NON_FINITE_LISTED)
        .map(|(i, _)| [i as u32 % e.width, i as u32 / e.width])
        .collect();
    let (flip, mut pool) = flip_of(e.width, e.height, &expected.display, &actual.display);
    let (d, stats, covered, mask) = match pixels {
        Pixels::All => {
            let stats = FlipStats::of(&mut pool, th);
            (crate::metrics::differences(e, a), stats, bad.len(), None)
        }
        Pixels::Covered => {
            let covered = coverage::covered(expected, actual);
            let keep: Vec<bool> = covered.iter().zip(&bad).map(|(&c, &b)| c && !b).collect();
            let only = |img: &Image| {
                let pixels: Vec<Vec3> = img
                    .pixels
                    .iter()
                    .zip(&keep)
                    .filter(|p| *p.1)
                    .map(|(&p, _)| p)
                    .collect();
                Image {
                    width: pixels.len() as u32,
                    height: 1,
                    pixels,
                }
            };
            let d = crate::metrics::differences(&only(e), &only(a));
            let stats = FlipStats::masked(&flip, &keep, th);
            let n = covered.iter().filter(|&&c| c).count();
            (d, stats, n, Some(covered))
        }
    };
    let non_finite = bad.iter().filter(|&&b| b).count();
    // Radiometric measures: the measured pixels lit in both images, so a silhouette pixel
    // one rasterizer covers is counted, not averaged in.
    let black = |p: Vec3| p == Vec3::ZERO;
    let (mut re, mut ra, mut coverage_mismatch) = (Vec::new(), Vec::new(), 0usize);
    for (i, (&pe, &pa)) in e.pixels.iter().zip(&a.pixels).enumerate() {
        let measured = !bad[i] && mask.as_ref().is_none_or(|m| m[i]);
        if !measured {
            continue;
        }
        match (black(pe), black(pa)) {
            (true, true) => {}
            (false, false) => {
                re.push(pe);
                ra.push(pa);
            }
            _ => coverage_mismatch += 1,
        }
    }
    let radiometric = crate::metrics::radiometric(&re, &ra, th.percentile as f64);
    let metrics = Metrics {
        width: e.width,
        height: e.height,
        pixels,
        covered,
        measured: covered - non_finite,
        max_abs: d.max_abs,
        max_rel: d.max_rel,
        rmse: d.rmse,
        psnr: d.psnr,
        flip_mean: stats.mean,
        flip_p95: stats.p95,
        flip_p99: stats.p99,
        flip_p999: stats.p999,
        flip_at_percentile: stats.at_percentile,
        differing_pixels: d.differing_pixels,
        histogram: d.histogram,
        non_finite,
        non_finite_at,
        alpha: (alpha == AlphaMode::Compare)
            .then(|| alpha::measure(expected, actual, th, mask.as_deref())),
        coverage_mismatch,
        radiometric,
    };
    Ok((metrics, flip))
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
