//! Adaptive light cuts: every probe texel a directional light, organised in a light tree, and
//! per pixel a cut through the tree refined until each cluster's error bound is a small
//! fraction of the pixel's value (Walter, Fernandez, Arbree, Bala, Donikian & Greenberg,
//! "Lightcuts: a scalable approach to illumination", SIGGRAPH 2005).
//!
//! # What is summed
//! The converged reference shades the full probe: `L_o = sum_t f(w_t, wo) cos(polar_t) E_t`
//! over every texel `t` of positive weight, `w_t` its centre direction (probe rotation
//! applied), `E_t = L_t Omega_t x intensity` its irradiance at normal incidence (W/m^2 for
//! a probe in W/(m^2 sr); `Omega_t` the exact texel solid angle,
//! [`crate::conventions::probe_texel_solid_angle`]). A cluster `C` of texels is shaded as
//! one light: its representative direction `w_C` (the luminance-weighted mean direction of
//! its texels, "Why the mean direction" below) carrying the cluster's total irradiance
//! `E_C = sum_{t in C} E_t`:
//! `L_C = f(w_C, wo) cos(polar_C) E_C`. Both `L_C` and the true sum over `C` lie in
//! `[0, B_C]` with `B_C = max_{w in cone(C)} f(w, wo) cos(polar) x E_C` (RGB), so `B_C`
//! bounds the cluster's error (the paper's `M_C G_C V_C I_C` bound, with no visibility
//! term: a distant environment is unoccluded here, as in every method of this renderer).
//! The material factor of `B_C` is [`crate::material::cone_bound`] (a function of the
//! closed material enum: derivations there).
//!
//! # The cut (per pixel, [`crate::shade`]; shared by squares of pixels on the fast path,
//! with a bound widened over the square, `src/shade/lightcuts/tile.rs`)
//! Start from the root; keep a max-heap of the cut's clusters keyed by the luminance of
//! `B_C` ([`crate::env::LUMINANCE_WEIGHTS`]), ties broken by the lower node index; replace
//! the top by its two children while its bound exceeds `cut_error` x the luminance of the
//! pixel's current estimate `sum_C L_C` and the cut has fewer than `cut_max` clusters. A
//! single texel is exact (bound 0). Deterministic and noise-free: the same cut for the same
//! pixel on any thread. Unlike the paper (2%, a perceptual threshold, representatives
//! chosen at random for an unbiased estimate), the default is 1% and the representative is
//! fixed, so the result is a deterministic function of the scene.
//!
//! # Why the mean direction
//! Each cluster's error is bounded by 1% of the pixel, but a cut holds hundreds of
//! clusters, so what keeps the *sum* accurate is that their errors do not add up. With the
//! brightest texel as the representative (Lightcuts' choice, made unbiased there by picking
//! it at random) a fixed choice errs to first order in the cluster's size, with the sign of
//! `f`'s slope, coherently over neighbouring clusters: measured on a 32 x 32 Blinn-Phong
//! (exponent 200) sphere under city, 3.7% relative RMSE at a mean cut of 248. The weighted
//! mean direction is the midpoint rule of the cluster's integral, exact to first order:
//! 0.68% at a mean cut of 251 on the same sphere. It is used when it lies inside the
//! bounding cone (always for a cone narrower than a hemisphere, which is convex), so the
//! estimate stays within `[0, B_C]`; otherwise the brightest texel.
//!
//! # The tree ([`LightTree`])
//! A binary tree over every texel of positive weight (a 512 x 256 probe: ~131k leaves,
//! ~262k nodes; a 4096 x 2048 one: 8.4 M leaves), built top-down once per scene and probe
//! (no cache): a cluster's texels are ordered along the largest extent of their
//! directions' bounding box and split at the luminance-weighted median (a selection, not a
//! sort), so a bright texel (the sun, a studio lamp) gets a cluster of its own within a few
//! levels; clusters of at least 2^15 texels on each side are split over two rayon tasks.
//! Each node stores (arrays of one value per node) its total irradiance and its
//! representative direction; each interior node a bounding cone (axis: the normalised
//! centre of the directions' box; half angle: the largest angle to a member, its cosine
//! lowered by [`tree::CONE_SLACK`]); a leaf, exact, needs none. About 56 bytes per texel,
//! nothing per texel beside the tree while it is built (directions, powers and weights are
//! computed from the probe's texels when needed): docs/environment-methods.md has the
//! build's time and memory per probe size.

pub mod tree;

pub use tree::LightTree;

use crate::env::schema::EnvSpec;
use crate::env::LoadReport;
use crate::error::Result;
use crate::material::cone_bound::BoundFault;
use std::path::Path;

/// A scene's light cuts: the tree and the cut's parameters (`[env] cut_error`, `cut_max`).
#[derive(Clone, Debug)]
pub struct LightCuts {
    pub tree: LightTree,
    /// Largest error bound of a cluster, relative to the pixel's estimate (luminance).
    pub cut_error: f32,
    /// Largest number of clusters in a pixel's cut.
    pub cut_max: usize,
    /// A seeded fault of the cluster bound (tests only).
    #[doc(hidden)]
    pub fault: BoundFault,
    /// A seeded fault of the tile bound of the shared cuts (tests only).
    #[doc(hidden)]
    pub tile_fault: TileFault,
}

/// A seeded fault of the tile path's bound (`crate::shade`, tests only): what the tests
/// must catch.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TileFault {
    #[default]
    None,
    /// The cluster cone not widened by the tile's frame and view spread: the bound at the
    /// tile's central frame and view only.
    NoWidening,
}

/// What [`prepare_lightcuts`] made.
#[derive(Clone, Debug)]
pub struct PreparedLightCuts {
    pub cuts: LightCuts,
    /// The probe loader's report.
    pub report: LoadReport,
}

/// Loads the probe of `spec` (relative to `base`; rotation and cleaning as every method
/// loads it, [`EnvSpec::load_options`]) and builds its light tree, texel radiance times
/// `spec.intensity`; `progress` counts the build ([`LightTree::build_with_progress`]).
/// Errors name the file or the field ([`EnvSpec::check`]).
pub fn prepare_lightcuts(
    spec: &EnvSpec,
    base: &Path,
    progress: &crate::progress::Progress,
) -> Result<PreparedLightCuts> {
    spec.check()?;
    let path = base.join(&spec.file);
    crate::image_io::check_regular_file(
        &path,
        crate::env::probe::MAX_PROBE_FILE_BYTES,
        "light probe",
    )
    .map_err(|e| crate::error::Error::Message(e.to_string()))?;
    let (probe, report) = crate::env::probe::load_probe(&path, &spec.load_options())?;
    Ok(PreparedLightCuts {
        cuts: LightCuts {
            tree: LightTree::build_with_progress(&probe, spec.intensity, progress),
            cut_error: spec.cut_error,
            cut_max: spec.cut_max,
            fault: BoundFault::None,
            tile_fault: TileFault::None,
        },
        report,
    })
}

#[cfg(test)]
mod tests;
