//! Frame preparation: everything shading decides once per frame, before any pixel.
//!
//! Design rule: per-frame decisions live here and nowhere else. [`FramePrep::new`] drops
//! negligible lights and the SH bands a material does not need, within the bounds of
//! [`crate::kernel::skip`], lays the directional lights out for the kernels
//! ([`DirLights`]), and chooses the instruction set once ([`Dispatch::choose`]), so the
//! image does not depend on the thread count. Its `pub` fields are how tests switch an
//! optimisation off (or seed a [`KernelFault`]); nothing else writes them.

use super::KernelFault;
use crate::brdf::Brdf;
use crate::kernel::lanes::{Dispatch, LANES};
use crate::kernel::models::LaneModel;
use crate::kernel::{cluster::DirLights, sh::ShRecurrence, skip};
use crate::light::Light;
use crate::scene::Scene;
use crate::sh::dataset::ShDataset;
use glam::Vec3;
use std::borrow::Cow;

/// Everything shading decides once per frame.
pub struct FramePrep<'a> {
    pub brdf: &'a dyn Brdf,
    pub dir: DirLights,
    pub points: Vec<Light>,
    /// The SH data set shaded (truncated to its effective bands when the band skip is on)
    /// and its recurrence constants.
    pub sh: Option<(Cow<'a, ShDataset>, ShRecurrence)>,
    pub eye: Vec3,
    /// Per-tile normal-cone culling of light chunks (on by default; it changes no bit, and
    /// a test proves it by turning it off).
    pub cull_lights: bool,
    /// Live (non-padding, non-black) lights per chunk of `dir`, for the work counters.
    pub chunk_live: Vec<u32>,
    /// Directional lights in the scene, before dropping.
    pub lights_total: usize,
    /// What dropping negligible lights removed ([`skip::drop_weak_lights`]); nothing when
    /// the scene's `render.drop_lights` is 0 or the material has no `|f cos|` bound.
    pub dropped: skip::LightDrop,
    /// Bands stored in the SH data set and bands shaded (0, 0 for other materials).
    pub sh_bands: (usize, usize),
    /// The material's lane form ([`LaneModel::of`]), used when it is not an SH data set.
    pub model: LaneModel<'a>,
    /// The instruction set of the kernels, chosen once per frame from the scene's
    /// `render.kernel` ([`Dispatch::choose`]); the same for every tile and thread, so the
    /// image does not depend on the thread count.
    pub dispatch: Dispatch,
    /// **Test only**: a seeded fault of the SH kernel path ([`KernelFault`]), for the
    /// mutation tests that show [`crate::kernel::SH_KERNEL_TOLERANCE`] catches real faults
    /// (tests/kernel_mutation.rs). Always `None` from [`FramePrep::new`]; no scene setting or
    /// command-line option reaches it. Tested once per pixel (a predictable branch beside
    /// the pixel's lights x `bands^2` x 3 FMAs; on the packed path, twice per pixel and once
    /// per batch), never per light or term.
    #[doc(hidden)]
    pub fault: Option<KernelFault>,
}

impl<'a> FramePrep<'a> {
    /// Prepares a frame of `scene`, applying the scene's skips (`render.drop_lights`,
    /// `render.band_skip`; see [`crate::kernel::skip`]).
    ///
    /// # Panics
    /// If the scene's `render.kernel` names a path this CPU cannot run: [`Scene::resolve`]
    /// refuses such a scene, so only a scene built in code can get here.
    pub fn new(scene: &'a Scene) -> FramePrep<'a> {
        let brdf = scene.material.as_brdf();
        let fraction = match brdf.max_cosine_weighted() {
            Some(_) => scene.render.drop_lights,
            None => 0.0,
        };
        let dropped = skip::drop_weak_lights(&scene.lights, fraction);
        let dir = DirLights::from_lights(&dropped.kept);
        let chunk_live = (0..dir.chunks())
            .map(|c| {
                (c * LANES..(c + 1) * LANES)
                    .filter(|&i| dir.er[i] != 0.0 || dir.eg[i] != 0.0 || dir.eb[i] != 0.0)
                    .count() as u32
            })
            .collect();
        let sh = scene.material.as_sh().map(|ds| {
            let keep = if scene.render.band_skip {
                ds.effective_bands()
            } else {
                ds.bands()
            };
            let ds = if keep < ds.bands() {
                Cow::Owned(ds.truncated(keep).expect("1 <= effective bands <= bands"))
            } else {
                Cow::Borrowed(ds)
            };
            let rec = ShRecurrence::new(ds.bands());
            (ds, rec)
        });
        FramePrep {
            brdf,
            sh_bands: match (scene.material.as_sh(), &sh) {
                (Some(full), Some((used, _))) => (full.bands(), used.bands()),
                _ => (0, 0),
            },
            dir,
            points: scene
                .lights
                .iter()
                .copied()
                .filter(|l| matches!(l, Light::Point { .. }))
                .collect(),
            model: LaneModel::of(&scene.material),
            dispatch: Dispatch::choose(scene.render.kernel).unwrap_or_else(|| {
                panic!(
                    "render.kernel = {}: not available on this CPU",
                    scene.render.kernel.name()
                )
            }),
            fault: None,
            sh,
            eye: scene.camera.position,
            cull_lights: true,
            chunk_live,
            lights_total: scene
                .lights
                .iter()
                .filter(|l| matches!(l, Light::Directional { .. }))
                .count(),
            dropped,
        }
    }
}
