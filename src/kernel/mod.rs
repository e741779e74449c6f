//! The shading kernel: a material against a set of lights, per pixel (thesis chapter 3:
//! 3.1.5 BRDF evaluation; the sum over delta lights `L(v) = sum_k f(l_k, v) cos(polar_k)
//! E_k`, Def. 10, with the light sets of 3.2; the SH form
//! `sum_k E_k w_k sum_lm c_lm(v) Y_lm(l_k)`, Def. 12, Code 4). Units: `E_k`
//! irradiance at normal incidence (W/m^2, RGB), `f` in 1/sr, the result radiance.
//!
//! # Design
//! - **Structures of arrays.** Directional lights live in [`DirLights`] (one array per
//!   component, chunks of [`LANES`], sorted for spatial coherence). Per pixel, the lights
//!   above its horizon are compacted into a per-worker [`sh::Scratch`] (local direction and
//!   weight per array, reused across pixels and tiles: no allocation or push per pixel) by
//!   masked compress-stores ([`sh::gather_dir`]); a pixel's RGB coefficients are one
//!   contiguous `[R.., G.., B..]` block.
//! - **Lanes.** Every kernel evaluates eight lights at once, one per lane: the SH basis by
//!   the rescaled associated-Legendre recurrence with a fused multiply-add per term and
//!   colour ([`sh`], monomorphised per band count 1..=10), the analytic models and the
//!   D-BRDF by their lane forms ([`models`]).
//! - **Dispatch.** SIMD lives only in [`lanes`]: [`lanes::F32x8`] on AVX2 + FMA
//!   (`core::arch`) or portable `[f32; 8]`, chosen once per frame from the scene's
//!   `render.kernel` ([`lanes::Dispatch::choose`], stored in [`crate::shade::FramePrep`]);
//!   the tile loop runs inside the chosen path's `target_feature` function. Every tile and
//!   thread takes the same path, and the two paths give the same bits (fused multiply-add
//!   on both), so the image depends neither on the thread count nor on the path.
//! - **Tolerance.** The kernel paths sum in another order than the scalar oracle
//!   ([`crate::shade::shade_reference`], and the f64 reference, neither of which uses any
//!   of this), use FMA, and the D-BRDF's `acos`/`atan2` are polynomials with stated,
//!   tested maximum errors ([`approx`]). Each path is held within [`KERNEL_TOLERANCE`]
//!   (analytic, D-BRDF) or [`SH_KERNEL_TOLERANCE`] (SH) of the oracle (tests/kernel.rs, both
//!   paths), which the golden check's `kernel-dispatch` tolerance builds on.
//!   tests/kernel_mutation.rs measures the worst case on every golden scene and shows, by
//!   faults seeded through the test-only `FramePrep::fault`, that the tolerance catches a
//!   dropped band, a dropped lane, a skipped group and a tabulated basis.
//! - **One SH basis.** Every light kind (directional, point, environment set) and every
//!   path (per pixel, pixel-packed, oracle, f64) evaluates the analytic SH basis, also for a
//!   data set that carries a basis table (the data set's definition:
//!   [`crate::sh::dataset`]; tests/sh_basis.rs).
//!
//! Work skipped, and why it changes nothing:
//! - lights are sorted once per frame into spatially coherent chunks of
//!   [`lanes::LANES`], each with a bounding cone; a tile skips a chunk when the chunk's
//!   cone lies wholly below the horizon of the tile's normal cone (with a safety margin).
//!   The skipped lights would have been left out of every pixel's compacted list anyway
//!   (they are below its horizon), so the image is bit-identical with and without culling,
//!   for any tile size;
//! - a chunk whose lanes are all below a pixel's horizon costs that pixel one mask test.
//!
//! Work skipped with a bounded change to the image (negligible lights, SH bands a material
//! does not need) is decided per frame in [`skip`].

pub mod approx;
pub mod lanes;
pub mod models;
pub mod sh;
pub mod skip;

use crate::light::Light;
use glam::Vec3;
use lanes::LANES;

/// Largest relative difference allowed between a kernel and the scalar oracle, per pixel
/// channel, relative to the pixel's largest channel or to 1% of the image's peak,
/// whichever is larger (SH terms of opposite sign can cancel to a pixel value far below
/// the terms themselves), plus 1e-6 absolute: f32 sums of up to
/// 1024 lights x 100 terms in a different (lane-grouped) order differ by a few ulps per
/// term, far below 1e-4 of the result; a wrong term, a wrong cosine or a missed light moves
/// the result by much more. Measured (tests/kernel_mutation.rs, every golden scene without
/// an SH data set, both instruction-set paths): at most 7.2e-6 against the oracle. Beyond
/// about a thousand lights the oracle's own plain f32 running sum drifts (golden
/// `fig3-8-full-studio`, 130519 lights: 4.0e-4 off the f64 reference of the same light set,
/// while the kernel's eight lane sums stay within 1.7e-5 of it), so there the kernel is
/// held to the f64 reference instead.
pub const KERNEL_TOLERANCE: f32 = 1e-4;

