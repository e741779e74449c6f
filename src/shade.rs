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
//! the plain per-light loop over [`Brdf::eval`], is the scalar oracle the kernels are
//! tested against.
//!
//! Per pixel: perspective-correct barycentrics of the source triangle give the world
//! position and the interpolated normal; back faces (two-sided mode) get the normal flipped,
//! so the inside of the teapot is lit as a surface facing the viewer. The shading frame is
//! [`ShadingFrame::from_normal`]. The view direction is clamped to at least
//! [`MIN_VIEW_COS`] above the horizon: interpolated normals can face slightly away from the
//! camera at silhouettes, and a BRDF is not defined there.

use crate::brdf::{eval_cosine_weighted, Brdf};
use crate::conventions::{hemi_texcoord, ShadingFrame};
use crate::image_io::Image;
use crate::kernel::lanes::{Dispatch, F32x8, Isa, Kernel, LANES};
use crate::kernel::models::LaneModel;
use crate::kernel::{self, sh::ShRecurrence, skip, Cone, DirLights};
use crate::light::Light;
use crate::mesh::Mesh;
use crate::raster::{VisBuffer, NO_TRIANGLE};
use crate::scene::Scene;
use crate::sh::dataset::ShDataset;
use glam::Vec3;
use rayon::prelude::*;
use std::borrow::Cow;

/// Smallest cosine between the view direction and the normal used for shading.
pub const MIN_VIEW_COS: f32 = 1e-3;

/// What shading needs to know about the surface seen through one pixel.
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    /// World position.
    pub position: Vec3,
    /// Unit shading normal, flipped towards the viewer for back faces.
    pub normal: Vec3,
    /// Whether the triangle faces the camera.
    pub front_facing: bool,
    /// Distance along the view axis (the clip w).
    pub view_depth: f32,
}

/// The surface seen through pixel `(x, y)`, if any.
#[inline]
pub fn surface_at(mesh: &Mesh, vis: &VisBuffer, x: u32, y: u32) -> Option<Surface> {
    surface_at_index(mesh, vis, vis.index(x, y), x, y)
}

/// [`surface_at`] for a pixel whose tile-major index `i` the caller already knows.
#[inline]
pub fn surface_at_index(mesh: &Mesh, vis: &VisBuffer, i: usize, x: u32, y: u32) -> Option<Surface> {
    let id = vis.visible[i];
    if id == NO_TRIANGLE {
        return None;
    }
    let t = &vis.triangles[id as usize];
    let b = t.source_bary(x, y);
    let tri = mesh.triangles[t.source as usize];
    let [p0, p1, p2] = tri.map(|k| mesh.positions[k as usize]);
    let [n0, n1, n2] = tri.map(|k| mesh.normals[k as usize]);
    let position = p0 * b[0] + p1 * b[1] + p2 * b[2];
    let geometric = (p1 - p0).cross(p2 - p0);
    let mut normal = (n0 * b[0] + n1 * b[1] + n2 * b[2])
        .try_normalize()
        .or_else(|| geometric.try_normalize())
        .unwrap_or(Vec3::Y);
    if !t.front_facing {
        normal = -normal;
    }
    Some(Surface {
        position,
        normal,
        front_facing: t.front_facing,
        view_depth: 1.0 / vis.depth[i],
    })
}

/// Pixels of tile `t` as `(index within the tile, x, y)`, row by row, without divisions
/// per pixel; the padding of edge tiles is left out.
pub fn tile_pixels(vis: &VisBuffer, t: usize) -> impl Iterator<Item = (usize, u32, u32)> + '_ {
    let ts = vis.tile_size;
    let x0 = (t as u32 % vis.tiles_x) * ts;
    let y0 = (t as u32 / vis.tiles_x) * ts;
    let w = ts.min(vis.width - x0);
    let h = ts.min(vis.height - y0);
    (0..h).flat_map(move |ly| (0..w).map(move |lx| ((ly * ts + lx) as usize, x0 + lx, y0 + ly)))
}

