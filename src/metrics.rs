//! Error measures between two images (or two sampled signals): the one place each
//! formula is written. [`crate::compare`] (what `brdfkit compare` reports and a GPU build's
//! CI checks), [`crate::golden`]'s fast-vs-reference bounds, the sweep's CSV columns,
//! the light-set irradiance error ([`crate::env::lightset::irradiance_error`]) and the acquisition
//! error report ([`crate::acquire::hemisphere_error`]) all call it.
//!
//! (Past 400 lines because it is the one place each error formula is written (design rule
//! below); a third of it is their closed-form tests.)
//!
//! Design rule: every measure is a pure function of its inputs, summed in index order in
//! f64 (no reduction across threads), so it gives the same bits for any thread count.
//! Differences of f32 values are taken after widening to f64 (exact), so the measure does
//! not depend on f32 rounding of the difference. FLIP (a perceptual measure on display
//! encodings) stays in [`crate::compare`], with the `nv-flip` crate.

use crate::image_io::Image;
use glam::{DVec3, Vec3};

/// The relative L2 error `sqrt(sum_sq_err / sum_sq_ref)` from its two sums: 0 when both
/// are 0 (nothing to get wrong, nothing wrong), infinite when only the reference's is 0
/// (any error is infinitely large relative to nothing).
pub fn relative_l2(sum_sq_err: f64, sum_sq_ref: f64) -> f64 {
    if sum_sq_ref > 0.0 {
        (sum_sq_err / sum_sq_ref).sqrt()
    } else if sum_sq_err > 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}

/// Relative RMSE of `img` against `reference`: `sqrt(sum |x - r|^2 / sum |r|^2)` over the
/// RGB channels of the pixels where `mask` is true (every pixel with `None`), in f64
/// ([`relative_l2`]: 0 when both sums are zero, infinite when only the reference's is).
/// The images must have the same number of pixels (panics otherwise).
pub fn relative_rmse(reference: &Image, img: &Image, mask: Option<&[bool]>) -> f64 {
    assert_eq!(
        reference.pixels.len(),
        img.pixels.len(),
        "image sizes differ"
    );
    if let Some(m) = mask {
        assert_eq!(m.len(), img.pixels.len(), "mask size differs");
    }
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (i, (r, x)) in reference.pixels.iter().zip(&img.pixels).enumerate() {
        if mask.is_none_or(|m| m[i]) {
            let (r, x) = (r.as_dvec3(), x.as_dvec3());
            num += (x - r).length_squared();
            den += r.length_squared();
        }
    }
    relative_l2(num, den)
}

/// The `q` quantile (e.g. 0.99) of the per-pixel relative error `|x - r| / |r|` (RGB
/// Euclidean norms, f64) over the pixels `keep` admits among those whose reference norm is
/// at least 1% of the mean norm of the covered (non-zero) reference pixels: uncovered
/// background and near-black pixels, where any absolute error is a large relative one, are
/// left out. 0 when no pixel is left. The images must have the same number of pixels
/// (panics otherwise). The sweep reports it beside [`relative_rmse`] as `p99_rel`.
pub fn relative_error_quantile(
    reference: &Image,
    img: &Image,
    q: f64,
    keep: impl Fn(glam::Vec3) -> bool,
) -> f64 {
    assert_eq!(
        reference.pixels.len(),
        img.pixels.len(),
        "image sizes differ"
    );
    let norms: Vec<f64> = reference
        .pixels
        .iter()
        .map(|p| p.as_dvec3().length())
        .collect();
    let covered: Vec<f64> = norms.iter().copied().filter(|&n| n > 0.0).collect();
    let mean = covered.iter().sum::<f64>() / covered.len().max(1) as f64;
    let mut rel: Vec<f64> = reference
        .pixels
        .iter()
        .zip(&img.pixels)
        .zip(&norms)
        .filter(|((r, _), &n)| n > 0.01 * mean && keep(**r))
        .map(|((r, x), &n)| (x.as_dvec3() - r.as_dvec3()).length() / n)
        .collect();
    rel.sort_by(f64::total_cmp);
    let i = ((rel.len() as f64 * q.clamp(0.0, 1.0)) as usize).min(rel.len().saturating_sub(1));
    rel.get(i).copied().unwrap_or(0.0)
}

/// Bucket upper bounds of [`Differences::histogram`]: exact zero, then `10^-7 .. 10^0`,
/// then everything larger (infinity).
pub fn histogram_bounds() -> Vec<f32> {
    std::iter::once(0.0)
        .chain((0..8).map(|k| 10f32.powi(k - 7)))
        .chain(std::iter::once(f32::INFINITY))
        .collect()
}

