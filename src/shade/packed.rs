//! The pixel-packed kernel path: the pixels of an SH data set under point lights only,
//! one pixel per lane, as many at once as the widest vectors hold (16 on AVX-512, else 8).
//!
//! Design rule: same terms as the per-pixel path ([`FramePrep::shade_surface`]), laid out
//! the other way round. With a handful of lights, a light per lane would leave most lanes
//! empty; here each pixel's sum runs in its own lane over the lights in order, so it does
//! not depend on which pixels share its batch (nor on the tile size or thread count).
//! Empty lanes and lights below a pixel's horizon get weight 0, which adds an exact 0.

use super::fault::drop_last_band;
use super::surfaces::TileSurfaces;
use super::FramePrep;
use super::KernelFault;
use crate::conventions::hemi_texcoord;
use crate::kernel::{self, sh::ShRecurrence};
use crate::lanes::{F32x8, Isa, Width, LANES, MAX_LANES};
use crate::sh::dataset::ShDataset;
use glam::Vec3;

impl FramePrep<'_> {
    /// Up to [`Width::N`] pixels (of `s`'s wide vectors; [`packed_width`]) of an SH data
    /// set lit only by point lights, one pixel per lane ([`kernel::sh::sh_sum_packed`]):
    /// with a handful of lights, a light per lane would leave most lanes empty. Same terms
    /// as [`FramePrep::shade_surface`]; each pixel's sum runs in its own lane over the
    /// lights in order, so it does not depend on which pixels share its batch, nor on the
    /// width (nor on the tile size or thread count). The pixels are `tile`'s `o .. o +
    /// count` (`count <= N`, their frames and views resolved with the tile's surfaces).
    /// Results in the first `N` entries.
    #[inline(always)]
    pub(super) fn shade_packed<S: Isa>(
        &self,
        s: S,
        ds: &ShDataset,
        rec: &ShRecurrence,
        (tile, o, count): (&TileSurfaces, usize, usize),
        buf: &mut Vec<f32>,
        sc: &mut kernel::gather::Scratch,
    ) -> [Vec3; MAX_LANES] {
        let w = s.wide();
        let lanes = packed_width(s);
        let t3 = 3 * ds.bands() * ds.bands();
        // `ct`: the batch's coefficients transposed (coefficient-major, a lane per pixel),
        // as `sh_sum_packed` reads them; `ones`: each pixel's looked-up coefficients as
        // `lookup_coeffs` writes them (pixel-major, rows padded to whole vectors), moved into
        // `ct` in 8 x 8 blocks below.
        let stride = kernel::gather::padded(t3);
        buf.resize(t3 * lanes + stride * lanes, 0.0);
        let (ct, ones) = buf.split_at_mut(t3 * lanes);
        let includes_cosine = self.brdf.includes_cosine();
        let np = self.points.len();
        let mut table_basis = [None; MAX_LANES];
        // Frames and view directions of the batch (resolved with the tile's surfaces), and
        // its view angles in lanes (the per-pixel path's bits: `pixel_lanes.rs`,
        // `kernel::approx::view_angles`).
        let px = tile.lanes(o, count);
        let (mut polar, mut azimuth) = ([0.0f32; MAX_LANES], [0.0f32; MAX_LANES]);
        for o in (0..count).step_by(LANES) {
            let (x, y, z) = (
                s.load(&px.wo[0][o..]),
                s.load(&px.wo[1][o..]),
                s.load(&px.wo[2][o..]),
            );
            kernel::approx::acos_01(s, z).store(&mut polar[o..]);
            kernel::approx::azimuth(s, y, x).store(&mut azimuth[o..]);
        }
        for p in 0..lanes {
            let one = &mut ones[p * stride..p * stride + t3];
            if p >= count {
                one.fill(0.0);
                for i in 0..np {
                    let o = i * lanes + p;
                    (sc.x[o], sc.y[o], sc.z[o]) = (0.0, 0.0, 1.0);
                    (sc.wr[o], sc.wg[o], sc.wb[o]) = (0.0, 0.0, 0.0);
                }
                continue;
            }
            let position = tile.position(o + p);
            let (frame, wo) = (px.frame(p), px.view(p));
            let (ts, tt) = hemi_texcoord(polar[p], azimuth[p]);
            kernel::sh::lookup_coeffs(s, ds, ts, tt, one);
            if self.fault == Some(KernelFault::DropLastBand) {
                drop_last_band(one, ds.bands());
            }
            if self.fault == Some(KernelFault::TableBasis) {
                table_basis[p] = Some(self.points.iter().fold(Vec3::ZERO, |sum, light| {
                    let (l, e) = light.at(position);
                    let wi = frame.to_local(l);
                    let w = kernel::gather::light_weight(e, wi.z, includes_cosine);
                    sum + ds.reconstruct_tabulated(wi, wo) * w
                }));
            }
            for (i, light) in self.points.iter().enumerate() {
                // Below the horizon (or degenerate, NaN): weight 0 along the normal, so
                // the lane adds an exact 0.
                let (wi, w) =
                    kernel::gather::point_light_local(light, position, &frame, includes_cosine)
                        .unwrap_or((Vec3::Z, Vec3::ZERO));
                let o = i * lanes + p;
                (sc.x[o], sc.y[o], sc.z[o]) = (wi.x, wi.y, wi.z);
                (sc.wr[o], sc.wg[o], sc.wb[o]) = (w.x, w.y, w.z);
            }
        }
        transpose_blocks(s, ones, t3, stride, lanes, ct);
        let mut lights = np;
        match self.fault {
            Some(KernelFault::DropLane(lane)) => {
                for i in 0..np {
                    let o = i * lanes + lane;
                    (sc.wr[o], sc.wg[o], sc.wb[o]) = (0.0, 0.0, 0.0);
                }
            }
            Some(KernelFault::SkipLastGroup) => lights = np.saturating_sub(1),
            _ => {}
        }
        let (r, g, b) = kernel::sh::sh_sum_packed(w, rec, ct, lights, sc);
        let mut a = [[0.0f32; MAX_LANES]; 3];
        w.store(r, &mut a[0]);
        w.store(g, &mut a[1]);
        w.store(b, &mut a[2]);
        std::array::from_fn(|p| table_basis[p].unwrap_or(Vec3::new(a[0][p], a[1][p], a[2][p])))
    }
}

