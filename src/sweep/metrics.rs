//! The deterministic measurements of a sweep row: an image's errors against the reference
//! over the pixels the mesh covers.
//!
//! Design rule: every value here is a pure function of the two images and the coverage
//! mask (no timing, no thread-count dependence), so shards merge exactly. `rel_rmse` is
//! computed here over covered pixels only; `max_err` and `flip_mean` come from
//! [`crate::compare`] over the whole frame, as `brdfkit compare` reports them.

use crate::compare::{self, Loaded, Thresholds};
use crate::error::Result;
use crate::image_io::Image;
use crate::scene::Scene;

/// `sqrt(sum |x - r|^2 / sum |r|^2)` over the RGB channels of the pixels where `mask` is
/// true (0 when both are zero there; infinite when only the reference is zero).
pub fn relative_rmse(reference: &Image, img: &Image, mask: &[bool]) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for ((r, x), &m) in reference.pixels.iter().zip(&img.pixels).zip(mask) {
        if m {
            let (r, x) = (r.as_dvec3(), x.as_dvec3());
            num += (x - r).length_squared();
            den += r.length_squared();
        }
    }
    if num == 0.0 {
        0.0
    } else {
        (num / den).sqrt()
    }
}

/// The pixels of `scene`'s frame that its mesh covers (row-major), the mask of `rel_rmse`.
pub(super) fn covered_pixels(scene: &Scene) -> Vec<bool> {
    let vis = crate::render::rasterize(scene, false);
    (0..scene.render.height)
        .flat_map(|y| (0..scene.render.width).map(move |x| (x, y)))
        .map(|(x, y)| vis.visible[vis.index(x, y)] != crate::raster::NO_TRIANGLE)
        .collect()
}

/// (relative RMSE over `covered` pixels, largest absolute channel difference in linear
/// radiance, mean FLIP of the display encodings) of `img` against `reference`.
pub(super) fn errors(reference: &Loaded, covered: &[bool], img: &Image) -> Result<(f64, f64, f64)> {
    let (m, _) = compare::compare(
        reference,
        &Loaded::from_linear(img.clone()),
        &Thresholds::DEFAULT,
    )?;
    Ok((
        relative_rmse(&reference.image, img, covered),
        m.max_abs as f64,
        m.flip_mean as f64,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn image(pixels: Vec<Vec3>) -> Image {
        Image {
            width: pixels.len() as u32,
            height: 1,
            pixels,
        }
    }

    #[test]
    fn relative_rmse_closed_forms() {
        let r = image(vec![Vec3::new(1.0, 2.0, 2.0), Vec3::splat(5.0)]);
        // 10% over on the covered pixel: sqrt(0.01 * 9 / 9) = 0.1; the uncovered pixel,
        // however wrong, does not count.
        let x = image(vec![Vec3::new(1.1, 2.2, 2.2), Vec3::splat(-7.0)]);
        let mask = [true, false];
        assert!((relative_rmse(&r, &x, &mask) - 0.1).abs() < 1e-6);
        assert_eq!(relative_rmse(&r, &r, &mask), 0.0);
        let zero = image(vec![Vec3::ZERO; 2]);
        assert_eq!(relative_rmse(&zero, &zero, &mask), 0.0);
        assert_eq!(relative_rmse(&zero, &x, &mask), f64::INFINITY);
    }
}
