//! The deterministic measurements of a sweep row: an image's errors against the reference
//! over the pixels the mesh covers.
//!
//! Design rule: every value here is a pure function of the two images and the coverage
//! mask (no timing, no thread-count dependence), so shards merge exactly. `rel_rmse` is
//! [`crate::metrics::relative_rmse`] over covered pixels only; `max_err` and `flip_mean` come from
//! [`crate::compare`] over the whole frame, as `brdfkit compare` reports them.

use crate::compare::{self, Loaded, Thresholds};
use crate::error::Result;
use crate::image_io::Image;
use crate::metrics;
use crate::scene::Scene;

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
        metrics::relative_rmse(&reference.image, img, Some(covered)),
        m.max_abs as f64,
        m.flip_mean as f64,
    ))
}
