//! Deferred shading: each visible pixel is shaded exactly once, after visibility is known.
//!
//! Design rule: shading reads only the visibility buffer, the mesh and the scene; it
//! computes every pixel independently (parallel over tiles), so the image does not depend
//! on the thread count or the tile size. Tiles that received no triangle are skipped.
//! Negligible lights and SH bands a material does not need are dropped once per frame in
//! [`FramePrep::new`], within the bounds of [`crate::kernel::skip`]; [`ShadeCounts`]
//! records the work done, so tests can see each skip.
//! Lights go through the kernels of [`crate::kernel`] (structure of arrays, eight lanes on
//! the instruction set dispatched once per frame, per-tile normal-cone culling that
//! provably changes no bit): per pixel, the lights above its horizon, one per lane; for SH
//! data sets under point lights only, eight pixels per group, one per lane. Every light
//! kind goes through the same kernel with the same (analytic) SH basis, basis table or not
//! (the data set's definition: [`crate::sh::dataset`], "Which basis defines a data set"). The image is
//! written tile by tile in place (parallel over bands of one tile row). [`shade_point`],
//! the plain per-light loop over [`crate::brdf::Brdf::eval`], is the scalar oracle the
//! kernels are tested against.
//!
//! Per pixel: perspective-correct barycentrics of the source triangle give the world
//! position and the interpolated normal; back faces (two-sided mode) get the normal flipped,
//! so the inside of the teapot is lit as a surface facing the viewer. The shading frame is
//! [`crate::conventions::ShadingFrame::from_normal`]. The view direction is clamped to at
//! least [`MIN_VIEW_COS`] above the horizon: interpolated normals can face slightly away
//! from the camera at silhouettes, and a BRDF is not defined there.
//!
//! # Layout
//!
//! One concept per file, in the order the data flows; the files are private and every
//! public name is re-exported here, so each has the one path `shade::X`.
//!
//! - `gbuffer.rs`: the surface seen through a pixel ([`Surface`], [`surface_at`],
//!   [`surface_at_index`], [`tile_pixels`]).
//! - `view.rs`: the view direction in the shading frame lifted above the horizon
//!   ([`local_view`], [`MIN_VIEW_COS`]); one body for f32 ([`lift_above_horizon`]) and f64
//!   ([`lift_above_horizon_f64`]).
//! - `prep.rs`: what is decided once per frame ([`FramePrep`]).
//! - `tile.rs`: the tile loop and the fast path's entry points ([`shade`], [`shade_with`],
//!   [`shade_with_counts`]); per tile it runs one of
//!   - `pixel.rs`: the per-pixel kernel path ([`FramePrep::shade_surface`]), lights
//!     across the lanes;
//!   - `packed.rs`: the pixel-packed path, pixels across the lanes (SH data sets under
//!     point lights only).
//! - `counts.rs`: the work counters ([`ShadeCounts`]).
//! - `oracle.rs`: the scalar f32 oracle ([`shade_point`], [`shade_reference`]).
//! - `reference_f64.rs`: the f64 path ([`shade_reference_f64`]); its point-light falloff
//!   is [`crate::light::Light::at_f64`], the f64 twin of [`crate::light::Light::at`].
//! - `fault.rs`: **test only**, faults seeded into the SH kernel path (`KernelFault`).

mod counts;
mod fault;
mod gbuffer;
mod oracle;
mod packed;
mod pixel;
mod prep;
mod reference_f64;
mod tile;
mod view;

#[doc(hidden)]
pub use fault::KernelFault;
pub use {
    counts::ShadeCounts,
    gbuffer::{surface_at, surface_at_index, tile_pixels, Surface},
    oracle::{shade_point, shade_reference},
    prep::FramePrep,
    reference_f64::shade_reference_f64,
    tile::{shade, shade_with, shade_with_counts},
    view::{lift_above_horizon, lift_above_horizon_f64, local_view, MIN_VIEW_COS},
};