/// Per-channel differences of two images of one size (`brdfkit compare`'s numbers).
#[derive(Clone, Debug, PartialEq)]
pub struct Differences {
    /// Largest absolute channel difference (infinite if any value is not finite).
    pub max_abs: f32,
    /// Largest relative channel difference `|a - e| / max(|e|, 1e-3)` (infinite if any
    /// value is not finite).
    pub max_rel: f32,
    /// Root mean square channel difference over every channel of every pixel (pixels with
    /// a non-finite value left out of the sum, not of the count).
    pub rmse: f64,
    /// PSNR in dB, `20 log10(peak / rmse)`, against a peak of max(1, largest expected
    /// value); infinite if `rmse` is 0.
    pub psnr: f64,
    /// Pixels whose largest channel difference is non-zero (non-finite ones included).
    pub differing_pixels: usize,
    /// Histogram of the per-pixel largest absolute difference over [`histogram_bounds`]:
    /// `(upper bound, count)`; non-finite pixels in the last bucket.
    pub histogram: Vec<(f32, usize)>,
    /// Pixels with a NaN or infinite value in either image.
    pub non_finite: usize,
}

/// The [`Differences`] of `actual` against `expected` (same pixel count; panics
/// otherwise).
pub fn differences(expected: &Image, actual: &Image) -> Differences {
    assert_eq!(
        expected.pixels.len(),
        actual.pixels.len(),
        "image sizes differ"
    );
    let n = expected.pixels.len();
    let mut max_abs = 0.0f32;
    let mut max_rel = 0.0f32;
    let mut sq = 0.0f64;
    let mut peak = 1.0f32;
    let mut differing = 0;
    let mut non_finite = 0;
    let bounds = histogram_bounds();
    let mut hist = vec![0usize; bounds.len()];
    for (pe, pa) in expected.pixels.iter().zip(&actual.pixels) {
        if !pe.is_finite() || !pa.is_finite() {
            non_finite += 1;
            *hist.last_mut().expect("buckets") += 1;
            differing += 1;
            continue;
        }
        let d = (*pa - *pe).abs();
        let m = d.max_element();
        max_abs = max_abs.max(m);
        let rel = d / pe.abs().max(Vec3::splat(1e-3));
        max_rel = max_rel.max(rel.max_element());
        sq += d.length_squared() as f64;
        peak = peak.max(pe.max_element());
        if m > 0.0 {
            differing += 1;
        }
        let b = bounds
            .iter()
            .position(|&ub| m <= ub)
            .unwrap_or(bounds.len() - 1);
        hist[b] += 1;
    }
    let rmse = (sq / (3 * n).max(1) as f64).sqrt();
    let psnr = if rmse == 0.0 {
        f64::INFINITY
    } else {
        20.0 * (peak as f64 / rmse).log10()
    };
    let inf_if_non_finite = |x: f32| if non_finite > 0 { f32::INFINITY } else { x };
    Differences {
        max_abs: inf_if_non_finite(max_abs),
        max_rel: inf_if_non_finite(max_rel),
        rmse,
        psnr,
        differing_pixels: differing,
        histogram: bounds.into_iter().zip(hist).collect(),
        non_finite,
    }
}

/// A pixel darker than this fraction of the reference's brightest pixel (RGB Euclidean
/// norm) has its relative error taken against the fraction instead
/// ([`Radiometric::rel_error_at_percentile`]): near-black pixels, where a tiny absolute
/// difference is a large relative one, are measured against 1% of the peak.
pub const DARK_FLOOR: f64 = 0.01;

/// Radiometric agreement of an image with its reference over a set of pixels (linear
/// values): the measures that catch a small global error (a gain, a normalisation
/// constant, a dropped light) that a perceptual measure lets pass. All in f64, summed in
/// pixel order.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Radiometric {
    /// Per channel, `sum actual / sum expected` (1 when both sums are 0, infinite when only
    /// the expected one is).
    pub mean_ratio: [f64; 3],
    /// `max_c |mean_ratio_c - 1|`: the largest relative error of a channel's mean.
    pub mean_error: f64,
    /// Relative RMSE `sqrt(sum |a - e|^2 / sum |e|^2)` ([`relative_l2`]).
    pub rel_rmse: f64,
    /// Per-pixel relative error `|a - e| / max(|e|, DARK_FLOOR x peak)` (RGB Euclidean
    /// norms, `peak` the largest `|e|`) at the 99th percentile.
    pub rel_error_p99: f64,
    /// The same at the percentile asked for.
    pub rel_error_at_percentile: f64,
    /// Pixels measured.
    pub pixels: usize,
}