/// Local view direction at a surface: `local_from_world(v)`, lifted above the horizon.
#[inline]
pub fn local_view(frame: &ShadingFrame, surface: &Surface, eye: Vec3) -> Vec3 {
    let v = (eye - surface.position).normalize_or(frame.n);
    let mut wo = frame.to_local(v);
    if wo.z < MIN_VIEW_COS {
        let h = (wo.x * wo.x + wo.y * wo.y).sqrt();
        let s = (1.0 - MIN_VIEW_COS * MIN_VIEW_COS).sqrt();
        wo = if h > 0.0 {
            Vec3::new(wo.x / h * s, wo.y / h * s, MIN_VIEW_COS)
        } else {
            Vec3::Z
        };
    }
    wo
}

/// Reflected radiance at one surface point: `sum_k f(l_k, v) cos E_k` (thesis Def. 10).
#[inline]
/// `lights` is the frame's light set (the scene's, less any dropped as negligible).
pub fn shade_point(brdf: &dyn Brdf, lights: &[Light], surface: &Surface, eye: Vec3) -> Vec3 {
    let frame = ShadingFrame::from_normal(surface.normal);
    let wo = local_view(&frame, surface, eye);
    let mut sum = Vec3::ZERO;
    for light in lights {
        let (l, e) = light.at(surface.position);
        let wi = frame.to_local(l);
        if wi.z > 0.0 {
            sum += eval_cosine_weighted(brdf, wi, wo) * e;
        }
    }
    sum
}

/// Everything shading decides once per frame.
pub struct FramePrep<'a> {
    pub brdf: &'a dyn Brdf,
    pub dir: DirLights,
    pub points: Vec<Light>,
    /// The SH data set shaded (truncated to its effective bands when the band skip is on)
    /// and its recurrence constants.
    pub sh: Option<(Cow<'a, ShDataset>, ShRecurrence)>,
    pub eye: Vec3,
    /// Per-tile normal-cone culling of light chunks (on by default; it changes no bit, and
    /// a test proves it by turning it off).
    pub cull_lights: bool,
    /// Live (non-padding, non-black) lights per chunk of `dir`, for the work counters.
    pub chunk_live: Vec<u32>,
    /// Directional lights in the scene, before dropping.
    pub lights_total: usize,
    /// What dropping negligible lights removed ([`skip::drop_weak_lights`]); nothing when
    /// the scene's `render.drop_lights` is 0 or the material has no `|f cos|` bound.
    pub dropped: skip::LightDrop,
    /// Bands stored in the SH data set and bands shaded (0, 0 for other materials).
    pub sh_bands: (usize, usize),
    /// The material's lane form ([`LaneModel::of`]), used when it is not an SH data set.
    pub model: LaneModel<'a>,
    /// The instruction set of the kernels, chosen once per frame from the scene's
    /// `render.kernel` ([`Dispatch::choose`]); the same for every tile and thread, so the
    /// image does not depend on the thread count.
    pub dispatch: Dispatch,
    /// **Test only**: a seeded fault of the SH kernel path ([`KernelFault`]), for the
    /// mutation tests that show [`kernel::SH_KERNEL_TOLERANCE`] catches real faults
    /// (tests/kernel_mutation.rs). Always `None` from [`FramePrep::new`]; no scene setting or
    /// command-line option reaches it. Tested once per pixel (a predictable branch beside
    /// the pixel's lights x `bands^2` x 3 FMAs; on the packed path, twice per pixel and once
    /// per batch), never per light or term.
    #[doc(hidden)]
    pub fault: Option<KernelFault>,
}

