//! The reflection-table term of an environment ([`crate::env::reflection`]):
//! `L_o += table(n, v)` per pixel, the radiance of every texel but the brightest (which the
//! lights' kernels shade as the environment's exact lights).
//!
//! Design rule: one lookup per pixel, whatever the probe's size or the lobe's width, on
//! every shading path in a plain pass of its own after the lights ([`add_reflection`]). The
//! surface, world normal and lifted view are those of every other path (`gbuffer.rs`,
//! [`super::frame_and_view`]); the material is not evaluated (the table holds it), and the
//! tangent does not matter (the table is of an isotropic material). f32 on every path (the
//! table is f32): the same bits for any thread count and tile size (each pixel adds one
//! value computed from its own surface alone).

use super::frame_and_view;
use super::traverse::{for_each_tile, for_each_visible, Pass};
use crate::conventions::FrameRule;
use crate::env::reflection::ReflectionTable;
use crate::image_io::Image;
use crate::raster::VisBuffer;
use crate::scene::Scene;

/// Adds the term of `table` to every visible pixel of `image` (rendered from `scene` and
/// `vis`), in a pass of its own, parallel over bands of one tile row.
pub(super) fn add_reflection(
    scene: &Scene,
    vis: &VisBuffer,
    table: &ReflectionTable,
    image: &mut Image,
) {
    let eye = scene.camera.position;
    for_each_tile(
        image,
        vis,
        Pass::Adds,
        None,
        || (),
        |_, rect, band| {
            for_each_visible(&scene.mesh, vis, rect, rect.y0, |p| {
                let (frame, wo) = frame_and_view(&p.surface, eye, &FrameRule::UP);
                band[p.at] += table.radiance(frame.n, frame.to_world(wo));
            });
        },
    );
}
