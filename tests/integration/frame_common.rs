//! Shared by the tangent-frame tests (`frame_invariance.rs`, `anisotropic_frame.rs`): a
//! scene rendered as `brdfkit render` does but for the frame check
//! ([`brdfkit::shade::FrameCheck`]: the frame turned or the alignment left out, the seeded
//! faults), and the error measure both compare renders with.

use brdfkit::image_io::Image;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::Scene;
use brdfkit::shade::FrameCheck;

/// The image of `scene` with the default options and the frame check `check`.
pub fn shade(scene: &Scene, check: FrameCheck) -> Image {
    let mut opts = RenderOptions::default();
    opts.shading.frame_check = check;
    render(scene, &opts).image
}

/// RMSE of `a - b` over the pixels `b` covers, relative to `b`'s RMS there; the object must
/// cover over 1000 pixels.
pub fn rel_rmse(a: &Image, b: &Image) -> f64 {
    let (mut d2, mut r2, mut n) = (0.0f64, 0.0f64, 0usize);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        if *q == glam::Vec3::ZERO {
            continue;
        }
        d2 += (*p - *q).as_dvec3().length_squared();
        r2 += q.as_dvec3().length_squared();
        n += 1;
    }
    assert!(n > 1000, "the object covers {n} pixels");
    (d2 / r2).sqrt()
}