/// **Test only**: a fault seeded into the SH path of [`FramePrep`] (its `fault` field), each
/// with exactly the effect a bug in the kernel's loops or basis would have. Applied to the
/// kernel's inputs per pixel (or per batch on the pixel-packed path), so the kernel itself
/// stays as shipped: a zero coefficient or a zero weight adds an exact 0 to an FMA sum,
/// which is what leaving the term or lane out of the loop gives.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelFault {
    /// The terms of the last SH band left out (a band loop one short).
    DropLastBand,
    /// Lane `.0` of every group of [`LANES`] left out: one light per group on the
    /// per-pixel path, one pixel per batch on the packed path (a wrong lane mask).
    DropLane(usize),
    /// The last group left out: the last (padded) group of lights on the per-pixel path,
    /// the last light on the packed path (a group loop one short).
    SkipLastGroup,
    /// The basis read from the data set's basis table
    /// ([`ShDataset::reconstruct_tabulated`]) instead of the analytic basis that defines it
    /// (what earlier versions did for point lights).
    TableBasis,
}

impl<'a> FramePrep<'a> {
    /// Prepares a frame of `scene`, applying the scene's skips (`render.drop_lights`,
    /// `render.band_skip`; see [`crate::kernel::skip`]).
    ///
    /// # Panics
    /// If the scene's `render.kernel` names a path this CPU cannot run: [`Scene::resolve`]
    /// refuses such a scene, so only a scene built in code can get here.
    pub fn new(scene: &'a Scene) -> FramePrep<'a> {
        let brdf = scene.material.as_ref();
        let fraction = match brdf.max_cosine_weighted() {
            Some(_) => scene.render.drop_lights,
            None => 0.0,
        };
        let dropped = skip::drop_weak_lights(&scene.lights, fraction);
        let dir = DirLights::from_lights(&dropped.kept);
        let chunk_live = (0..dir.chunks())
            .map(|c| {
                (c * LANES..(c + 1) * LANES)
                    .filter(|&i| dir.er[i] != 0.0 || dir.eg[i] != 0.0 || dir.eb[i] != 0.0)
                    .count() as u32
            })
            .collect();
        let sh = brdf.as_sh().map(|ds| {
            let keep = if scene.render.band_skip {
                ds.effective_bands()
            } else {
                ds.bands()
            };
            let ds = if keep < ds.bands() {
                Cow::Owned(ds.truncated(keep).expect("1 <= effective bands <= bands"))
            } else {
                Cow::Borrowed(ds)
            };
            let rec = ShRecurrence::new(ds.bands());
            (ds, rec)
        });
        FramePrep {
            brdf,
            sh_bands: match (brdf.as_sh(), &sh) {
                (Some(full), Some((used, _))) => (full.bands(), used.bands()),
                _ => (0, 0),
            },
            dir,
            points: scene
                .lights
                .iter()
                .copied()
                .filter(|l| matches!(l, Light::Point { .. }))
                .collect(),
            model: LaneModel::of(brdf),
            dispatch: Dispatch::choose(scene.render.kernel).unwrap_or_else(|| {
                panic!(
                    "render.kernel = {}: not available on this CPU",
                    scene.render.kernel.name()
                )
            }),
            fault: None,
            sh,
            eye: scene.camera.position,
            cull_lights: true,
            chunk_live,
            lights_total: scene
                .lights
                .iter()
                .filter(|l| matches!(l, Light::Directional { .. }))
                .count(),
            dropped,
        }
    }

    /// Radiance of one surface point lit by the chunks `chunks` of the directional lights
    /// and by every point light, on the instruction set `s` (called from the tile loop,
    /// which [`FramePrep::dispatch`] runs once per tile).
    ///
    /// The lights above the horizon, directional and point alike, go into `scratch` (local
    /// direction, weight `E cos`) and from there through the SH kernel or the material's
    /// lane model.
    #[inline(always)]
    pub fn shade_surface<S: Isa>(
        &self,
        s: S,
        surf: &Surface,
        chunks: &[u32],
        coeff_buf: &mut Vec<f32>,
        scratch: &mut kernel::sh::Scratch,
    ) -> Vec3 {
        let frame = ShadingFrame::from_normal(surf.normal);
        let wo = local_view(&frame, surf, self.eye);
        scratch.clear();
        let includes_cosine = self.brdf.includes_cosine();
        kernel::sh::gather_dir(s, &frame, includes_cosine, &self.dir, chunks, scratch);
        for light in &self.points {
            let (l, e) = light.at(surf.position);
            let wi = frame.to_local(l);
            if wi.z > 0.0 {
                scratch.push(wi, if includes_cosine { e } else { e * wi.z });
            }
        }
        match &self.sh {
            Some((ds, rec)) => {
                if scratch.n == 0 {
                    Vec3::ZERO
                } else {
                    coeff_buf.resize(3 * ds.bands() * ds.bands(), 0.0);
                    let (p, a) = kernel::approx::view_angles(s, wo);
                    let (ts, tt) = hemi_texcoord(p, a);
                    kernel::sh::lookup_coeffs(s, ds, ts, tt, coeff_buf);
                    if let Some(fault) = self.fault {
                        if let Some(sum) = seed_fault(fault, ds, wo, coeff_buf, scratch) {
                            return sum;
                        }
                    }
                    kernel::sh::sh_sum(s, rec, coeff_buf, scratch)
                }
            }
            None => self.model.sum(s, wo, scratch),
        }
    }
}

/// Applies a seeded [`KernelFault`] to one pixel's kernel inputs (its coefficients `c`,
/// `[R.., G.., B..]`, and its light list `sc`); returns the pixel's result when the fault
/// replaces the kernel sum ([`KernelFault::TableBasis`]).
#[cold]
fn seed_fault(
    fault: KernelFault,
    ds: &ShDataset,
    wo: Vec3,
    c: &mut [f32],
    sc: &mut kernel::sh::Scratch,
) -> Option<Vec3> {
    match fault {
        KernelFault::DropLastBand => drop_last_band(c, ds.bands()),
        KernelFault::DropLane(lane) => {
            let end = sc.pad();
            for o in (0..end).step_by(LANES) {
                (sc.wr[o + lane], sc.wg[o + lane], sc.wb[o + lane]) = (0.0, 0.0, 0.0);
            }
        }
        KernelFault::SkipLastGroup => sc.n = (sc.n.div_ceil(LANES) - 1) * LANES,
        KernelFault::TableBasis => {
            return Some((0..sc.n).fold(Vec3::ZERO, |sum, i| {
                let wi = Vec3::new(sc.x[i], sc.y[i], sc.z[i]);
                let w = Vec3::new(sc.wr[i], sc.wg[i], sc.wb[i]);
                sum + ds.reconstruct_tabulated(wi, wo) * w
            }));
        }
    }
    None
}

/// Zeroes the terms of band `bands - 1` in coefficients `[R.., G.., B..]` ([`KernelFault`]).
fn drop_last_band(c: &mut [f32], bands: usize) {
    let t = bands * bands;
    for colour in c.chunks_exact_mut(t) {
        colour[(bands - 1) * (bands - 1)..].fill(0.0);
    }
}

impl FramePrep<'_> {
    /// Up to eight pixels of an SH data set lit only by point lights, one pixel per lane
    /// ([`kernel::sh::sh_sum_packed`]): with a handful of lights, a light per lane would
    /// leave most lanes empty. Same terms as [`FramePrep::shade_surface`]; each pixel's
    /// sum runs in its own lane over the lights in order, so it does not depend on which
    /// pixels share its batch (nor on the tile size or thread count).
    #[inline(always)]
    fn shade_packed<S: Isa>(
        &self,
        s: S,
        ds: &ShDataset,
        rec: &ShRecurrence,
        batch: &[(usize, Surface)],
        buf: &mut Vec<f32>,
        sc: &mut kernel::sh::Scratch,
    ) -> [Vec3; LANES] {
        let t3 = 3 * ds.bands() * ds.bands();
        buf.resize(t3 * (LANES + 1), 0.0);
        let (ct, one) = buf.split_at_mut(t3 * LANES);
        let includes_cosine = self.brdf.includes_cosine();
        let np = self.points.len();
        let mut table_basis = [None; LANES];
        for p in 0..LANES {
            let Some((_, surf)) = batch.get(p) else {
                for k in 0..t3 {
                    ct[k * LANES + p] = 0.0;
                }
                for i in 0..np {
                    let o = i * LANES + p;
                    (sc.x[o], sc.y[o], sc.z[o]) = (0.0, 0.0, 1.0);
                    (sc.wr[o], sc.wg[o], sc.wb[o]) = (0.0, 0.0, 0.0);
                }
                continue;
            };
            let frame = ShadingFrame::from_normal(surf.normal);
            let wo = local_view(&frame, surf, self.eye);
            let (pa, az) = kernel::approx::view_angles(s, wo);
            let (ts, tt) = hemi_texcoord(pa, az);
            kernel::sh::lookup_coeffs(s, ds, ts, tt, one);
            if self.fault == Some(KernelFault::DropLastBand) {
                drop_last_band(one, ds.bands());
            }
            if self.fault == Some(KernelFault::TableBasis) {
                table_basis[p] = Some(self.points.iter().fold(Vec3::ZERO, |sum, light| {
                    let (l, e) = light.at(surf.position);
                    let wi = frame.to_local(l);
                    let w = if includes_cosine { e } else { e * wi.z };
                    sum + ds.reconstruct_tabulated(wi, wo) * w
                }));
            }
            for (k, &c) in one.iter().enumerate() {
                ct[k * LANES + p] = c;
            }
            for (i, light) in self.points.iter().enumerate() {
                let (l, e) = light.at(surf.position);
                let wi = frame.to_local(l);
                // Below the horizon (or degenerate, NaN): weight 0 along the normal, so
                // the lane adds an exact 0.
                let (wi, w) = if wi.z > 0.0 {
                    (wi, if includes_cosine { e } else { e * wi.z })
                } else {
                    (Vec3::Z, Vec3::ZERO)
                };
                let o = i * LANES + p;
                (sc.x[o], sc.y[o], sc.z[o]) = (wi.x, wi.y, wi.z);
                (sc.wr[o], sc.wg[o], sc.wb[o]) = (w.x, w.y, w.z);
            }
        }
        let mut lights = np;
        match self.fault {
            Some(KernelFault::DropLane(lane)) => {
                for i in 0..np {
                    let o = i * LANES + lane;
                    (sc.wr[o], sc.wg[o], sc.wb[o]) = (0.0, 0.0, 0.0);
                }
            }
            Some(KernelFault::SkipLastGroup) => lights = np.saturating_sub(1),
            _ => {}
        }
        let (r, g, b) = kernel::sh::sh_sum_packed(s, rec, ct, lights, sc);
        let (mut ar, mut ag, mut ab) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
        r.store(&mut ar);
        g.store(&mut ag);
        b.store(&mut ab);
        std::array::from_fn(|p| table_basis[p].unwrap_or(Vec3::new(ar[p], ag[p], ab[p])))
    }
}

