//! The one entry point of shading, [`shade`], and what it returns ([`Shaded`]); its form
//! into a caller's image and buffers kept across frames, [`shade_into`] (what `shade` runs).
//!
//! Design rule: one function for every shading path; the caller's choices are
//! [`ShadeOptions`] (path, instruction set, culling, progress). The frame's decisions are made
//! once ([`FramePrep`]) for the paths that use them (the kernels, the scalar oracle); the f64
//! path uses none of them (no skips).

use super::f64_path::shade_f64_no_skips;
use super::lightcuts::{add_lightcuts, CutStats};
use super::reflection::add_reflection;
use super::scalar_oracle::shade_scalar_oracle;
use super::tile::{shade_kernels, Pass, ShadeScratch};
use super::transfer::{add_transfer, fits};
use super::{FramePrep, ShadeCounts, ShadeOptions, ShadingPath};
use crate::conventions::FrameRule;
use crate::image_io::Image;
use crate::lanes::Dispatch;
use crate::raster::VisBuffer;
use crate::scene::Scene;

/// A shaded image and what shading did.
#[derive(Clone, Debug)]
pub struct Shaded {
    /// Linear radiance per pixel (background black).
    pub image: Image,
    /// What shading did ([`ShadeReport`]).
    pub report: ShadeReport,
}

/// What one shading of a frame did: the path, the work counted, the lights and bands
/// dropped, the light cuts.
#[derive(Clone, Debug)]
pub struct ShadeReport {
    /// The path that shaded it.
    pub path: ShadingPath,
    /// Work done by the kernels' tile loop ([`ShadingPath::Kernels`]; all zero otherwise).
    pub counts: ShadeCounts,
    /// Lights in the scene: the directional ones (before dropping) on the kernels and the
    /// scalar oracle, every light on the f64 path.
    pub lights: usize,
    /// Directional lights dropped as negligible (0 on the f64 path).
    pub lights_dropped: usize,
    /// Dropped irradiance over total irradiance, largest over the channels (0 if none).
    pub dropped_fraction: f32,
    /// SH bands stored in the material's data set and bands shaded (0, 0 if not SH or on
    /// the f64 path).
    pub sh_bands: (usize, usize),
    /// Light-cut sizes when the scene has light cuts (`[env] method = "lightcuts"`; all
    /// zero otherwise).
    pub cuts: CutStats,
}

/// [`shade_into`] a new image with new buffers.
pub fn shade(scene: &Scene, vis: &VisBuffer, opts: &ShadeOptions) -> Shaded {
    let mut image = Image::default();
    let report = shade_into(scene, vis, opts, &mut image, &ShadeScratch::default());
    Shaded { image, report }
}

/// Shades every visible pixel of `vis` (rasterized from `scene`) into `image` on the path `opts` chooses
/// ([`ShadeOptions::path_for`]): the kernels, the scalar f32 oracle or the f64 path with no
/// skips. Every tile of the frame is counted once into `opts.progress`. When the scene has
/// a transfer table (`[env] method = "transfer"`), its term is added to every visible
/// pixel, on every path: in the tile loop beside the lights on the kernels, in a second
/// plain pass on the others (`transfer.rs`); a reflection table's term (`[env] method =
/// "reflection"`) in a plain pass on every path (`reflection.rs`); the light-cut term of a scene with light
/// cuts (`[env] method = "lightcuts"`, `lightcuts.rs`) is added after the lights on every path.
///
/// The image is `image`, resized to `vis`'s frame and every pixel rewritten (black where
/// nothing is visible), whatever it held before; the workers' buffers are `scratch`'s,
/// emptied as they are lent. Called again with the same `image` and `scratch` for a frame
/// of the same size, it allocates no image and no worker buffers: a caller drawing frame
/// after frame (`render::FrameContext`) touches no new memory there. The bits are those of
/// [`shade`] with a new image and new buffers.
///
/// # Panics
/// If the kernel path chosen (by `opts.kernel` or the scene's `render.kernel`) is not
/// available on this CPU; [`Scene::resolve`] refuses such a scene file.
pub fn shade_into(
    scene: &Scene,
    vis: &VisBuffer,
    opts: &ShadeOptions,
    image: &mut Image,
    scratch: &ShadeScratch,
) -> ShadeReport {
    // A new image is allocated black, its pages untouched until written: the lights' pass
    // clears nothing then. A kept one is cleared band by band as it is shaded.
    let pass = if (image.width, image.height) != (vis.width, vis.height) {
        *image = Image::new(vis.width, vis.height);
        Pass::WritesOnBlack
    } else {
        Pass::Writes
    };
    let rule = opts.frame_rule(scene);
    let mut report = shade_lights(scene, vis, opts, &rule, image, pass, scratch);
    if let Some(table) = scene.environment.transfer_table() {
        assert!(
            fits(table, &scene.material),
            "the scene's transfer table does not fit its material"
        );
        // The fast path added the term in its tile loop (`pixel.rs`); the others add it in
        // a pass of their own.
        if report.path != ShadingPath::Kernels {
            add_transfer(scene, vis, table, image, &rule);
        }
    }
    if let Some(table) = scene.environment.reflection_term() {
        // Every path adds it in a pass of its own, after the lights (`reflection.rs`).
        add_reflection(scene, vis, table, image);
    }
    if let Some(cuts) = scene.environment.light_cuts() {
        // The kernels' path shares one cut per tile; the scalar oracle keeps the per-pixel
        // cut as the reference (`lightcuts/tile.rs`).
        let shared = (report.path == ShadingPath::Kernels).then(|| {
            let kernel = opts.kernel.unwrap_or(scene.render.kernel);
            Dispatch::choose(kernel)
                .unwrap_or_else(|| panic!("kernel {}: not available on this CPU", kernel.name()))
        });
        report.cuts = add_lightcuts(scene, vis, cuts, image, shared, &rule);
    }
    report
}

/// [`shade_into`] without the transfer term: the scene's lights only, written into every
/// pixel of `image` (of `vis`'s size).
fn shade_lights(
    scene: &Scene,
    vis: &VisBuffer,
    opts: &ShadeOptions,
    rule: &FrameRule,
    image: &mut Image,
    pass: Pass,
    scratch: &ShadeScratch,
) -> ShadeReport {
    let path = opts.path_for(scene);
    if path == ShadingPath::F64NoSkips {
        shade_f64_no_skips(scene, vis, &opts.progress, rule, image, pass);
        return ShadeReport {
            path,
            counts: ShadeCounts::default(),
            lights: scene.delta_lights().len(),
            lights_dropped: 0,
            dropped_fraction: 0.0,
            sh_bands: (0, 0),
            cuts: CutStats::default(),
        };
    }
    let prep = FramePrep::with_options(scene, opts);
    let counts = match path {
        ShadingPath::Kernels => {
            shade_kernels(&prep, scene, vis, &opts.progress, image, pass, scratch)
        }
        _ => {
            shade_scalar_oracle(&prep, scene, vis, &opts.progress, image, pass);
            ShadeCounts::default()
        }
    };
    let d = &prep.dropped;
    ShadeReport {
        path,
        counts,
        lights: prep.lights_total,
        lights_dropped: d.dropped,
        dropped_fraction: (0..3)
            .filter(|&c| d.total_irradiance[c] > 0.0)
            .map(|c| d.dropped_irradiance[c] / d.total_irradiance[c])
            .fold(0.0, f32::max),
        sh_bands: prep.sh_bands,
        cuts: CutStats::default(),
    }
}