/// The [`Radiometric`] measures of `actual` against `expected` (equally long lists of RGB
/// values, the pixels to measure; panics otherwise), with the relative error read at
/// `percentile` in (0, 1) besides the 99th (nearest rank: the smallest value at or above
/// that share of the pixels). No pixels: every measure 0, ratios 1.
pub fn radiometric(expected: &[Vec3], actual: &[Vec3], percentile: f64) -> Radiometric {
    assert_eq!(expected.len(), actual.len(), "pixel counts differ");
    let (mut sum_e, mut sum_a) = (DVec3::ZERO, DVec3::ZERO);
    let (mut num, mut den) = (0.0f64, 0.0f64);
    let mut peak = 0.0f64;
    for (e, a) in expected.iter().zip(actual) {
        let (e, a) = (e.as_dvec3(), a.as_dvec3());
        sum_e += e;
        sum_a += a;
        num += (a - e).length_squared();
        den += e.length_squared();
        peak = peak.max(e.length());
    }
    let ratio = |a: f64, e: f64| {
        if e != 0.0 {
            a / e
        } else if a == 0.0 {
            1.0
        } else {
            f64::INFINITY
        }
    };
    let mean_ratio = [
        ratio(sum_a.x, sum_e.x),
        ratio(sum_a.y, sum_e.y),
        ratio(sum_a.z, sum_e.z),
    ];
    let mean_error = mean_ratio
        .iter()
        .map(|r| (r - 1.0).abs())
        .fold(0.0, f64::max);
    let floor = DARK_FLOOR * peak;
    let mut rel: Vec<f64> = expected
        .iter()
        .zip(actual)
        .map(|(e, a)| {
            let (e, a) = (e.as_dvec3(), a.as_dvec3());
            let d = (a - e).length();
            if d == 0.0 {
                0.0
            } else {
                d / e.length().max(floor)
            }
        })
        .collect();
    rel.sort_by(f64::total_cmp);
    let at = |q: f64| {
        if rel.is_empty() {
            return 0.0;
        }
        let k = ((q * rel.len() as f64).ceil() as usize).clamp(1, rel.len());
        rel[k - 1]
    };
    Radiometric {
        mean_ratio,
        mean_error,
        rel_rmse: relative_l2(num, den),
        rel_error_p99: at(0.99),
        rel_error_at_percentile: at(percentile),
        pixels: expected.len(),
    }
}