/// Work done by one [`shade_with_counts`] call, gathered per tile and summed after
/// (integers: the totals do not depend on the thread count or the order of the sum).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadeCounts {
    /// Tiles with at least one triangle, shaded.
    pub tiles_shaded: u64,
    /// Tiles no triangle touched, skipped without looking at a pixel.
    pub tiles_skipped: u64,
    /// Pixels shaded (visible surface).
    pub pixels_shaded: u64,
    /// (pixel x light) pairs handed to the kernel: per tile, its pixels times the live
    /// lights of the chunks its normal cone keeps plus the point lights.
    pub light_pairs: u64,
}

impl std::ops::Add for ShadeCounts {
    type Output = ShadeCounts;
    fn add(self, o: ShadeCounts) -> ShadeCounts {
        ShadeCounts {
            tiles_shaded: self.tiles_shaded + o.tiles_shaded,
            tiles_skipped: self.tiles_skipped + o.tiles_skipped,
            pixels_shaded: self.pixels_shaded + o.pixels_shaded,
            light_pairs: self.light_pairs + o.light_pairs,
        }
    }
}

/// Shades every visible pixel of `vis` into a linear radiance image (background black).
pub fn shade(scene: &Scene, vis: &VisBuffer) -> Image {
    shade_with(&FramePrep::new(scene), scene, vis)
}