/// [`KERNEL_TOLERANCE`] for SH data sets: the sum `sum_lm c_lm Y_lm` of a specular data
/// set at 8 bands cancels heavily (terms of opposite sign, each far larger than the sum),
/// so two f32 summation orders differ by more. Measured against the oracle
/// (tests/kernel_mutation.rs, every golden scene with an SH data set, both instruction-set
/// paths, which give the same bits): at most 1.94e-4 (`fig3-10-blue-silk-nearest`; 1.87e-4
/// on `fig3-12-gold-dust-paint-median-cut`, 129 lights), so 1e-3 leaves a margin of 5.
/// (With the portable path's `mul_add` unfused, as before, gold-dust reached 4.4e-4.) Seeded
/// kernel faults exceed it by far (same test, 8-band blue-silk and teal-paint under a
/// 64-light environment set and under one point light, both paths): the last band dropped
/// 5.1e0 and more, one lane of each group dropped 7.8e-1 and more, the last padded group
/// skipped 8.6e-1 and more, the basis read from a 16 x 8 nearest basis table instead of
/// the analytic basis 9.0e-1 and more; the smallest is 777 times the tolerance. A tighter
/// value would buy nothing against such faults and leave less room for summation order.
pub const SH_KERNEL_TOLERANCE: f32 = 1e-3;

/// Margin (in cosine) of the tile/chunk cone test: cones must be this far below the
/// horizon before a chunk is skipped, so rounding in the per-pixel local directions can
/// never turn a skipped light into a (tiny) contributing one.
pub const CULL_MARGIN: f32 = 1e-3;

/// Directional lights as a structure of arrays, in chunks of [`LANES`] (padded with
/// zero-irradiance lights pointing up), sorted for spatial coherence.
#[derive(Clone, Debug, Default)]
pub struct DirLights {
    pub dx: Vec<f32>,
    pub dy: Vec<f32>,
    pub dz: Vec<f32>,
    /// Irradiance at normal incidence (RGB).
    pub er: Vec<f32>,
    pub eg: Vec<f32>,
    pub eb: Vec<f32>,
    /// Per chunk: cone axis (unit) and the sine of its half-angle (2 for an empty or
    /// all-directions chunk, which no cone test can skip).
    pub chunk_axis: Vec<Vec3>,
    pub chunk_cos: Vec<f32>,
    pub chunk_sin: Vec<f32>,
    /// Per chunk: bit `i` set when lane `i` carries irradiance (not padding, not black).
    pub chunk_live_mask: Vec<u8>,
}

/// A normal cone: every normal `n` of a tile has `n . axis >= cos`, `sin = sqrt(1-cos^2)`
/// (only meaningful when `cos >= 0`; a wider cone skips nothing).
#[derive(Clone, Copy, Debug)]
pub struct Cone {
    pub axis: Vec3,
    pub cos: f32,
    pub sin: f32,
}

impl Cone {
    /// The cone around the normalised sum of `normals`; `None` if they span a half-space or
    /// more (nothing can be culled) or the list is empty.
    pub fn around(normals: impl Iterator<Item = Vec3> + Clone) -> Option<Cone> {
        let axis = normals
            .clone()
            .fold(Vec3::ZERO, |a, n| a + n)
            .try_normalize()?;
        let cos = normals.map(|n| n.dot(axis)).fold(1.0f32, f32::min);
        if !(cos > 0.0) {
            return None;
        }
        Some(Cone {
            axis,
            cos,
            sin: (1.0 - cos * cos).max(0.0).sqrt(),
        })
    }
}

/// Morton-style key of a unit direction on an octahedral map: nearby directions get nearby
/// keys, so consecutive lights form tight chunks.
fn direction_key(d: Vec3) -> u64 {
    let l1 = d.x.abs() + d.y.abs() + d.z.abs();
    let p = if l1 > 0.0 { d / l1 } else { Vec3::Y };
    let (mut u, mut v) = (p.x, p.z);
    if p.y < 0.0 {
        let (ou, ov) = (u, v);
        u = (1.0 - ov.abs()) * ou.signum();
        v = (1.0 - ou.abs()) * ov.signum();
    }
    let q = |x: f32| (((x * 0.5 + 0.5).clamp(0.0, 1.0)) * 65535.0) as u64;
    let (a, b) = (q(u), q(v));
    let mut key = 0u64;
    for bit in 0..16 {
        key |= ((a >> bit) & 1) << (2 * bit);
        key |= ((b >> bit) & 1) << (2 * bit + 1);
    }
    key
}

