//! The reflection term of an environment ([`crate::env::reflection`]):
//! `L_o += table(n, v)` per pixel, the radiance of every texel but the brightest (which the
//! lights' kernels shade as the environment's exact lights); for an anisotropic D-BRDF the
//! term is filtered importance sampling instead ([`crate::env::reflection::filtered`]: a
//! fixed set of half vectors per pixel, each a lookup in the residual's pyramid), in the
//! same pass.
//!
//! Design rule: one lookup per pixel, whatever the probe's size or the lobe's width, on
//! every shading path in a plain pass of its own after the lights ([`add_reflection`]). The
//! surface, world normal and lifted view are those of every other path (`gbuffer.rs`,
//! [`super::frame_and_view`]); the material is not evaluated (the table holds it), and the
//! tangent does not matter (the table is of an isotropic material). f32 on every path (the
//! table is f32): the same bits for any thread count and tile size (each pixel adds one
//! value computed from its own surface alone). The filtered sampler needs the tangent:
//! its pixels take the material's frame ([`effective_frame_rule`], the mesh's tangent for
//! an anisotropic model) and the lifted local view, as the lights' kernels do.

use super::frame_and_view;
use super::options::effective_frame_rule;
use super::traverse::{for_each_tile, for_each_visible, Pass};
use crate::conventions::FrameRule;
use crate::env::reflection::ReflectionTerm;
use crate::image_io::Image;
use crate::raster::VisBuffer;
use crate::scene::Scene;

/// Adds the term of `term` to every visible pixel of `image` (rendered from `scene` and
/// `vis`), in a pass of its own, parallel over bands of one tile row.
pub(super) fn add_reflection(
    scene: &Scene,
    vis: &VisBuffer,
    term: &ReflectionTerm,
    image: &mut Image,
) {
    let eye = scene.camera.position;
    // The table is of an isotropic material (any tangent will do); the sampler reads the
    // material's own frame.
    let rule = match term {
        ReflectionTerm::Table(_) => FrameRule::UP,
        ReflectionTerm::Filtered(_) => effective_frame_rule(&scene.material, &scene.mesh),
    };
    for_each_tile(
        image,
        vis,
        Pass::Adds,
        None,
        || (),
        |_, rect, band| {
            for_each_visible(&scene.mesh, vis, rect, rect.y0, |p| {
                let (frame, wo) = frame_and_view(&p.surface, eye, &rule);
                band[p.at] += match term {
                    ReflectionTerm::Table(table) => table.radiance(frame.n, frame.to_world(wo)),
                    ReflectionTerm::Filtered(sampler) => sampler.radiance(&frame, wo),
                };
            });
        },
    );
}