/// [`shade`] with explicit frame preparation (to switch optimisations off in tests).
pub fn shade_with(prep: &FramePrep, scene: &Scene, vis: &VisBuffer) -> Image {
    shade_with_counts(prep, scene, vis).0
}

/// [`shade_with`], also returning the work done ([`ShadeCounts`]).
pub fn shade_with_counts(prep: &FramePrep, scene: &Scene, vis: &VisBuffer) -> (Image, ShadeCounts) {
    let mut img = Image::new(vis.width, vis.height);
    let band_len = (vis.width * vis.tile_size) as usize;
    // Per-pixel lists, or the pixel-packed point-light path's eight lanes per light.
    let room = prep.dir.len() + LANES * prep.points.len();
    // Parallel over bands of one tile row (contiguous in the image, so tiles write their
    // pixels in place); each worker keeps its buffers across the tiles it shades.
    let counts: Vec<ShadeCounts> = img
        .pixels
        .par_chunks_mut(band_len)
        .enumerate()
        .map_init(
            || (Vec::new(), kernel::sh::Scratch::default(), Vec::new()),
            |(buf, scratch, surfaces), (ty, band)| {
                let mut counts = ShadeCounts::default();
                for tx in 0..vis.tiles_x as usize {
                    let t = ty * vis.tiles_x as usize + tx;
                    if !vis.tile_occupied[t] {
                        counts.tiles_skipped += 1;
                        continue;
                    }
                    scratch.reserve(room);
                    counts = counts
                        + prep.dispatch.run(ShadeTile {
                            prep,
                            scene,
                            vis,
                            t,
                            band,
                            buf,
                            scratch,
                            surfaces,
                        });
                }
                counts
            },
        )
        .collect();
    let total = counts
        .into_iter()
        .fold(ShadeCounts::default(), |a, b| a + b);
    (img, total)
}