impl DirLights {
    /// Collects the directional lights of `lights` (point lights are left to the caller),
    /// sorted by `direction_key` (ties by original index), padded to whole chunks.
    pub fn from_lights(lights: &[Light]) -> DirLights {
        let mut dirs: Vec<(u64, usize, Vec3, Vec3)> = lights
            .iter()
            .enumerate()
            .filter_map(|(i, l)| match *l {
                Light::Directional {
                    to_light,
                    irradiance,
                } => Some((direction_key(to_light), i, to_light, irradiance)),
                Light::Point { .. } => None,
            })
            .collect();
        dirs.sort_by_key(|&(k, i, _, _)| (k, i));
        let mut s = DirLights::default();
        for &(_, _, d, e) in &dirs {
            s.dx.push(d.x);
            s.dy.push(d.y);
            s.dz.push(d.z);
            s.er.push(e.x);
            s.eg.push(e.y);
            s.eb.push(e.z);
        }
        while s.dx.len() % LANES != 0 {
            for (v, x) in [
                (&mut s.dx, 0.0),
                (&mut s.dy, 1.0),
                (&mut s.dz, 0.0),
                (&mut s.er, 0.0),
                (&mut s.eg, 0.0),
                (&mut s.eb, 0.0),
            ] {
                v.push(x);
            }
        }
        for c in 0..s.chunks() {
            let r = c * LANES..(c + 1) * LANES;
            let live_mask = r
                .clone()
                .filter(|&i| s.er[i] != 0.0 || s.eg[i] != 0.0 || s.eb[i] != 0.0)
                .fold(0u8, |m, i| m | 1 << (i - c * LANES));
            s.chunk_live_mask.push(live_mask);
            let live: Vec<Vec3> = r
                .clone()
                .filter(|&i| s.er[i] != 0.0 || s.eg[i] != 0.0 || s.eb[i] != 0.0)
                .map(|i| Vec3::new(s.dx[i], s.dy[i], s.dz[i]))
                .collect();
            match Cone::around(live.iter().copied()) {
                Some(cone) if !live.is_empty() => {
                    s.chunk_axis.push(cone.axis);
                    s.chunk_cos.push(cone.cos);
                    s.chunk_sin.push(cone.sin);
                }
                _ if live.is_empty() => {
                    // No irradiance at all: always skippable.
                    s.chunk_axis.push(Vec3::Y);
                    s.chunk_cos.push(f32::INFINITY);
                    s.chunk_sin.push(0.0);
                }
                _ => {
                    s.chunk_axis.push(Vec3::Y);
                    s.chunk_cos.push(-1.0);
                    s.chunk_sin.push(2.0);
                }
            }
        }
        s
    }

    /// Number of chunks of [`LANES`] lights.
    pub fn chunks(&self) -> usize {
        self.dx.len() / LANES
    }

    /// Number of real (unpadded) lights is not tracked; this is the padded count.
    pub fn len(&self) -> usize {
        self.dx.len()
    }

    pub fn is_empty(&self) -> bool {
        self.dx.is_empty()
    }

    /// Indices of the chunks that can light some normal of `tile` (all chunks when the
    /// tile has no usable cone).
    pub fn chunks_for(&self, tile: Option<Cone>) -> Vec<u32> {
        (0..self.chunks() as u32)
            .filter(|&c| {
                let c = c as usize;
                if self.chunk_cos[c] == f32::INFINITY {
                    return false; // zero irradiance
                }
                let Some(t) = tile else { return true };
                if self.chunk_sin[c] > 1.0 {
                    return true;
                }
                // Largest n.l over the two cones is cos(max(0, angle - a_t - a_c)); the chunk
                // is skippable when angle >= pi/2 + a_t + a_c, i.e.
                // cos(angle) <= cos(pi/2 + a) = -sin(a), a = a_t + a_c.
                let cos_a = t.cos * self.chunk_cos[c] - t.sin * self.chunk_sin[c];
                let sin_a = t.sin * self.chunk_cos[c] + t.cos * self.chunk_sin[c];
                if cos_a <= 0.0 {
                    return true; // combined cone reaches past 90 degrees
                }
                t.axis.dot(self.chunk_axis[c]) > -sin_a - CULL_MARGIN
            })
            .collect()
    }
}
