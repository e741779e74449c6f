//! The transfer-table term of an environment ([`crate::env::transfer`]):
//! `L_o += sum_k c_k(wo) T_k(n)` per colour.
//!
//! Design rule: per pixel, one table lookup at the normal and one dot product with the
//! material's coefficients at the view, whatever the number of texels behind the table.
//! Two forms of the same term:
//! - the fast path adds it in its tile loop, in the same place as the lights' radiance, on
//!   the surface, frame, view and coefficients `c(wo)` the lights already use
//!   ([`FramePrep::shade_surface`], [`TransferTerm`], SIMD lookup and dot by
//!   [`radiance_lanes`]): one surface per pixel;
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
use super::traverse::{for_each_tile, for_each_visible, Pass};
use crate::conventions::{hemi_texcoord, local_angles, FrameRule, ShadingFrame};
use crate::env::transfer::table::Corners;
use crate::env::transfer::TransferTable;
use crate::image_io::Image;
use crate::kernel::approx::{acos_01, azimuth};
use crate::lanes::{F32x8, Isa, LANES};
use crate::material::{Material, TransferModel};
use crate::raster::VisBuffer;
use crate::scene::Scene;
use crate::sh::dataset::MAX_BANDS;
use glam::Vec3;

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
    for_each_tile(
        image,
        vis,
        Pass::Adds,
        None,
        buffers,
        |(cbuf, tbuf), rect, band| {
            let c = &mut cbuf[..3 * nt];
            for_each_visible(&scene.mesh, vis, rect, rect.y0, |p| {
                match scene.material.transfer_model() {
                    Some(TransferModel::Sh(ds)) => {
                        let (frame, wo) = frame_and_view(&p.surface, eye, rule);
                        let (polar, azimuth) = local_angles(wo);
                        let (u, v) = hemi_texcoord(polar, azimuth);
                        ds.lookup_coeffs(u, v, ds.coeff_lookup, c);
                        if *rule != FrameRule::UP {
                            to_table_frame(c, ds.bands(), &frame);
                        }
                    }
                    Some(TransferModel::Lambert(m)) => {
                        let k = m.albedo / std::f32::consts::PI;
                        c.copy_from_slice(&[k.x, k.y, k.z]);
                    }
                    None => return,
                }
                band[p.at] += table.radiance_with(p.surface.normal, c, tbuf);
            });
        },
    );
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
    match material.transfer_model() {
        Some(TransferModel::Sh(ds)) => table.terms() == ds.bands() * ds.bands(),
        Some(TransferModel::Lambert(_)) => table.terms() == 1,
        None => false,
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
        let lambert = match scene.material.transfer_model() {
            Some(TransferModel::Lambert(m)) => Some((m.albedo / std::f32::consts::PI).to_array()),
            Some(TransferModel::Sh(_)) | None => None,
        };
        Some(TransferTerm { table, lambert })
    }
}

/// The fast path's [`TransferTable::radiance_with`] of `table`, on the instruction set `s`:
/// corners by [`corners_fast`], then per colour the four nodes blended
/// and dotted with `c` eight terms at a time (`acc = (t0 a0 + t1 a1 + t2 a2 + t3 a3) c
/// + acc`, fused multiply-adds in that order, lanes summed by [`F32x8::sum`]), the
/// terms past the last multiple of eight in scalar order after them. `c` holds
/// `3 x nc` coefficients (`[R.., G.., B..]`) with `nc <= terms`: a data set truncated to
/// its effective bands ([`crate::kernel::skip`]) dots with the table's first `nc` terms
/// per colour, which are its bands (the basis is ordered by band). Same bits on every
/// instruction set ([`crate::lanes`]) and for any thread count (one pixel, no
/// shared state). Differs from [`TransferTable::radiance_with`] by the angle
/// approximation and the summation order only ([`crate::env::transfer::FAST_PATH_TOLERANCE`]).
#[inline(always)]
pub(super) fn radiance_lanes<S: Isa>(table: &TransferTable, s: S, n: Vec3, c: &[f32]) -> Vec3 {
    let nt = table.terms();
    let nc = c.len() / 3;
    debug_assert!(c.len() == 3 * nc && nc <= nt);
    let [(n0, a0), (n1, a1), (n2, a2), (n3, a3)] = corners_fast(table, s, n);
    let (t0, t1, t2, t3) = (
        table.node(n0),
        table.node(n1),
        table.node(n2),
        table.node(n3),
    );
    let (w0, w1, w2, w3) = (s.splat(a0), s.splat(a1), s.splat(a2), s.splat(a3));
    let full = nc / LANES * LANES;
    let mut rgb = [0.0f32; 3];
    for (ch, out) in rgb.iter_mut().enumerate() {
        let (tb, cb) = (ch * nt, ch * nc);
        let mut acc = s.zero();
        for o in (0..full).step_by(LANES) {
            let t = s.load(&t0[tb + o..]) * w0;
            let t = s.load(&t1[tb + o..]).mul_add(w1, t);
            let t = s.load(&t2[tb + o..]).mul_add(w2, t);
            let t = s.load(&t3[tb + o..]).mul_add(w3, t);
            acc = t.mul_add(s.load(&c[cb + o..]), acc);
        }
        let mut sum = acc.sum();
        for k in full..nc {
            let t = a0 * t0[tb + k] + a1 * t1[tb + k] + a2 * t2[tb + k] + a3 * t3[tb + k];
            sum += t * c[cb + k];
        }
        *out = sum;
    }
    Vec3::from_array(rgb)
}

/// [`TransferTable::corners`] of `table` with the fast path's polynomial angles
/// ([`crate::kernel::approx::acos_01`], [`crate::kernel::approx::azimuth`], errors
/// <= 1e-6 rad, about 2e-5 of the default grid's 2.8 degree azimuth step) on the
/// instruction set `s`, lane 0.
#[inline(always)]
pub(super) fn corners_fast<S: Isa>(table: &TransferTable, s: S, n: Vec3) -> Corners {
    let (x, z) = table.unrotated_xz(n);
    // acos(y) = pi - acos(-y) for y < 0.
    let half = acos_01(s, s.splat(n.y.abs())).lane(0);
    let polar = if n.y < 0.0 {
        std::f32::consts::PI - half
    } else {
        half
    };
    // Probe azimuth atan2(-x, z) in [0, 2 pi).
    let az = azimuth(s, s.splat(-x), s.splat(z)).lane(0);
    table.corners_at(polar, az * (0.5 * std::f32::consts::FRAC_1_PI))
}
