//! The transfer-table term of an environment ([`crate::env::transfer`]):
//! `L_o += sum_k c_k(wo) T_k(n)` per colour.
//!
//! Design rule: per pixel, one table lookup at the normal and one dot product with the
//! material's coefficients at the view, whatever the number of texels behind the table.
//! Two forms of the same term:
//! - the fast path adds it in its tile loop, in the same place as the lights' radiance, on
//!   the surface, frame, view and coefficients `c(wo)` the lights already use
//!   ([`FramePrep::shade_surface`], [`TransferTerm`], SIMD lookup and dot by
//!   [`TransferTable::radiance_lanes`]): one surface per pixel;
//! - the scalar oracle and the f64 path add it in a second, plain pass over the image
//!   ([`add_transfer`]: `std` angles, [`crate::sh::dataset::ShDataset::lookup_coeffs`],
//!   [`TransferTable::radiance_with`]), the simple form the fast one is held to within
//!   [`crate::env::transfer::FAST_PATH_TOLERANCE`] (tests/integration/transfer_scene.rs).
//!
//! The surface, frame and lifted view are those of every other path (`gbuffer.rs`,
//! [`super::frame_and_view`] under the material's [`FrameRule`]); `c(wo)` is the data
//! set's filtered coefficient lookup, turned back into the table's world-up frame when the
//! material's frame is view-aligned ([`to_table_frame`]), or `albedo / pi` for Lambert. f32
//! on every path (the table is f32).

use super::frame_and_view;
use super::traverse::{for_each_tile, for_each_visible};
use crate::conventions::{hemi_texcoord, local_angles, FrameRule, ShadingFrame};
use crate::env::transfer::TransferTable;
use crate::image_io::Image;
use crate::material::Material;
use crate::raster::VisBuffer;
use crate::scene::Scene;
use crate::sh::dataset::MAX_BANDS;

/// The scalar oracle's and the f64 path's form (module doc): adds the transfer term of
/// `table` to every visible pixel of `image` (rendered from `scene` and `vis`), in a pass
/// of its own, parallel over bands of one tile row. Materials other than SH data
/// sets and Lambert add nothing ([`crate::scene::Scene::resolve`] refuses them).
pub(super) fn add_transfer(
    scene: &Scene,
    vis: &VisBuffer,
    table: &TransferTable,
    image: &mut Image,
    rule: &FrameRule,
) {
    let eye = scene.camera.position;
    let nt = table.terms();
    let buffers = || {
        (
            [0.0f32; 3 * MAX_BANDS * MAX_BANDS],
            [0.0f32; 3 * MAX_BANDS * MAX_BANDS],
        )
    };
    for_each_tile(image, vis, None, buffers, |(cbuf, tbuf), rect, band| {
        let c = &mut cbuf[..3 * nt];
        for_each_visible(&scene.mesh, vis, rect, rect.y0, |p| {
            match &scene.material {
                Material::Sh(ds) => {
                    let (frame, wo) = frame_and_view(&p.surface, eye, rule);
                    let (polar, azimuth) = local_angles(wo);
                    let (u, v) = hemi_texcoord(polar, azimuth);
                    ds.lookup_coeffs(u, v, ds.coeff_lookup, c);
                    if *rule != FrameRule::UP {
                        to_table_frame(c, ds.bands(), &frame);
                    }
                }
                Material::Lambert(m) => {
                    let k = m.albedo / std::f32::consts::PI;
                    c.copy_from_slice(&[k.x, k.y, k.z]);
                }
                Material::Phong(_)
                | Material::BlinnPhong(_)
                | Material::AshikhminShirley(_)
                | Material::DBrdf(_)
                | Material::LambertDbrdf(_)
                | Material::Merl(_)
                | Material::Rgl(_) => return,
            }
            band[p.at] += table.radiance_with(p.surface.normal, c, tbuf);
        });
    });
}

/// Coefficients `c` (`3 bands^2`, `[R.., G.., B..]`) looked up in the pixel's `frame` (turned
/// about the normal: [`crate::conventions`], "Frame of isotropic tabulated materials")
/// rewritten in place in the world-up frame [`ShadingFrame::from_normal`] of the same
/// normal, in which the table stores the environment ([`crate::env::transfer`], "Grid of
/// normals"): turned back by the angle between the two tangents
/// ([`crate::sh::rotate_about_z`]).
#[inline]
pub(super) fn to_table_frame(c: &mut [f32], bands: usize, frame: &ShadingFrame) {
    let up = ShadingFrame::from_normal(frame.n);
    let (cos, sin) = (frame.t.dot(up.t), frame.t.dot(up.b));
    crate::sh::rotate_about_z(c, bands, cos, sin);
}

/// Whether `table` can shade `material` (its basis has the material's term count).
pub(super) fn fits(table: &TransferTable, material: &Material) -> bool {
    match material {
        Material::Sh(ds) => table.terms() == ds.bands() * ds.bands(),
        Material::Lambert(_) => table.terms() == 1,
        Material::Phong(_)
        | Material::BlinnPhong(_)
        | Material::AshikhminShirley(_)
        | Material::DBrdf(_)
        | Material::LambertDbrdf(_)
        | Material::Merl(_)
        | Material::Rgl(_) => false,
    }
}

/// The transfer term as the fast path adds it (module doc): the table and, for Lambert,
/// the one coefficient per colour `albedo / pi` (SH data sets use the coefficients the
/// lights' kernel looked up at the pixel's view).
#[derive(Clone, Copy)]
pub(crate) struct TransferTerm<'a> {
    pub(super) table: &'a TransferTable,
    /// `albedo / pi` per colour for Lambert; `None` for SH data sets.
    pub(super) lambert: Option<[f32; 3]>,
}

impl<'a> TransferTerm<'a> {
    /// The scene's transfer term, if it has a table.
    pub(super) fn of(scene: &'a Scene) -> Option<TransferTerm<'a>> {
        let table = scene.environment.transfer_table()?;
        let lambert = match &scene.material {
            Material::Lambert(m) => Some((m.albedo / std::f32::consts::PI).to_array()),
            Material::Sh(_)
            | Material::Phong(_)
            | Material::BlinnPhong(_)
            | Material::AshikhminShirley(_)
            | Material::DBrdf(_)
            | Material::LambertDbrdf(_)
            | Material::Merl(_)
            | Material::Rgl(_) => None,
        };
        Some(TransferTerm { table, lambert })
    }
}