/// `ct[k lanes + p] = ones[p stride + k]` for `k < t3`, `p < lanes` (a multiple of
/// [`LANES`]): the pixel-major coefficients of a batch turned coefficient-major, in 8 x 8
/// blocks ([`Isa::transpose8`]; values moved, never computed: the bits are the lookup's).
/// `stride` is `t3` rounded up to [`LANES`], so each block reads whole rows of `ones`.
#[inline(always)]
fn transpose_blocks<S: Isa>(
    s: S,
    ones: &[f32],
    t3: usize,
    stride: usize,
    lanes: usize,
    ct: &mut [f32],
) {
    debug_assert!(lanes.is_multiple_of(LANES) && stride >= t3 && stride.is_multiple_of(LANES));
    for h in (0..lanes).step_by(LANES) {
        for k0 in (0..t3).step_by(LANES) {
            let rows = std::array::from_fn(|i| s.load(&ones[(h + i) * stride + k0..]));
            for (j, col) in s.transpose8(rows).into_iter().enumerate().take(t3 - k0) {
                col.store(&mut ct[(k0 + j) * lanes + h..]);
            }
        }
    }
}

/// How many pixels [`FramePrep::shade_packed`] shades at once on `s`: the lanes of its
/// widest vectors.
#[inline(always)]
pub(super) fn packed_width<S: Isa>(_s: S) -> usize {
    <S::Wide as Width>::N
}
