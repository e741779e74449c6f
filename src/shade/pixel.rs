//! The per-pixel kernel path: one surface point, its lights across the lanes.
//!
//! Design rule: every light kind goes through the same kernel with the same (analytic) SH
//! basis, basis table or not (the data set's definition: [`crate::sh::dataset`], "Which
//! basis defines a data set"). The lights above the pixel's horizon, directional and point
//! alike, are gathered into one list (local direction, weight `E cos`), eight per SIMD
//! group, and summed by the SH kernel or the material's lane model. The pixel-packed
//! alternative for point lights only is `packed.rs`.

use super::fault::{seed_fault, shift_one_azimuth_node};
use super::{FramePrep, KernelFault, Surface};
use crate::conventions::{hemi_texcoord, FrameRule, ShadingFrame};
use crate::kernel;
use crate::lanes::Isa;
use glam::Vec3;

impl FramePrep<'_> {
    /// Radiance of one surface point lit by the chunks `chunks` of the directional lights
    /// and by every point light, on the instruction set `s` (called from the tile loop,
    /// which [`FramePrep::dispatch`] runs once per tile); `(frame, wo)` is the surface's
    /// shading frame and lifted local view ([`super::frame_and_view`]'s, resolved with the
    /// tile's surfaces).
    ///
    /// The lights above the horizon, directional and point alike, go into `scratch` (local
    /// direction, weight `E cos`) and from there through the SH kernel or the material's
    /// lane model. With a transfer table (`[env] method = "transfer"`), its term is added
    /// here too, at the same surface with the same coefficients (`transfer.rs`).
    #[inline(always)]
    pub fn shade_surface<S: Isa>(
        &self,
        s: S,
        surf: &Surface,
        (frame, wo): (ShadingFrame, Vec3),
        chunks: &[u32],
        coeff_buf: &mut Vec<f32>,
        scratch: &mut kernel::gather::Scratch,
    ) -> Vec3 {
        scratch.clear();
        let includes_cosine = self.brdf.includes_cosine();
        kernel::gather::gather_dir(s, &frame, includes_cosine, &self.dir, chunks, scratch);
        for light in &self.points {
            if let Some((wi, w)) =
                kernel::gather::point_light_local(light, surf.position, &frame, includes_cosine)
            {
                scratch.push(wi, w);
            }
        }
        self.sum_gathered(s, wo, Some((surf.normal, &frame)), coeff_buf, scratch)
    }

    /// Radiance of one surface point lit by the dropped lights only
    /// ([`FramePrep::dropped_dir`], every chunk, no point light): what the tile loop adds
    /// where [`crate::kernel::skip::needs_restore`] says leaving them out could change the
    /// pixel by more than `render.drop_lights` of its value; `(frame, wo)` as
    /// [`FramePrep::shade_surface`]'s.
    #[inline(always)]
    pub fn shade_dropped<S: Isa>(
        &self,
        s: S,
        (frame, wo): (ShadingFrame, Vec3),
        coeff_buf: &mut Vec<f32>,
        scratch: &mut kernel::gather::Scratch,
    ) -> Vec3 {
        scratch.clear();
        let includes_cosine = self.brdf.includes_cosine();
        kernel::gather::gather_dir(
            s,
            &frame,
            includes_cosine,
            &self.dropped_dir,
            &self.dropped_chunks,
            scratch,
        );
        self.sum_gathered(s, wo, None, coeff_buf, scratch)
    }

    /// Lanes the kernel occupies for a pixel's `n` gathered lights (the work counters'
    /// [`super::ShadeCounts::lane_slots`]): the SH kernel's groups of eight (16-light
    /// groups on AVX-512 leave the same padding: the tail is a group of eight), or the lane
    /// model's ([`kernel::models::LaneModel::lane_slots`]).
    pub(super) fn lane_slots(&self, n: usize) -> u64 {
        match &self.sh {
            Some(_) => kernel::gather::padded(n) as u64,
            None => self.model.lane_slots(n) as u64,
        }
    }

    /// The gathered lights of `scratch` summed by the SH kernel or the material's lane
    /// model, at local view direction `wo`; with `transfer_at` (the world normal and the
    /// pixel's frame) and a transfer table (`[env] method = "transfer"`), plus the table's
    /// term at that normal with the same coefficients `c(wo)` (SH; turned back into the
    /// table's world-up frame when the pixel's frame is turned, [`super::transfer::to_table_frame`])
    /// or `albedo / pi` (Lambert) (`transfer.rs`).
    #[inline(always)]
    fn sum_gathered<S: Isa>(
        &self,
        s: S,
        wo: Vec3,
        transfer_at: Option<(Vec3, &ShadingFrame)>,
        coeff_buf: &mut Vec<f32>,
        scratch: &mut kernel::gather::Scratch,
    ) -> Vec3 {
        let transfer = transfer_at.and_then(|n| self.transfer.map(|t| (t, n)));
        let lights = match &self.sh {
            Some((ds, rec)) => {
                if scratch.n == 0 && transfer.is_none() {
                    return Vec3::ZERO;
                }
                coeff_buf.resize(3 * ds.bands() * ds.bands(), 0.0);
                let (p, a) = kernel::approx::view_angles(s, wo);
                let (ts, tt) = hemi_texcoord(p, a);
                kernel::sh::lookup_coeffs(s, ds, ts, tt, coeff_buf);
                if let Some(fault) = self.fault {
                    if let Some(sum) = seed_fault(fault, ds, wo, coeff_buf, scratch) {
                        return sum;
                    }
                }
                if scratch.n == 0 {
                    Vec3::ZERO
                } else {
                    kernel::sh::sh_sum(s, rec, coeff_buf, scratch)
                }
            }
            None => self.model.sum(s, wo, scratch),
        };
        match transfer {
            Some((term, (mut n, frame))) => {
                let c = match &term.lambert {
                    Some(k) => &k[..],
                    None => {
                        if self.rule != FrameRule::UP {
                            let bands = self.sh.as_ref().map_or(1, |(ds, _)| ds.bands());
                            super::transfer::to_table_frame(coeff_buf, bands, frame);
                        }
                        &coeff_buf[..]
                    }
                };
                if self.fault == Some(KernelFault::TransferAzimuthShift) {
                    n = shift_one_azimuth_node(term.table, n);
                }
                lights + super::transfer::radiance_lanes(term.table, s, n, c)
            }
            None => lights,
        }
    }
}
