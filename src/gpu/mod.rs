//! The wgpu renderer (cargo feature `gpu`): the scene the CPU path renders, drawn by the
//! GPU's rasterizer and shaded per fragment, as a second, independent implementation that
//! the CPU oracle checks (`brdfkit golden check --device gpu`, docs/gpu.md).
//!
//! Design rule: the GPU side shares the *scene* with the CPU path (the resolved
//! [`Scene`]: mesh, camera, lights, material, render settings) and the image types and
//! writers, and nothing of the CPU renderer's arithmetic: the WGSL in `shaders/` is written
//! from the thesis and the conventions of [`crate::conventions`] (each file says which
//! section), not translated from [`crate::shade`] or [`crate::kernel`]. Visibility is the
//! GPU's own (its rasterization rules and depth test), so edge pixels may differ from the
//! CPU's fixed-point rasterizer; the golden check's FLIP bounds absorb that, not exact bits.
//! Nothing assumes a particular adapter: every size a scene needs is checked against the
//! limits the adapter reports ([`adapter::Gpu::limits`]), with a one-line error naming the
//! limit.
//!
//! Layout, one concept per file:
//! - `adapter.rs`: finding an adapter, opening a device with the adapter's own limits;
//! - `upload.rs`: the scene packed into GPU buffers (uniforms, vertices, lights, the
//!   material's table, the environment's transfer table or reflection-space table) and
//!   checked against those limits;
//! - `shaders/*.wgsl`: conventions (frame, angles, GL texel filtering), BRDF models, real
//!   SH, the frame (vertex and fragment entry points), and the transfer table's term
//!   (`transfer.wgsl`: `T` bilinear at the pixel's normal on the grid of
//!   [`crate::env::transfer`], dotted with the coefficients the fragment looked up at its
//!   view), and the reflection table's term (`reflection.wgsl`: the lobes' Fourier series in
//!   psi bilinear over the octahedral vertices around the reflected direction and linear
//!   between the view-angle slices, each vertex's psi in its own chart, plus the diffuse
//!   term bilinear at the normal, all in the probe's frame; [`crate::env::reflection`]);
//! - `pipeline.rs`: the shader assembled, the render pipeline, one draw;
//! - `readback.rs`: the float render target copied back into an [`Image`];
//! - `fault.rs`: the seeded faults that show the golden check catches a broken port.
//!
//! What it renders: Lambert, Phong, Blinn-Phong, SH data sets (nearest and bilinear
//! coefficient lookup), D-BRDF and Lambert + D-BRDF, under point and directional lights and
//! delta-light sets from probes (`[env] method = "lights"`), and SH data sets and Lambert
//! under transfer tables (`[env] method = "transfer"`: the table's term per pixel, once,
//! plus its brightest texels, which are in the scene's lights), and the isotropic models
//! among them (Blinn-Phong, Phong, isotropic D-BRDFs) under reflection-space tables
//! (`[env] method = "reflection"`, the table path: its term per pixel, once, plus its
//! exact lights), on the f32 path. It also writes the debug outputs of [`crate::aov`] but
//! `coverage`. Not: Ashikhmin-Shirley, MERL tables, `[env] method = "lightcuts"` (an
//! adaptive cut of a light tree refined per pixel; on a GPU use `transfer` or a light set),
//! and the reflection method's filtered importance sampling of anisotropic D-BRDFs;
//! [`unsupported`] names the reason, which callers report.

mod adapter;
mod fault;
mod pipeline;
mod readback;
mod upload;

pub use adapter::{adapter_name, Gpu};
pub use fault::Faults;

use crate::aov::Aov;
use crate::error::Result;
use crate::image_io::Image;
use crate::material::Material;
use crate::scene::Scene;

/// Why the GPU renderer cannot render `scene` (with debug output `aov`), or `None` when it
/// can.
pub fn unsupported(scene: &Scene, aov: Option<Aov>) -> Option<String> {
    if aov == Some(Aov::Coverage) {
        return Some(
            "debug output 'coverage' counts every triangle over a pixel before the depth test, \
             which the GPU's depth-tested draw does not"
                .into(),
        );
    }
    if let Some(why) = scene.environment.gpu_unsupported() {
        return Some(why.into());
    }
    match &scene.material {
        Material::AshikhminShirley(_) | Material::Merl(_) | Material::Rgl(_) => Some(format!(
            "material '{}' is not implemented on the GPU",
            scene.material.name()
        )),
        Material::Lambert(_)
        | Material::Phong(_)
        | Material::BlinnPhong(_)
        | Material::DBrdf(_)
        | Material::LambertDbrdf(_)
        | Material::Sh(_) => None,
    }
}

impl Gpu {
    /// Renders `scene`'s beauty image (linear radiance, the CPU path's units) with the
    /// seeded `faults` (none for a real render). Errors: a scene [`unsupported`] names, a
    /// scene that needs more than the adapter's limits, a device error.
    pub fn render(&self, scene: &Scene, faults: Faults) -> Result<Image> {
        self.render_aov(scene, None, faults)
    }

    /// [`Gpu::render`], or with `aov` that debug output ([`crate::aov`]: the same values,
    /// computed by the fragment shader; `coverage` is [`unsupported`]).
    pub fn render_aov(&self, scene: &Scene, aov: Option<Aov>, faults: Faults) -> Result<Image> {
        if let Some(why) = unsupported(scene, aov) {
            return Err(crate::error::Error::Message(format!("--device gpu: {why}")));
        }
        let up = upload::Uploads::new(self, scene, aov, faults)?;
        let target = pipeline::draw(self, &up)?;
        readback::read_image(self, &target, scene.render.width, scene.render.height)
    }
}
