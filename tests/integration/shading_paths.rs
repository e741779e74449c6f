//! Shared by the tests that hold the kernels to the other shading paths: the image of each
//! path other than the kernels, through the one entry point `brdfkit::shade::shade`.

// Each test file uses the paths it needs.
#![allow(dead_code)]

use brdfkit::image_io::Image;
use brdfkit::raster::VisBuffer;
use brdfkit::scene::Scene;
use brdfkit::shade::{shade, ShadeOptions, ShadingPath};

/// The scalar f32 oracle's image of `s` ([`ShadingPath::ScalarOracle`]: the kernels' skips,
/// no kernel, no culling).
pub fn scalar_oracle(s: &Scene, vis: &VisBuffer) -> Image {
    let opts = ShadeOptions::default().with_path(ShadingPath::ScalarOracle);
    shade(s, vis, &opts).image
}

/// The f64 path's image of `s` ([`ShadingPath::F64NoSkips`]: every light, every band, f64).
pub fn f64_no_skips(s: &Scene, vis: &VisBuffer) -> Image {
    let opts = ShadeOptions::default().with_path(ShadingPath::F64NoSkips);
    shade(s, vis, &opts).image
}