/// One occupied tile, as a [`Kernel`] so the whole tile loop is compiled for the
/// instruction set dispatched once per frame. `band` is the image rows of the tile's row
/// of tiles; buffers are the worker's, reused.
struct ShadeTile<'p, 'a, 'o> {
    prep: &'p FramePrep<'a>,
    scene: &'p Scene,
    vis: &'p VisBuffer,
    t: usize,
    band: &'o mut [Vec3],
    buf: &'o mut Vec<f32>,
    scratch: &'o mut kernel::sh::Scratch,
    surfaces: &'o mut Vec<(usize, Surface)>,
}

impl Kernel for ShadeTile<'_, '_, '_> {
    type Out = ShadeCounts;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> ShadeCounts {
        let ShadeTile {
            prep,
            scene,
            vis,
            t,
            band,
            buf,
            scratch,
            surfaces,
        } = self;
        let per_tile = (vis.tile_size * vis.tile_size) as usize;
        let y0 = (t as u32 / vis.tiles_x) * vis.tile_size;
        surfaces.clear();
        surfaces.extend(tile_pixels(vis, t).filter_map(|(i, x, y)| {
            let at = ((y - y0) * vis.width + x) as usize;
            surface_at_index(&scene.mesh, vis, t * per_tile + i, x, y).map(|s| (at, s))
        }));
        let cone = if prep.cull_lights {
            Cone::around(surfaces.iter().map(|(_, s)| s.normal))
        } else {
            None
        };
        let chunks = prep.dir.chunks_for(cone);
        match &prep.sh {
            Some((ds, rec)) if prep.dir.is_empty() => {
                for batch in surfaces.chunks(LANES) {
                    let rgb = prep.shade_packed(s, ds, rec, batch, buf, scratch);
                    for (k, (at, _)) in batch.iter().enumerate() {
                        band[*at] = rgb[k];
                    }
                }
            }
            _ => {
                for (at, surf) in surfaces.iter() {
                    band[*at] = prep.shade_surface(s, surf, &chunks, buf, scratch);
                }
            }
        }
        let lights = chunks
            .iter()
            .map(|&c| prep.chunk_live[c as usize] as u64)
            .sum::<u64>()
            + prep.points.len() as u64;
        ShadeCounts {
            tiles_shaded: 1,
            tiles_skipped: 0,
            pixels_shaded: surfaces.len() as u64,
            light_pairs: surfaces.len() as u64 * lights,
        }
    }
}

