//! The shading kernel: a material against a set of lights, per pixel (thesis chapter 3:
//! 3.1.5 BRDF evaluation; the sum over delta lights `L(v) = sum_k f(l_k, v) cos(polar_k)
//! E_k`, Def. 10, with the light sets of 3.2; the SH form
//! `sum_k E_k w_k sum_lm c_lm(v) Y_lm(l_k)`, Def. 12, Code 4). Units: `E_k`
//! irradiance at normal incidence (W/m^2, RGB), `f` in 1/sr, the result radiance.
//!
//! # Design
//! - **Structures of arrays.** Directional lights live in [`cluster::DirLights`] (one array
//!   per component, chunks of [`crate::lanes::LANES`], sorted for spatial coherence; [`cluster`]).
//!   Per pixel, the lights above its horizon are compacted into a per-worker
//!   [`gather::Scratch`] (local direction and weight per array, reused across pixels and
//!   tiles: no allocation or push per pixel) by masked compress-stores
//!   ([`gather::gather_dir`]), whatever the material; a pixel's RGB coefficients are one
//!   contiguous `[R.., G.., B..]` block.
//! - **Lanes.** Every kernel evaluates eight lights at once, one per lane: the SH basis by
//!   the rescaled associated-Legendre recurrence with a fused multiply-add per term and
//!   colour ([`sh`], monomorphised per band count 1..=10), the analytic models and the
//!   D-BRDF by their lane forms ([`models`], chosen by matching on the scene's
//!   [`crate::material::Material`]). Where a frame has only a few lights, the lanes are
//!   pixels instead (`crate::shade`'s pixel-packed paths: SH data sets under point lights,
//!   Lambert and Blinn-Phong under at most [`crate::shade::PACKED_MAX_LIGHTS`] lights), with
//!   each pixel's frame, view direction and view angles computed eight at a time.
//! - **Dispatch.** SIMD lives only in [`crate::lanes`]: [`crate::lanes::F32x8`] on AVX-512 (F + VL:
//!   mask registers; 16-lane vectors, [`crate::lanes::Width`], for the SH basis sums of 16 lights
//!   and for 16 pixels of the pixel-packed path), AVX2 + FMA (`core::arch`) or portable
//!   `[f32; 8]`, chosen once per frame from the scene's `render.kernel`
//!   ([`crate::lanes::Dispatch::choose`], stored in [`crate::shade::FramePrep`]); the tile loop
//!   runs inside the chosen path's `target_feature` function. Every tile and thread takes
//!   the same path, and the paths give the same bits (fused multiply-add on all, sums
//!   across lights on eight lanes in one order), so the image depends neither on the thread
//!   count nor on the path.
//! - **Tolerance.** The kernel paths sum in another order than the scalar oracle
//!   ([`crate::shade::ShadingPath::ScalarOracle`], and the f64 path, neither of which uses
//!   any of this), use FMA, and the view angles' `acos`/`atan2` are polynomials with stated,
//!   tested maximum errors ([`approx`]). Each path is held within [`KERNEL_TOLERANCE`]
//!   (analytic, D-BRDF) or [`SH_KERNEL_TOLERANCE`] (SH) of the oracle
//!   (tests/integration/kernel.rs, both paths), which the golden check's `kernel-dispatch`
//!   tolerance builds on. tests/integration/kernel_mutation.rs measures the worst case on
//!   every golden scene and shows, by faults seeded through the test-only `fault` of
//!   [`crate::shade::ShadeOptions`], that
//!   the tolerance catches a dropped band, a dropped lane, a skipped group and a tabulated
//!   basis.
//! - **One SH basis.** Every light kind (directional, point, environment set) and every
//!   path (per pixel, pixel-packed, oracle, f64) evaluates the analytic SH basis, also for a
//!   data set that carries a basis table (the data set's definition:
//!   [`crate::sh::dataset`]; tests/integration/sh_basis.rs).
//!
//! Work skipped, and why it changes nothing:
//! - lights are sorted once per frame into spatially coherent chunks of
//!   [`crate::lanes::LANES`], each with a bounding cone; a tile skips a chunk when the chunk's
//!   cone lies wholly below the horizon of the tile's normal cone (with a safety margin).
//!   The skipped lights would have been left out of every pixel's compacted list anyway
//!   (they are below its horizon), so the image is bit-identical with and without culling,
//!   for any tile size ([`cluster`]);
//! - a chunk whose lanes are all below a pixel's horizon costs that pixel one mask test.
//!
//! Work skipped with a bounded change to the image (negligible lights, SH bands a material
//! does not need) is decided per frame in [`skip`].

pub mod approx;
pub mod cluster;
pub mod gather;
pub mod models;
pub mod sh;
pub mod skip;

/// Largest relative difference allowed between a kernel and the scalar oracle, per pixel
/// channel, relative to the pixel's largest channel or to 1% of the image's peak,
/// whichever is larger (SH terms of opposite sign can cancel to a pixel value far below
/// the terms themselves), plus 1e-6 absolute: f32 sums of up to
/// 1024 lights x 100 terms in a different (lane-grouped) order differ by a few ulps per
/// term, far below 1e-4 of the result; a wrong term, a wrong cosine or a missed light moves
/// the result by much more. Measured (tests/integration/kernel_mutation.rs, every golden
/// scene without an SH data set, both instruction-set paths): at most 7.2e-6 against the
/// oracle. Beyond
/// about a thousand lights the oracle's own plain f32 running sum drifts (golden
/// `fig3-8-full-studio`, 130519 lights: 4.0e-4 off the f64 path on the same light set,
/// while the kernel's eight lane sums stay within 1.7e-5 of it), so there the kernel is
/// held to the f64 path instead.
pub const KERNEL_TOLERANCE: f32 = 1e-4;

/// [`KERNEL_TOLERANCE`] for SH data sets: the sum `sum_lm c_lm Y_lm` of a specular data
/// set at 8 bands cancels heavily (terms of opposite sign, each far larger than the sum),
/// so two f32 summation orders differ by more. Measured against the oracle
/// (tests/integration/kernel_mutation.rs, every golden scene with an SH data set, both
/// instruction-set paths, which give the same bits): at most 1.94e-4
/// (`fig3-10-blue-silk-nearest`), so 1e-3 leaves a margin of 5. (With the portable path's
/// `mul_add` unfused, as before, the ringing gold dust reached 4.4e-4.) Seeded
/// kernel faults exceed it by far (same test, 8-band blue-silk and teal-paint under a
/// 64-light environment set and under one point light, both paths): the last band dropped
/// 5.1e0 and more, one lane of each group dropped 7.8e-1 and more, the last padded group
/// skipped 8.6e-1 and more, the basis read from a 16 x 8 nearest basis table instead of
/// the analytic basis 9.0e-1 and more; the smallest is 777 times the tolerance. A tighter
/// value would buy nothing against such faults and leave less room for summation order.
pub const SH_KERNEL_TOLERANCE: f32 = 1e-3;
