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
//! the plain per-light loop over [`crate::brdf::Brdf::eval`], is the scalar f32 oracle the
//! kernels are tested against.
//!
//! One entry point, [`shade`], shades on any of three paths ([`ShadingPath`], chosen in
//! [`ShadeOptions`]): the kernels (the fast path), the scalar f32 oracle (same skips, no
//! kernel), and the f64 path with no skips (every light, every band; on the full probe, the
//! converged reference).
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
//!   [`surface_at_index`]).
//! - `traverse.rs`: the one per-pixel traversal of every path (bands of rows in parallel,
//!   a band's occupied tiles, a rectangle's visible pixels: [`for_each_visible`],
//!   [`tile_surfaces`]).
//! - `view.rs`: the view direction in the shading frame lifted above the horizon
//!   ([`local_view`], [`MIN_VIEW_COS`]); one body for f32 ([`lift_above_horizon`]) and f64
//!   ([`lift_above_horizon_f64`]).
//! - `pixel_lanes.rs`: the shading frames and view directions of pixels in lanes, with
//!   the scalar definitions' bits, and a group of them as the packed paths read it
//!   (`PixelLanes`).
//! - `surfaces.rs`: a tile's surfaces resolved once for the fast path, structure of
//!   arrays, in lanes with [`surface_at_index`]'s bits, with their frames and views
//!   (`TileSurfaces`).
//! - `options.rs`: what the caller chooses ([`ShadeOptions`], [`ShadingPath`]).
//! - `entry.rs`: the one entry point ([`shade`]; [`shade_into`], its form into a caller's
//!   image and buffers) and its result ([`Shaded`], [`ShadeReport`]).
//! - `prep.rs`: what is decided once per frame ([`FramePrep`]).
//! - `tile.rs`: the tile loops, counting tiles into [`ShadeOptions::progress`], and the
//!   workers' buffers kept across frames ([`ShadeScratch`]): the fast path's loop, which
//!   per tile runs one of
//!   - `pixel.rs`: the per-pixel kernel path ([`FramePrep::shade_surface`]), lights
//!     across the lanes;
//!   - `packed.rs`: the pixel-packed path, pixels across the lanes (SH data sets under
//!     point lights only);
//!   - `packed_analytic.rs`: the pixel-packed path of Lambert and Blinn-Phong under at
//!     most [`PACKED_MAX_LIGHTS`] lights (the default scene's one key light).
//!
//!   and the per-pixel one that the scalar oracle and the f64 path share.
//! - `transfer.rs`: the transfer-table term of an environment (`[env] method =
//!   "transfer"`, [`crate::env::transfer`]): on the fast path added per pixel beside the
//!   lights (`pixel.rs`), on the scalar oracle and the f64 path in a plain pass of its own.
//! - `lightcuts/`: the light-cut term of an environment (`[env] method = "lightcuts"`,
//!   [`crate::env::lightcuts`]): a cut through the light tree per square of pixels on the
//!   kernels' path (`tile.rs`), per pixel on the scalar oracle (the reference), added to
//!   the path's image after its lights ([`CutStats`]: the cut sizes).
//! - `counts.rs`: the work counters ([`ShadeCounts`]).
//! - `scalar_oracle.rs`: the scalar f32 oracle ([`shade_point`] per pixel;
//!   [`ShadingPath::ScalarOracle`]).
//! - `f64_path.rs`: the f64 path with no skips ([`ShadingPath::F64NoSkips`]); its
//!   point-light falloff is [`crate::light::Light::at_f64`], the f64 twin of
//!   [`crate::light::Light::at`].
//! - `fault.rs`: **test only**, faults seeded into the SH kernel path (`KernelFault`).

mod counts;
mod entry;
mod f64_path;
mod fault;
mod gbuffer;
mod lightcuts;
mod options;
mod packed;
mod packed_analytic;
mod pixel;
mod pixel_lanes;
mod prep;
mod reflection;
mod scalar_oracle;
mod surfaces;
mod tile;
mod transfer;
mod traverse;
mod view;

#[doc(hidden)]
pub use fault::KernelFault;
pub use {
    counts::ShadeCounts,
    entry::{shade, shade_into, ShadeReport, Shaded},
    gbuffer::{surface_at, surface_at_index, Surface},
    lightcuts::{tile::CUT_TILE, CutStats},
    options::{effective_frame_rule, FrameCheck, ShadeOptions, ShadingPath},
    packed_analytic::PACKED_MAX_LIGHTS,
    prep::FramePrep,
    scalar_oracle::shade_point,
    tile::ShadeScratch,
    traverse::{for_each_visible, tile_surfaces, VisiblePixel},
    view::{
        frame_and_view, frame_and_view_f64, lift_above_horizon, lift_above_horizon_f64, local_view,
        MIN_VIEW_COS,
    },
};
