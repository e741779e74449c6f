//! Frame preparation: everything shading decides once per frame, before any pixel.
//!
//! Design rule: per-frame decisions live here and nowhere else. [`FramePrep::new`] drops
//! negligible lights and the SH bands a material does not need, within the bounds of
//! [`crate::kernel::skip`], lays the directional lights out for the kernels
//! ([`DirLights`]), and chooses the instruction set once ([`Dispatch::choose`]), so the
//! image does not depend on the thread count. The caller's choices (instruction set, light
//! culling, a seeded [`KernelFault`]) come in through [`ShadeOptions`] and are read-only
//! afterwards; tests read the other fields to see what was decided.

use super::transfer::TransferTerm;
use super::{KernelFault, ShadeOptions};
use crate::brdf::Brdf;
use crate::conventions::FrameRule;
use crate::kernel::models::LaneModel;
use crate::kernel::{cluster::DirLights, sh::ShRecurrence, skip};
use crate::lanes::{Dispatch, LANES};
use crate::light::Light;
use crate::scene::Scene;
use crate::sh::dataset::ShDataset;
use glam::Vec3;
use std::borrow::Cow;

/// Everything shading decides once per frame.
pub struct FramePrep<'a> {
    pub brdf: &'a dyn Brdf,
    pub dir: DirLights,
    /// The dropped directional lights ([`skip::LightDrop::removed`]), laid out for the
    /// kernels: shaded at the pixels [`skip::needs_restore`] picks
    /// ([`FramePrep::shade_dropped`]).
    pub dropped_dir: DirLights,
    /// Every chunk of `dropped_dir` (no culling for the restored lights).
    pub(crate) dropped_chunks: Vec<u32>,
    pub points: Vec<Light>,
    /// The SH data set shaded (truncated to its effective bands when the band skip is on)
    /// and its recurrence constants.
    pub sh: Option<(Cow<'a, ShDataset>, ShRecurrence)>,
    pub eye: Vec3,
    /// Per-tile normal-cone culling of light chunks ([`ShadeOptions::cull_lights`]).
    pub(crate) cull_lights: bool,
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
    /// The instruction set of the kernels, chosen once per frame from
    /// [`ShadeOptions::kernel`] or else the scene's `render.kernel` ([`Dispatch::choose`]);
    /// the same for every tile and thread, so the image does not depend on the thread count.
    pub(crate) dispatch: Dispatch,
    /// **Test only**: a seeded fault of the SH kernel path ([`KernelFault`]), for the
    /// mutation tests that show [`crate::kernel::SH_KERNEL_TOLERANCE`] catches real faults
    /// (tests/integration/kernel_mutation.rs), from [`ShadeOptions`]'s hidden `fault` field;
    /// no scene setting or command-line option reaches it. Tested once per pixel (a
    /// predictable branch beside the pixel's lights x `bands^2` x 3 FMAs; on the packed path,
    /// twice per pixel and once
    /// per batch), never per light or term.
    pub(crate) fault: Option<KernelFault>,
    /// The scene's transfer table (`[env] method = "transfer"`) and the coefficients its
    /// term dots with, which the fast path adds per pixel beside the lights
    /// (`pixel.rs`); `None` otherwise. The scalar oracle and the f64 path add it in a
    /// pass of their own (`transfer.rs`).
    pub(crate) transfer: Option<TransferTerm<'a>>,
    /// How every pixel's shading frame is chosen ([`ShadeOptions::frame_rule`]: the
    /// material's [`crate::material::Material::frame_rule`]).
    pub rule: FrameRule,
}

impl<'a> FramePrep<'a> {
    /// Prepares a frame of `scene` with the default [`ShadeOptions`]
    /// (what [`crate::shade::shade`] prepares), to see what the frame decides.
    pub fn new(scene: &'a Scene) -> FramePrep<'a> {
        FramePrep::with_options(scene, &ShadeOptions::default())
    }

    /// Prepares a frame of `scene`, applying the scene's skips (`render.drop_lights`,
    /// `render.band_skip`; see [`crate::kernel::skip`]) and the caller's choices `opts`.
    ///
    /// # Panics
    /// If the kernel path (`opts.kernel`, else the scene's `render.kernel`) names a path
    /// this CPU cannot run: [`Scene::resolve`] refuses such a scene, so only a scene built
    /// in code (or such options) can get here.
    pub(crate) fn with_options(scene: &'a Scene, opts: &ShadeOptions) -> FramePrep<'a> {
        let brdf = scene.material.as_brdf();
        let (fraction, max_f_cos) = match brdf.max_cosine_weighted() {
            Some(m) => (scene.render.drop_lights, m),
            None => (0.0, Vec3::ZERO),
        };
        let dropped = skip::drop_weak_lights(&scene.delta_lights(), fraction, max_f_cos);
        let dir = DirLights::from_lights(&dropped.kept);
        let dropped_dir = DirLights::from_lights(&dropped.removed);
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
            dropped_chunks: (0..dropped_dir.chunks() as u32).collect(),
            dropped_dir,
            points: scene
                .delta_lights()
                .iter()
                .copied()
                .filter(|l| matches!(l, Light::Point { .. }))
                .collect(),
            model: LaneModel::of(&scene.material),
            dispatch: {
                let kernel = opts.kernel.unwrap_or(scene.render.kernel);
                Dispatch::choose(kernel).unwrap_or_else(|| {
                    panic!("kernel {}: not available on this CPU", kernel.name())
                })
            },
            fault: opts.fault,
            transfer: TransferTerm::of(scene),
            rule: opts.frame_rule(scene),
            sh,
            eye: scene.camera.position,
            cull_lights: opts.cull_lights,
            chunk_live,
            lights_total: scene
                .delta_lights()
                .iter()
                .filter(|l| matches!(l, Light::Directional { .. }))
                .count(),
            dropped,
        }
    }

    /// The instruction set the kernels run on (see the `dispatch` field).
    pub fn dispatch(&self) -> Dispatch {
        self.dispatch
    }

    /// Whether the fast path's tile loop adds a transfer term (then every pixel takes the
    /// per-pixel path, which has the coefficients at hand).
    #[inline(always)]
    pub(super) fn has_transfer(&self) -> bool {
        self.transfer.is_some()
    }
}
