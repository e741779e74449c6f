//! Which pixels a comparison measures: the object, not the background.
//!
//! Design rule: coverage is decided from the colour values the two images carry, the same
//! way for EXR and PNG, with no scene or AOV at hand: brdfkit's renderer writes RGB with
//! the background exactly 0 (no alpha channel), so a pixel is **covered** when either
//! image has a non-zero colour channel there, or a value that is not finite. Taking either
//! image (not the expected one alone) keeps an error that draws onto the expected
//! background, such as a silhouette one pixel off or a lit clear colour, inside the
//! measurement. A pixel black in both images is background and left out of every mean,
//! percentile and count; a frame that is mostly background (83% of the default frame) no
//! longer dilutes an error on the object. An alpha channel does not decide coverage (a
//! read-back's alpha is often 1 everywhere); under [`super::AlphaMode::Compare`] the alpha
//! measures add the pixels whose alpha differs ([`alpha_pixels`]).

use super::Loaded;

/// Which pixels a comparison's statistics are taken over.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Pixels {
    /// The covered pixels ([`covered`]): what `brdfkit compare` and `golden check --device
    /// gpu` measure.
    #[default]
    Covered,
    /// Every pixel of the frame: the sweep's `flip_mean` column and the golden set's
    /// recorded fast-vs-reference bounds, which were measured so.
    All,
}

impl Pixels {
    /// How the report names the pixel set: "covered pixels" or "all pixels".
    pub fn label(self) -> &'static str {
        match self {
            Pixels::Covered => "covered pixels",
            Pixels::All => "all pixels",
        }
    }
}

/// What [`covered`] says, in one phrase (for the report and the help text).
pub const COVERAGE_RULE: &str = "non-black in either image";

/// Whether each pixel (row-major) is covered: a colour channel of either image is non-zero
/// or not finite. The images must have the same number of pixels (panics otherwise).
pub fn covered(expected: &Loaded, actual: &Loaded) -> Vec<bool> {
    let (e, a) = (&expected.image.pixels, &actual.image.pixels);
    assert_eq!(e.len(), a.len(), "image sizes differ");
    e.iter()
        .zip(a)
        .map(|(pe, pa)| {
            pe.to_array()
                .iter()
                .chain(&pa.to_array())
                .any(|&c| c != 0.0)
        })
        .collect()
}

/// The pixels the alpha measures cover: the colour's covered pixels and every pixel whose
/// alpha differs (`expected_alpha` and `actual_alpha` per pixel; a NaN differs).
pub fn alpha_pixels(covered: &[bool], expected_alpha: &[f32], actual_alpha: &[f32]) -> Vec<bool> {
    covered
        .iter()
        .zip(expected_alpha.iter().zip(actual_alpha))
        .map(|(&c, (x, y))| c || x != y)
        .collect()
}

/// Whether a pixel of either image holds a NaN or infinite channel.
pub fn non_finite(expected: glam::Vec3, actual: glam::Vec3) -> bool {
    !(expected.is_finite() && actual.is_finite())
}
