//! The alpha channel compared as a fourth channel ([`super::AlphaMode::Compare`]): its
//! largest difference and its FLIP, alpha shown as a grey image. An image without alpha
//! counts as opaque (alpha 1 everywhere). The largest difference and the differing count
//! are over every pixel; the FLIP statistics over the colour's covered pixels plus every
//! pixel whose alpha differs ([`super::coverage::alpha_pixels`]), or over every pixel when
//! the comparison measures all of them.

use super::{coverage, flip_of, FlipStats, Loaded, Thresholds};
use crate::image_io;

/// The alpha channel compared as a fourth channel ([`super::AlphaMode::Compare`]).
#[derive(Clone, Debug, serde::Serialize)]
pub struct AlphaMetrics {
    /// Largest absolute alpha difference.
    pub max_abs: f32,
    /// Pixels whose alpha differs.
    pub differing_pixels: usize,
    /// FLIP of alpha shown as a grey image (8-bit, `round(255 clamp(alpha))`, no tone
    /// map): its mean and its value at the threshold's percentile, over the covered pixels
    /// and those whose alpha differs.
    pub flip_mean: f32,
    pub flip_at_percentile: f32,
    /// NaN or infinite alpha values in either image.
    pub non_finite: usize,
}

/// The alpha measures of two images of one size (missing alpha counts as 1); `covered`:
/// the colour's covered pixels, `None` for every pixel.
pub(super) fn measure(
    expected: &Loaded,
    actual: &Loaded,
    th: &Thresholds,
    covered: Option<&[bool]>,
) -> AlphaMetrics {
    let n = (expected.image.width * expected.image.height) as usize;
    let opaque = vec![1.0f32; n];
    let e = expected.alpha.as_deref().unwrap_or(&opaque);
    let a = actual.alpha.as_deref().unwrap_or(&opaque);
    let grey = |v: &[f32]| -> Vec<u8> {
        v.iter()
            .flat_map(|&x| [image_io::display::to_u8(x); 3])
            .collect()
    };
    let (flip, mut pool) = flip_of(
        expected.image.width,
        expected.image.height,
        &grey(e),
        &grey(a),
    );
    let stats = match covered {
        None => FlipStats::of(&mut pool, th),
        Some(c) => FlipStats::masked(&flip, &coverage::alpha_pixels(c, e, a), th),
    };
    let mut m = AlphaMetrics {
        max_abs: 0.0,
        differing_pixels: 0,
        flip_mean: stats.mean,
        flip_at_percentile: stats.at_percentile,
        non_finite: 0,
    };
    for (&x, &y) in e.iter().zip(a) {
        if !(x.is_finite() && y.is_finite()) {
            m.non_finite += 1;
            continue;
        }
        let d = (x - y).abs();
        m.max_abs = m.max_abs.max(d);
        m.differing_pixels += usize::from(d != 0.0);
    }
    m
}
