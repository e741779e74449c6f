//! # brdfkit
//!
//! A CPU renderer for *acquired* (measured) BRDF data, after O'Toole, "Real-time Rendering of
//! Acquired BRDF Data Sets" (2007, "the thesis"). It is the renderer on machines without a
//! GPU, the oracle GPU builds of the same method are checked against, and a benchmark of
//! the shading kernel.
//!
//! ## Stages (modules follow the data's path)
//! 1. **Scene and assets in**: [`scene`] (TOML scene file, defaults, checks; [`scene::camera`]),
//!    [`mesh`] (Utah teapot from Newell's patches, UV sphere, OBJ via tobj; the UV sphere
//!    names its exact sphere, which shading intersects per pixel instead of its facets).
//! 2. **Lights and materials prepared**: [`light`] (delta lights: point, directional),
//!    [`env`](mod@env), one concept per module: the light probe [`env::probe`]; the
//!    `[env]` table of every method [`env::schema`]; `method = "lights"`, the probe
//!    collapsed into a delta-light set [`env::lightset`] (its samplers: uniform, importance
//!    sampling, median cut, Lloyd relaxation, the full probe as reference; its file format,
//!    its preparation and disk cache; thesis 2.3.2, 3.2); and the two methods
//!    `[env] method = "auto"`, the default, chooses between per material
//!    ([`scene::env_method`]): `transfer`, [`env::transfer`]: the full probe projected
//!    onto an SH data set's basis or into irradiance per normal, tabulated once and
//!    interpolated per pixel by [`shade`]; `lightcuts`, [`env::lightcuts`]: every texel a
//!    light in a light tree, cut per pixel by [`shade`] within the bounds of
//!    [`material::cone_bound`], Walter et al. 2005; and `reflection`,
//!    [`env::reflection`]: an isotropic material's outgoing radiance under the probe,
//!    tabulated over reflected direction, view angle and a Fourier series about it, looked
//!    up per pixel by [`shade`], Ramamoorthi & Hanrahan 2002),
//!    [`brdf`] (the [`brdf::Brdf`] trait; Lambert, Phong, Blinn-Phong, Ashikhmin-Shirley,
//!    D-BRDF with its file format [`brdf::dbrdf::file`], Lambert + D-BRDF lobe, MERL tables,
//!    and the library's stand-in source models [`brdf::stand_ins`]), [`sh`] (real spherical
//!    harmonics, SH coefficient data sets, which implement the trait, and their file format
//!    [`sh::file`] beside them: thesis 2.3.3-2.3.4, 3.1.3-3.1.5). [`library`] builds the
//!    materials after the thesis's figures 3.9-3.15 (a source model plus the representation it
//!    is rendered with). [`material`] is the closed set of models the renderer shades: one
//!    [`material::Material`] per scene, built once by [`scene::Scene::resolve`] and dispatched
//!    by tag (the pbrt-v4 way), so the models know nothing of the kernels that shade them.
//! 3. **Triangles binned to tiles and visibility resolved**: [`raster`] (homogeneous
//!    clipping, fixed-point edge functions with a top-left rule, binning, per-tile depth).
//! 4. **Pixels shaded**: [`shade`] (deferred: one shading per visible pixel, one entry point
//!    [`shade::shade`] for the three paths of [`shade::ShadingPath`]: the kernels, the
//!    scalar f32 oracle, the f64 path with no skips; the frame's skips decided once in
//!    [`shade::FramePrep`]), [`kernel`] (8 lights per SIMD group from
//!    structure-of-arrays buffers: light clustering and culling [`kernel::cluster`], a pixel's
//!    lights gathered for every material [`kernel::gather`], SH sums [`kernel::sh`], lane
//!    models for the analytic and D-BRDF materials [`kernel::models`], chosen by matching on
//!    the [`material::Material`]; [`lanes`] is the only SIMD code, [`kernel::skip`]
//!    bounds what each skip changes, [`kernel::approx`] states the error of each
//!    approximation), [`aov`] (debug outputs: normal, depth, coverage, view and light angles).
//! 5. **Images out**: [`image_io`] (linear EXR; PNG via the one display encoding
//!    [`image_io::display`]: exposure, tone map, sRGB; atomic writes), [`golden`]
//!    (golden images and their check), [`metrics`] (every image error measure, written
//!    once), [`compare`] (those measures and FLIP for a GPU build's CI).
//!
//! [`render`] strings the stages together (one entry point, [`render::render`], its settings
//! in one struct, [`render::RenderOptions`]; [`render::render_into`] is the same into a
//! [`render::FrameContext`] the caller keeps, whose buffers the next frame reuses); [`cli`] is the command line (including the
//! `SOURCE` argument of `acquire` and `fit-dbrdf`, [`cli::source`], and the `lights`
//! command's reports: [`cli::lights_report`], the light set drawn on its probe
//! [`cli::lights_overlay`], thesis figures 3.6 and 3.8).
//! [`hash`] is the one stable hash (XXH3-64) behind every cache key, checksum and golden
//! image hash.
//!
//! Off the rendering path: [`acquire`] measures any BRDF as an SH data set (projection,
//! least squares, error and ringing reports) or fits a D-BRDF to it (thesis 2.3.3-2.3.6).
//! [`sweep`] renders a grid of configurations (every `[env] method` and its parameters, on
//! any scene or one of three material classes) against the converged reference (run time
//! against error, Pareto front); [`turntable`] renders animated sequences; [`shard`] splits
//! either over machines. [`export`] writes a scene's resolved camera matrices, mesh,
//! lights and material for a GPU build to draw the same frame. [`view`] is the interactive
//! viewer (`brdfkit view`: a window, winit + softbuffer, each frame [`render::render_into`]
//! of a scene file it can write out).
//!
//! Behind the cargo feature `gpu`: `gpu`, a wgpu renderer of the same resolved scene (WGSL
//! written from the thesis and [`conventions`], not from the kernels), which `brdfkit render
//! --device gpu` and `brdfkit golden check --device gpu` use (docs/gpu.md); it sits beside
//! [`render`] in the layering and imports no tool.
//!
//! ## Layering
//! Dependencies point one way, leaf first, with no import cycle between modules or between
//! files: a module imports only modules of the layers before its own (the list below, which
//! tests/integration/architecture.rs reads and checks on all non-test code). The main path is
//! [`conventions`] -> [`brdf`] -> [`sh`] -> [`material`] -> [`kernel`] -> [`shade`] ->
//! [`render`] -> tools -> [`cli`]; off it, [`acquire`] (after [`sh`]) -> [`library`] (after
//! [`material`], which it builds) -> [`scene`] (which resolves a library name).
//! 1. [`conventions`], [`error`], [`hash`], [`progress`], [`lanes`]: the leaves ([`lanes`] is
//!    the one SIMD wrapper, below every module that computes in lanes: the kernels, and any
//!    other hot loop of a layer before theirs).
//! 2. [`image_io`]: files in and out.
//! 3. [`brdf`], [`light`], [`mesh`], [`raster`], [`metrics`], [`shard`]: models, geometry, measures.
//! 4. [`sh`], [`compare`]: SH data sets (which implement the BRDF trait); image comparison.
//! 5. [`material`], [`acquire`]: the closed set of models; measuring a model as an SH data set.
//! 6. [`kernel`], [`env`](mod@env), [`library`]: the lane kernels; the environment prepared
//!    (its lookups on the kernel's lanes, as the transfer table's, live in [`shade`]); the
//!    library of materials.
//! 7. [`scene`]: the scene file resolved into its parts.
//! 8. [`shade`]: pixels shaded.
//! 9. [`aov`]: debug outputs (surfaces and views as shading sees them).
//! 10. [`render`], [`export`], `gpu`: the frame (CPU, or the wgpu renderer beside it);
//!     the scene written out for a GPU build.
//! 11. [`golden`], [`sweep`], [`turntable`], [`view`]: the tools.
//! 12. [`cli`]: the command line.
//!
//! A file format sits beside the type it stores ([`sh::file`], [`brdf::dbrdf::file`],
//! [`env::lightset::file`], [`env::transfer::file`]); a model never names a consumer (the BRDF trait has no hooks for the
//! kernels: they match on [`material::Material`]).
//!
//! ## Adding an environment method
//! An `[env] method` is a variant of two closed enums: [`env::schema::EnvMethod`], the
//! method as the scene file and the command line name it (with `auto`), and
//! [`scene::Environment`], what the method prepared, which [`scene::Scene`] holds. Every
//! per-method answer is a method of one of the two, an exhaustive `match` without a
//! wildcard arm, and no consumer matches the method itself: adding the two variants, the
//! compiler names every site that must say what the method does, 22 matches in 4 files
//! (measured with a dummy variant in both enums and `cargo check --all-targets --features
//! gpu`):
//! 1. `src/env/schema.rs`: the `EnvMethod` variant, its name and its `[env]` fields
//!    ([`env::schema::EnvSpec`]);
//! 2. `src/scene/env_table.rs`: the fields it reads ([`scene::method_fields`]; a field of
//!    another method is an error) and how it is written back;
//! 3. `src/scene/env_method.rs`, what the tools ask before anything is built: whether
//!    `auto` may stand for it, whether the GPU build draws it and `export` writes it, the
//!    viewer's refinement ladder and status line, the command line's progress bar for its
//!    preparation;
//! 4. `src/scene/environment.rs`: the `Environment` variant, its arm of
//!    [`scene::build_environment`] (the one function [`scene::Scene::resolve`] and the
//!    sweep build an environment with; a method with a table and exact lights shares the
//!    table methods' steps) and of every method there: its delta lights, the table or cuts
//!    shading adds, turning it, the command line's report, the golden summary, the
//!    viewer's preview, why it has no light list, whether a `[transfer] table` file may
//!    shade beside it.
//!
//! Beside those: the method's own module under [`env`](mod@env) (its preparation; a
//! tabulated one through [`env::transfer::prepare_table`] and a cache entry through
//! [`env::cache_entry`]); a method that adds a term of its own to the image also writes it
//! under [`shade`] and calls it from `shade/entry.rs` through an accessor of
//! [`scene::Environment`], as the transfer table and the light cuts are. The sweep runs a
//! method once [`sweep::MethodKind`] has a variant for it (the sweep's own closed set). Its
//! docs: docs/scene-format.md, docs/environment-methods.md.
//!
//! ## Conventions
//! Every coordinate convention (world axes, spherical angle names, the shading frame and
//! its azimuth, texel centres, probe orientation) lives in [`conventions`], and every other
//! module calls it. Screen space and the fill rule are documented in [`raster::setup`];
//! clip space in [`raster::clip`]; the display encoding in [`image_io`].
//!
//! ## Determinism contract
//! The same scene gives the same bits for any thread count and any tile size. Parallel work
//! is split so that each output value is computed by exactly one task from inputs in a
//! fixed order: vertices and triangle set-up per element (results gathered in source order),
//! binning in triangle order, visibility per tile (ties keep the earlier triangle), shading
//! per pixel. No floating-point reduction crosses a task boundary (sums over parallel work
//! are collected and added in index order). Seeded samplers use explicit seeds. There is
//! no fast-math anywhere. The kernel's instruction set is chosen once per frame from the
//! scene's `render.kernel` ([`lanes::KernelPath`]: `auto`, `portable`, `avx2`,
//! `avx512`; there is no other path), never per thread, and every path gives the same bits:
//! every multiply-add is fused, every lane sum has one order (16-lane vectors compute
//! per-light or per-pixel values only). The golden check demands
//! identical bits on the platform and path that blessed an entry and applies the entry's
//! tolerance elsewhere ([`golden`]). The fast path's polynomial `acos`/`atan2` and FMA
//! contractions are explicit, with stated error bounds; the scalar f32 oracle and the f64
//! path ([`shade::ShadingPath`]) use neither.
//!
//! ## Where the thesis is corrected
//! Every departure from the thesis a GPU port must follow (azimuth range, pole frame, probe
//! solid angles, luminance weights, negative texels, normalised Phong and Blinn-Phong, the
//! D-BRDF normalisation, the view lift, the SH convention) is listed in one place, in the
//! doc of [`conventions`].

// `!(x > 0.0)` is how this crate says "not positive, or NaN" (a NaN must take the
// rejecting branch); rewriting it as `x <= 0.0` would let NaN through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod acquire;
pub mod aov;
pub mod brdf;
pub mod cli;
pub mod compare;
pub mod conventions;
pub mod env;
pub mod error;
pub mod export;
pub mod golden;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod hash;
pub mod image_io;
pub mod kernel;
pub mod lanes;
pub mod library;
pub mod light;
pub mod material;
pub mod mesh;
pub mod metrics;
pub mod progress;
pub mod raster;
pub mod render;
pub mod scene;
pub mod sh;
pub mod shade;
pub mod shard;
pub mod sweep;
pub mod turntable;
pub mod view;
