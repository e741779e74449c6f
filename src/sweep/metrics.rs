//! The deterministic measurements of a sweep row: an image's errors against the reference
//! over the pixels the mesh covers.
//!
//! Design rule: every value here is a pure function of the two images and the coverage
//! mask (no timing, no thread-count dependence), so shards merge exactly. `rel_rmse` is
//! [`crate::metrics::relative_rmse`] and `p99_rel` [`crate::metrics::relative_error_quantile`]
//! over covered pixels only; `max_err` and `flip_mean` come from
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

/// The deterministic errors of one image against the reference.
#[derive(Clone, Copy, Debug)]
pub struct Errors {
    /// Relative RMSE over the covered pixels.
    pub rel_rmse: f64,
    /// 99th percentile of the per-pixel relative error over the covered pixels
    /// ([`metrics::relative_error_quantile`]).
    pub p99_rel: f64,
    /// Largest absolute channel difference, linear radiance.
    pub max_err: f64,
    /// Mean FLIP of the display encodings.
    pub flip_mean: f64,
}

/// The [`Errors`] of `img` against `reference`.
pub(super) fn errors(reference: &Loaded, covered: &[bool], img: &Image) -> Result<Errors> {
    let (m, _) = compare::compare(
        reference,
        &Loaded::from_linear(img.clone()),
        &Thresholds::DEFAULT,
    )?;
    // The quantile over covered pixels only: both images black elsewhere (the quantile
    // leaves out pixels whose reference is black).
    let only_covered = |im: &Image| {
        let mut out = im.clone();
        for (p, &c) in out.pixels.iter_mut().zip(covered) {
            if !c {
                *p = glam::Vec3::ZERO;
            }
        }
        out
    };
    let (r_cov, x_cov) = (only_covered(&reference.image), only_covered(img));
    Ok(Errors {
        rel_rmse: metrics::relative_rmse(&reference.image, img, Some(covered)),
        p99_rel: metrics::relative_error_quantile(&r_cov, &x_cov, 0.99, |_| true),
        max_err: m.max_abs as f64,
        flip_mean: m.flip_mean as f64,
    })
}