/// The reference render: every light, no culling, the BRDF through [`Brdf::eval_f64`],
/// frames, directions and the light sum in f64; the result is rounded to f32 once per
/// pixel. Used by `brdfkit render --reference` (with the full probe as the light set) and
/// as the converged reference of the run-time-against-error measurements.
pub fn shade_reference_f64(scene: &Scene, vis: &VisBuffer) -> Image {
    use glam::DVec3;
    let mut img = Image::new(vis.width, vis.height);
    let brdf = scene.material.as_ref();
    let eye = scene.camera.position.as_dvec3();
    img.pixels
        .par_chunks_mut(vis.width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, out) in row.iter_mut().enumerate() {
                let Some(s) = surface_at(&scene.mesh, vis, x as u32, y as u32) else {
                    continue;
                };
                let f = ShadingFrame::from_normal(s.normal);
                let (t, b, n) = (f.t.as_dvec3(), f.b.as_dvec3(), f.n.as_dvec3());
                let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
                let p = s.position.as_dvec3();
                let mut wo = local((eye - p).normalize_or(n));
                if wo.z < MIN_VIEW_COS as f64 {
                    let h = (wo.x * wo.x + wo.y * wo.y).sqrt();
                    let c = MIN_VIEW_COS as f64;
                    let sn = (1.0 - c * c).sqrt();
                    wo = if h > 0.0 {
                        DVec3::new(wo.x / h * sn, wo.y / h * sn, c)
                    } else {
                        DVec3::Z
                    };
                }
                let mut sum = DVec3::ZERO;
                for light in &scene.lights {
                    let (l, e) = match *light {
                        Light::Directional {
                            to_light,
                            irradiance,
                        } => (to_light.as_dvec3(), irradiance.as_dvec3()),
                        Light::Point {
                            position,
                            intensity,
                        } => {
                            let d = position.as_dvec3() - p;
                            let d2 = d.length_squared();
                            if !(d2 > 0.0 && d2.is_finite()) {
                                continue;
                            }
                            (
                                d / d2.sqrt(),
                                intensity.as_dvec3()
                                    / d2.max(crate::light::MIN_POINT_DISTANCE2 as f64),
                            )
                        }
                    };
                    let wi = local(l);
                    if wi.z > 0.0 {
                        let f = brdf.eval_f64(wi, wo);
                        sum += if brdf.includes_cosine() { f } else { f * wi.z } * e;
                    }
                }
                *out = sum.as_vec3();
            }
        });
    img
}

/// The scalar oracle: [`shade_point`] at every visible pixel, no kernel, no culling.
///
/// It shades what the fast path shades: the light set and SH bands that [`FramePrep::new`]
/// kept (dropping negligible lights and bands is a decision about the scene, bounded in
/// [`crate::kernel::skip`], not about the kernel), so the two differ only by the kernel's
/// arithmetic. [`shade_reference_f64`] is the other reference: every light, every band, f64.
pub fn shade_reference(scene: &Scene, vis: &VisBuffer) -> Image {
    let mut img = Image::new(vis.width, vis.height);
    let prep = FramePrep::new(scene);
    let brdf: &dyn Brdf = match &prep.sh {
        Some((ds, _)) => ds.as_ref(),
        None => scene.material.as_ref(),
    };
    let lights = &prep.dropped.kept;
    img.pixels
        .par_chunks_mut(vis.width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, out) in row.iter_mut().enumerate() {
                if let Some(s) = surface_at(&scene.mesh, vis, x as u32, y as u32) {
                    *out = shade_point(brdf, lights, &s, scene.camera.position);
                }
            }
        });
    img
}
