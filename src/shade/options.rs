//! What a caller chooses about shading: the path (fast kernels, scalar f32 oracle, f64 path),
//! the instruction set, light culling, progress, and (tests only) a seeded kernel fault.
//!
//! Design rule: every shading choice a caller can make is a field here, passed to the one
//! entry point [`super::shade`]; nothing else reaches [`super::FramePrep`]. The scene's
//! `[render]` table holds the settings a scene file can carry (`precision`, `kernel`, the
//! skips); a field left `None` here follows the scene. [`ShadeOptions::default`] is what
//! `brdfkit render` does. The render-level settings (AOV, threads, stats) are
//! [`crate::render::RenderOptions`], which holds one of these; the two are split only so that
//! `shade` does not depend on `render` (or on `aov`).

use super::KernelFault;
use crate::conventions::FrameRule;
use crate::lanes::KernelPath;
use crate::material::Material;
use crate::progress::Progress;
use crate::scene::Precision;

/// Which arithmetic shades the beauty image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadingPath {
    /// The fast path: the kernels of [`crate::kernel`] in f32, with the scene's skips
    /// (`render.drop_lights`, `render.band_skip`) and per-tile light culling
    /// (`render.precision = "f32"`).
    Kernels,
    /// The scalar f32 oracle the kernels are tested against: [`super::shade_point`], the
    /// plain per-light loop over [`crate::brdf::Brdf::eval`], at every visible pixel; no
    /// kernel, no culling, but the same skips as [`ShadingPath::Kernels`] (the lights and
    /// SH bands [`super::FramePrep`] kept), so the two differ only by the kernel's
    /// arithmetic. Several times slower than the kernels.
    ScalarOracle,
    /// The f64 path with no skips: every light of the scene and every SH band (the scene's
    /// `render.drop_lights` and `render.band_skip` are ignored), no culling; frames,
    /// directions, the BRDF ([`crate::brdf::Brdf::eval_f64`]) and the light sum in f64,
    /// rounded to f32 once per pixel (`render.precision = "f64"`). On a scene whose light set
    /// is the full probe, this is the converged reference
    /// ([`crate::render::RenderOptions::converged_reference`]). Several times slower.
    F64NoSkips,
}

impl ShadingPath {
    /// The path a scene's `render.precision` names.
    pub fn of_precision(p: Precision) -> ShadingPath {
        match p {
            Precision::F32 => ShadingPath::Kernels,
            Precision::F64 => ShadingPath::F64NoSkips,
        }
    }
}

/// Shading choices for [`super::shade`]; see the module doc. `Default` is what
/// `brdfkit render` does: the scene's precision and kernel, culling on, no progress shown.
#[derive(Clone, Debug)]
pub struct ShadeOptions {
    /// The shading path; `None` follows the scene's `render.precision`
    /// ([`ShadingPath::of_precision`]).
    pub path: Option<ShadingPath>,
    /// The instruction set of the kernels ([`ShadingPath::Kernels`] only); `None` follows the
    /// scene's `render.kernel`. Every path gives the same bits; this changes only speed.
    ///
    /// # Panics
    /// [`super::shade`] panics when this CPU cannot run the path named (here or in a scene
    /// built in code; [`crate::scene::Scene::resolve`] refuses such a scene file).
    pub kernel: Option<KernelPath>,
    /// Per-tile normal-cone culling of directional-light chunks ([`ShadingPath::Kernels`]
    /// only). On by default; it changes no bit, and tests prove it by turning it off.
    pub cull_lights: bool,
    /// Where the tile loop counts finished tiles (every tile of the frame, empty ones
    /// included, once each: the caller sizes the bar with [`crate::render::tile_count`]).
    /// Hidden by default. Counting changes no bit of the image.
    pub progress: Progress,
    /// **Test only**: a fault seeded into the SH kernel path ([`KernelFault`];
    /// [`ShadingPath::Kernels`] only), for the mutation tests that show
    /// [`crate::kernel::SH_KERNEL_TOLERANCE`] catches real faults. No scene setting or
    /// command-line option reaches it.
    #[doc(hidden)]
    pub fault: Option<KernelFault>,
    /// **Test only**: what the frame-invariance test does to the shading frames
    /// ([`FrameCheck`]). No scene setting or command-line option reaches it.
    #[doc(hidden)]
    pub frame_check: FrameCheck,
}

/// **Test only**: the shading-frame changes of the test that an isotropic material's image
/// does not depend on the tangent frame (tests/integration/frame_invariance.rs).
#[doc(hidden)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrameCheck {
    /// The material's own frame rule.
    #[default]
    None,
    /// The world-up frame turned by a pseudo-random angle per pixel before the material's
    /// rule applies ([`crate::conventions::FrameRule::scramble`]).
    Scramble,
    /// The seeded fault the test must catch: scrambled, and the material's view alignment
    /// left out (the frame then stays scrambled).
    ScrambleUnaligned,
    /// The world-up frame for every material, as before isotropic tabulated materials
    /// were aligned to the view (the pictures of the lid before and after).
    Unaligned,
}

impl Default for ShadeOptions {
    fn default() -> ShadeOptions {
        ShadeOptions {
            path: None,
            kernel: None,
            cull_lights: true,
            progress: Progress::hidden(),
            fault: None,
            frame_check: FrameCheck::None,
        }
    }
}

/// [`Material::frame_rule`] for `material` on `mesh`: the mesh-tangent rule becomes
/// [`FrameRule::UP`] where the mesh has no tangents (every pixel would fall back to the
/// world-up frame; the kernels' lane path then builds those frames in lanes).
pub fn effective_frame_rule(material: &Material, mesh: &crate::mesh::Mesh) -> FrameRule {
    let rule = material.frame_rule();
    if rule.mesh_tangent && mesh.tangents.is_empty() {
        FrameRule {
            mesh_tangent: false,
            ..rule
        }
    } else {
        rule
    }
}

impl ShadeOptions {
    /// These options on shading path `path` (overriding the scene's `render.precision`).
    pub fn with_path(mut self, path: ShadingPath) -> ShadeOptions {
        self.path = Some(path);
        self
    }

    /// The frame rule the pixels of `scene` are shaded with: its material's
    /// ([`Material::frame_rule`]; the mesh-tangent rule is the world-up one on a mesh
    /// without tangents, which gives the same frames), changed only by the test-only
    /// [`ShadeOptions::frame_check`].
    pub fn frame_rule(&self, scene: &crate::scene::Scene) -> FrameRule {
        let rule = effective_frame_rule(&scene.material, &scene.mesh);
        match self.frame_check {
            FrameCheck::None => rule,
            FrameCheck::Scramble => FrameRule {
                scramble: true,
                ..rule
            },
            FrameCheck::ScrambleUnaligned => FrameRule {
                scramble: true,
                view_azimuth: None,
                ..rule
            },
            FrameCheck::Unaligned => FrameRule::UP,
        }
    }

    /// The path these options shade `scene` with: [`ShadeOptions::path`] or the scene's
    /// `render.precision`.
    pub fn path_for(&self, scene: &crate::scene::Scene) -> ShadingPath {
        self.path
            .unwrap_or_else(|| ShadingPath::of_precision(scene.render.precision))
    }
}
