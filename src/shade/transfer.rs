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

use super::{frame_and_view, surface_at_index, tile_pixels, FramePrep};
use crate::conventions::{hemi_texcoord, local_angles, FrameRule, ShadingFrame};
use crate::env::transfer::TransferTable;
use crate::image_io::Image;
use crate::material::Material;
use crate::raster::VisBuffer;
use crate::scene::Scene;
use crate::sh::dataset::MAX_BANDS;
use rayon::prelude::*;

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
    let band_len = (vis.width * vis.tile_size) as usize;
    let per_tile = (vis.tile_size * vis.tile_size) as usize;
    let nt = table.terms();
    image
        .pixels
        .par_chunks_mut(band_len)
        .enumerate()
        .for_each(|(ty, band)| {
            let mut cbuf = [0.0f32; 3 * MAX_BANDS * MAX_BANDS];
            let mut tbuf = [0.0f32; 3 * MAX_BANDS * MAX_BANDS];
            let c = &mut cbuf[..3 * nt];
            let y0 = ty as u32 * vis.tile_size;
            for tx in 0..vis.tiles_x as usize {
                let t = ty * vis.tiles_x as usize + tx;
                if !vis.tile_occupied[t] {
                    continue;
                }
                for (i, x, y) in tile_pixels(vis, t) {
                    let Some(s) = surface_at_index(&scene.mesh, vis, t * per_tile + i, x, y) else {
                        continue;
                    };
                    match &scene.material {
                        Material::Sh(ds) => {
                            let (frame, wo) = frame_and_view(&s, eye, rule);
                            let (p, a) = local_angles(wo);
                            let (u, v) = hemi_texcoord(p, a);
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
                        | Material::Merl(_) => continue,
                    }
                    let at = ((y - y0) * vis.width + x) as usize;
                    band[at] += table.radiance_with(s.normal, c, &mut tbuf);
                }
            }
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
        | Material::Merl(_) => false,
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
            | Material::Merl(_) => None,
        };
        Some(TransferTerm { table, lambert })
    }
}

impl FramePrep<'_> {
    /// Whether the fast path's tile loop adds a transfer term (then every pixel takes the
    /// per-pixel path, which has the coefficients at hand).
    #[inline(always)]
    pub(super) fn has_transfer(&self) -> bool {
        self.transfer.is_some()
    }
}
