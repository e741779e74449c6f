//! Per-pixel tolerances of the golden check, by name, each with the reason for its size,
//! and the comparison that applies them.

use super::*;

/// A per-pixel tolerance for the golden check, plus the FLIP bounds `brdfkit compare
/// --bounds golden/manifest.toml --entry` applies to a GPU build's image of the entry.
///
/// Per channel: `|actual - expected| <= abs + rel * max(|expected|, peak_floor * peak)`,
/// `peak` being the largest channel value of the expected image. `peak_floor` keeps the
/// relative bound meaningful where a sum of large terms of both signs cancels to a value
/// far below its terms (SH ringing; thesis 2.3.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    pub abs: f32,
    pub rel: f32,
    pub peak_floor: f32,
    /// FLIP bounds for another implementation's image of the entry (see [`Thresholds`]).
    pub flip: Thresholds,
}

/// For values that must agree across machines and compilers bit for bit up to libm: the
/// debug outputs (angles through `acos`/`atan2`, depths, normals, integer coverage) and the
/// f64 path (rounded to f32 once per pixel). Another libm moves an f32 result by a few
/// ulps (about 1e-7 relative) and an f64 one by far less; never by a shading or coverage
/// change (a covered pixel moves by far more than 1e-4, an angle AOV at a texel seam by
/// 1e-2 and more).
pub const CROSS_PLATFORM: Tolerance = Tolerance {
    abs: 1e-5,
    rel: 1e-4,
    peak_floor: 0.0,
    flip: Thresholds::DEFAULT,
};

/// For shaded images of the f32 fast path checked off the platform and kernel path that
/// blessed them (on it, every bit must agree: see the module doc): another platform's libm,
/// another instruction set, or a GPU build sums the same terms in another order, and each
/// kernel is held within [`crate::kernel::SH_KERNEL_TOLERANCE`] (relative to the pixel or
/// to 1% of the image's peak) of the scalar oracle. The scalar oracle, another summation
/// order, passes every shaded f32 entry at this tolerance (tests/integration/golden.rs,
/// `the_scalar_oracle_passes_every_shaded_f32_entry`, which prints the share used). The
/// faults of tests/integration/perturbation.rs (half-texel lookup shift, wrong cosine
/// factor, flipped azimuth) move pixels by 1e-2 and more, and tests/integration/golden.rs
/// shows a lookup-mode change, an environment turned by 2 degrees and a 1% pixel change are
/// each caught at it.
pub const KERNEL_DISPATCH: Tolerance = Tolerance {
    abs: 1e-6,
    rel: crate::kernel::SH_KERNEL_TOLERANCE,
    peak_floor: 0.01,
    flip: Thresholds::DEFAULT,
};

/// Every tolerance with its manifest name.
pub const TOLERANCES: [(&str, Tolerance); 2] = [
    ("cross-platform", CROSS_PLATFORM),
    ("kernel-dispatch", KERNEL_DISPATCH),
];

/// Looks up a tolerance by its manifest name.
pub fn tolerance_named(name: &str) -> Option<Tolerance> {
    TOLERANCES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// Compares two images with a tolerance: `(largest absolute error, pixels over the
/// tolerance)`; `None` if their sizes differ. A NaN in either image fails its pixel.
pub fn compare(expected: &Image, actual: &Image, tol: Tolerance) -> Option<(f32, usize)> {
    if expected.width != actual.width || expected.height != actual.height {
        return None;
    }
    let peak = expected
        .pixels
        .iter()
        .map(|p| p.abs().max_element())
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    let floor = Vec3::splat(tol.peak_floor * peak);
    let mut max_abs = 0.0f32;
    let mut over = 0;
    for (e, a) in expected.pixels.iter().zip(&actual.pixels) {
        let d = (*a - *e).abs();
        let lim = Vec3::splat(tol.abs) + e.abs().max(floor) * tol.rel;
        // NaN in either image fails.
        if !(d.cmple(lim).all()) {
            over += 1;
        }
        max_abs = max_abs.max(if d.is_nan() {
            f32::INFINITY
        } else {
            d.max_element()
        });
    }
    Some((max_abs, over))
}