/// `sum_i |a_i - b_i|^2` and `sum_i |b_i|^2` of two equally long lists of RGB values, in
/// index order: the two sums of [`relative_l2`] for signals other than images.
pub fn squared_error_sums(a: &[DVec3], b: &[DVec3]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold((0.0, 0.0), |(num, den), (x, r)| {
        (num + (*x - *r).length_squared(), den + r.length_squared())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(pixels: Vec<Vec3>) -> Image {
        Image {
            width: pixels.len() as u32,
            height: 1,
            pixels,
        }
    }

    #[test]
    fn relative_l2_edge_cases() {
        assert_eq!(relative_l2(0.0, 0.0), 0.0);
        assert_eq!(relative_l2(1.0, 0.0), f64::INFINITY);
        assert_eq!(relative_l2(0.25, 1.0), 0.5);
    }

    #[test]
    fn relative_rmse_closed_forms() {
        let r = image(vec![Vec3::new(1.0, 2.0, 2.0), Vec3::splat(5.0)]);
        // 10% over on the covered pixel: sqrt(0.01 * 9 / 9) = 0.1; the uncovered pixel,
        // however wrong, does not count.
        let x = image(vec![Vec3::new(1.1, 2.2, 2.2), Vec3::splat(-7.0)]);
        let mask = [true, false];
        assert!((relative_rmse(&r, &x, Some(&mask)) - 0.1).abs() < 1e-6);
        // Both pixels: sqrt((0.09 + 3 * 144) / (9 + 75)).
        let all = ((0.09f64 + 432.0) / 84.0).sqrt();
        assert!((relative_rmse(&r, &x, None) - all).abs() < 1e-6);
        assert_eq!(relative_rmse(&r, &r, Some(&mask)), 0.0);
        let zero = image(vec![Vec3::ZERO; 2]);
        assert_eq!(relative_rmse(&zero, &zero, Some(&mask)), 0.0);
        // A black reference: any error is infinite (the golden bound used to report 0).
        assert_eq!(relative_rmse(&zero, &x, None), f64::INFINITY);
    }

    #[test]
    fn differences_closed_forms() {
        let e = image(vec![Vec3::new(1.0, 2.0, 0.0), Vec3::splat(4.0), Vec3::ZERO]);
        let a = image(vec![Vec3::new(1.5, 2.0, 0.0), Vec3::splat(4.0), Vec3::ZERO]);
        let d = differences(&e, &a);
        assert_eq!(d.max_abs, 0.5);
        assert_eq!(d.max_rel, 0.5);
        // One channel of nine off by 0.5: sqrt(0.25 / 9) = 1/6; peak 4.
        assert!((d.rmse - 1.0 / 6.0).abs() < 1e-12);
        assert!((d.psnr - 20.0 * (4.0f64 * 6.0).log10()).abs() < 1e-9);
        assert_eq!(d.differing_pixels, 1);
        assert_eq!(d.non_finite, 0);
        // 0.5 falls in the bucket (0.1, 1]; the other two pixels are exact zeros.
        let count = |ub: f32| d.histogram.iter().find(|b| b.0 == ub).unwrap().1;
        assert_eq!((count(0.0), count(1.0)), (2, 1));
        assert_eq!(d.histogram.iter().map(|b| b.1).sum::<usize>(), 3);

        let nan = image(vec![
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::splat(4.0),
            Vec3::ZERO,
        ]);
        let d = differences(&e, &nan);
        assert_eq!((d.non_finite, d.differing_pixels), (1, 1));
        assert_eq!(d.max_abs, f32::INFINITY);
        assert_eq!(d.histogram.last().unwrap().1, 1);
        assert_eq!(d.rmse, 0.0);
    }

    #[test]
    fn radiometric_closed_forms() {
        let e = [Vec3::new(1.0, 2.0, 2.0), Vec3::splat(4.0), Vec3::ZERO];
        // A 0.5% gain: every mean 0.5% high, relative RMSE and every pixel's error 0.005
        // (the black pixel stays 0).
        let a: Vec<Vec3> = e.iter().map(|p| *p * 1.005).collect();
        let r = radiometric(&e, &a, 0.5);
        for m in r.mean_ratio {
            assert!((m - 1.005).abs() < 1e-6, "{m}");
        }
        assert!((r.mean_error - 0.005).abs() < 1e-6);
        assert!((r.rel_rmse - 0.005).abs() < 1e-6);
        assert!((r.rel_error_p99 - 0.005).abs() < 1e-6);
        // Nearest rank: the median of {0, 0.005, 0.005} is 0.005.
        assert!((r.rel_error_at_percentile - 0.005).abs() < 1e-6);
        assert_eq!(r.pixels, 3);
        // A near-black pixel is measured against 1% of the peak (|e| = sqrt(48)), not
        // against itself: an error of 1e-3 on a 1e-6 pixel is 1e-3 / 0.0693, not 1000.
        let e = [Vec3::splat(4.0), Vec3::new(1e-6, 0.0, 0.0)];
        let a = [Vec3::splat(4.0), Vec3::new(1e-6 + 1e-3, 0.0, 0.0)];
        let r = radiometric(&e, &a, 0.99);
        let want = 1e-3 / (DARK_FLOOR * 48f64.sqrt());
        assert!(
            (r.rel_error_p99 - want).abs() < 1e-6 * want,
            "{}",
            r.rel_error_p99
        );
        // Equal images: all zero, ratios 1; an empty set likewise.
        let r = radiometric(&e, &e, 0.99);
        assert_eq!((r.mean_error, r.rel_rmse, r.rel_error_p99), (0.0, 0.0, 0.0));
        assert_eq!(radiometric(&[], &[], 0.99).mean_ratio, [1.0; 3]);
        // A channel the reference does not have, lit in the image: infinite.
        let r = radiometric(&[Vec3::X], &[Vec3::new(1.0, 0.1, 0.0)], 0.99);
        assert_eq!(r.mean_ratio[1], f64::INFINITY);
    }

    #[test]
    fn squared_error_sums_closed_form() {
        let a = [DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 3.0, 0.0)];
        let b = [DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
        assert_eq!(squared_error_sums(&a, &b), (5.0, 1.0));
        assert_eq!(relative_l2(5.0, 1.0), 5f64.sqrt());
    }
}

/// The negative values of one image (radiance cannot be negative: SH data that rings,
/// [`crate::acquire::Method`], is the usual cause): how many pixels have a channel below
/// zero and the most negative channel value.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NegativePixels {
    /// Pixels with at least one channel `< 0`.
    pub pixels: usize,
    /// The smallest channel value of the image, when it is negative (else 0).
    pub min: f32,
}

/// Counts the pixels of `img` with a channel below zero ([`NegativePixels`]); NaN channels
/// are not negative.
pub fn negative_pixels(img: &Image) -> NegativePixels {
    let mut out = NegativePixels::default();
    for p in &img.pixels {
        let m = p.min_element();
        if m < 0.0 {
            out.pixels += 1;
            out.min = out.min.min(m);
        }
    }
    out
}
