//! The light-cut term of an environment ([`crate::env::lightcuts`]), added to every visible
//! pixel after the lights are shaded.
//!
//! Two paths ([`add_lightcuts`]): the kernels' path (the default) shares one cut among the
//! pixels of a square of at most [`tile::CUT_TILE`]^2 pixels and shades the cut's
//! representatives through the lane kernels (`tile.rs`, with the derivation of its bound);
//! the scalar-oracle path keeps the per-pixel cut below as the reference.
//!
//! Design rule (per-pixel cut): one cut through the scene's light tree, refined from the root by
//! a max-heap of cluster error bounds (Walter et al. 2005, section 4.2; the criterion and
//! the bound are in [`crate::env::lightcuts`] and [`crate::material::cone_bound`]). The
//! surface, frame and lifted view are those of every other path (`gbuffer.rs`,
//! [`super::frame_and_view`] under the material's [`FrameRule`]); a cluster's light is its
//! representative direction in that frame, shaded as [`super::shade_point`] shades a
//! directional light (`f(wi, wo) cos(polar_i) E` when above the horizon). f32 on every path.
//! Deterministic: the heap's order is a total order on (bound, node index), and the
//! pixel's radiance is summed over the final cut in the heap's storage order, which depends
//! only on the sequence of pushes and pops.

use super::frame_and_view;
use super::traverse::{bands, for_each_tile, for_each_visible, Pass, TileSum};
use crate::conventions::{FrameRule, ShadingFrame};
use crate::env::lightcuts::{LightCuts, LightTree};
use crate::env::LUMINANCE_WEIGHTS;
use crate::image_io::Image;
use crate::kernel::models::LaneModel;
use crate::lanes::Dispatch;
use crate::material::cone_bound::{BoundFault, Cone, ConeBound};
use crate::material::Material;
use crate::raster::{PixelRect, VisBuffer};
use crate::scene::Scene;
use glam::Vec3;
use std::collections::BinaryHeap;
use tile::{shade_square, TileCtx, TilePixel, TileScratch, CUT_TILE};

pub mod tile;

/// Cut sizes of one frame: pixels cut, clusters summed over them, the largest cut, and the
/// pixels whose cut stopped at `cut_max` before meeting `cut_error`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CutStats {
    pub pixels: u64,
    pub clusters: u64,
    pub largest: u64,
    pub capped: u64,
    /// Cuts made: one per pixel on the per-pixel path, one per tile on the tile path.
    pub tiles: u64,
}

impl CutStats {
    /// Mean clusters per pixel (0 with no pixel).
    pub fn mean(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.clusters as f64 / self.pixels as f64
        }
    }
}

impl TileSum for CutStats {
    fn plus(self, o: Self) -> Self {
        self + o
    }
}

impl std::ops::Add for CutStats {
    type Output = CutStats;
    fn add(self, o: CutStats) -> CutStats {
        CutStats {
            pixels: self.pixels + o.pixels,
            clusters: self.clusters + o.clusters,
            largest: self.largest.max(o.largest),
            capped: self.capped + o.capped,
            tiles: self.tiles + o.tiles,
        }
    }
}

/// A cluster of the cut: the heap key (bound bits above, inverted node index below, so
/// the larger bound and then the lower index come first) and its estimate. Both cut paths
/// (per pixel here, per square in `tile.rs`) keep their cut in a heap of these.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cluster {
    pub(super) key: u64,
    pub(super) estimate: Vec3,
}

impl PartialEq for Cluster {
    fn eq(&self, o: &Self) -> bool {
        self.key == o.key
    }
}
impl Eq for Cluster {}
impl PartialOrd for Cluster {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cluster {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.key.cmp(&o.key)
    }
}

impl Cluster {
    /// Node `i` with error bound `err` (a luminance) and `estimate`, under the one ordering
    /// rule of both cut paths: a NaN bound refines first (keyed as `f32::MAX`), a negative
    /// one is clamped to 0, and a bound >= 0 orders as its bits do.
    pub(super) fn new(err: f32, i: usize, estimate: Vec3) -> Cluster {
        let err = if err >= 0.0 {
            err
        } else if err.is_nan() {
            f32::MAX
        } else {
            0.0
        };
        Cluster {
            key: ((err.to_bits() as u64) << 32) | (u32::MAX - i as u32) as u64,
            estimate,
        }
    }
    /// The node index.
    pub(super) fn node(&self) -> usize {
        (u32::MAX - (self.key & 0xffff_ffff) as u32) as usize
    }
    /// The error bound.
    pub(super) fn bound(&self) -> f32 {
        f32::from_bits((self.key >> 32) as u32)
    }
}

#[inline]
pub(super) fn luminance(v: Vec3) -> f32 {
    let w = LUMINANCE_WEIGHTS;
    w[0] as f32 * v.x + w[1] as f32 * v.y + w[2] as f32 * v.z
}

/// One node as a member of the cut: estimate and heap key.
#[inline]
#[allow(clippy::too_many_arguments)]
fn cluster(
    tree: &LightTree,
    i: usize,
    bound: &ConeBound,
    material: &Material,
    frame: &ShadingFrame,
    wo: Vec3,
    fault: BoundFault,
) -> Cluster {
    let e = tree.irradiance[i];
    let wi = frame.to_local(tree.rep[i]);
    let estimate = if wi.z > 0.0 {
        material.eval(wi, wo) * wi.z * e
    } else {
        Vec3::ZERO
    };
    let err = if tree.is_leaf(i) {
        0.0
    } else {
        let c = tree.cone_slot(i);
        let cone = Cone {
            axis: frame.to_local(tree.axis[c]),
            cos: tree.cos_half[c],
            sin: tree.sin_half[c],
            sin_half: tree.sin_quarter[c],
        };
        let b = if fault == BoundFault::None {
            bound.f_cos_max(&cone, wo)
        } else {
            bound.f_cos_max_with_fault(material, &cone, wo, fault)
        };
        luminance(b * e)
    };
    Cluster::new(err, i, estimate)
}

/// The radiance (RGB) of the light tree of `cuts` at a surface with shading frame `frame`,
/// view `wo` (local, above the horizon), and the cut's size and whether `cut_max` stopped
/// it (parent module doc). `heap` is scratch space (cleared first).
fn cut_radiance(
    cuts: &LightCuts,
    bound: &ConeBound,
    material: &Material,
    frame: &ShadingFrame,
    wo: Vec3,
    heap: &mut BinaryHeap<Cluster>,
) -> (Vec3, usize, bool) {
    let tree = &cuts.tree;
    heap.clear();
    if tree.is_empty() {
        return (Vec3::ZERO, 0, false);
    }
    let at = |i: usize| cluster(tree, i, bound, material, frame, wo, cuts.fault);
    let root = at(0);
    let mut total = root.estimate;
    heap.push(root);
    let mut capped = false;
    while let Some(top) = heap.peek() {
        let err = top.bound();
        if !(err > cuts.cut_error * luminance(total)) {
            break;
        }
        if heap.len() >= cuts.cut_max {
            capped = true;
            break;
        }
        let top = heap.pop().expect("peeked");
        let i = top.node();
        let (l, r) = (at(tree.left(i)), at(tree.right(i)));
        total += l.estimate + r.estimate - top.estimate;
        heap.push(l);
        heap.push(r);
    }
    let sum = heap.iter().fold(Vec3::ZERO, |s, c| s + c.estimate);
    (sum, heap.len(), capped)
}

/// Adds the light-cut term of `cuts` to every visible pixel of `image` (rendered from
/// `scene` and `vis`), parallel over bands of one tile row; returns the cut sizes. With
/// `shared = Some(dispatch)` one cut per [`tile::CUT_TILE`]-square of pixels, shaded through
/// the lane kernels on `dispatch` (`tile.rs`, the fast path); with `None` one cut per pixel
/// (the reference, the scalar-oracle path). The material must have a cone bound
/// ([`ConeBound::new`]; [`crate::scene::Scene::resolve`] refuses a scene whose material has
/// none).
pub(in crate::shade) fn add_lightcuts(
    scene: &Scene,
    vis: &VisBuffer,
    cuts: &LightCuts,
    image: &mut Image,
    shared: Option<Dispatch>,
    rule: &FrameRule,
) -> CutStats {
    match shared {
        Some(dispatch) => add_shared_cuts(scene, vis, cuts, image, dispatch, rule),
        None => add_per_pixel_cuts(scene, vis, cuts, image, rule),
    }
}

/// The tile path of [`add_lightcuts`].
fn add_shared_cuts(
    scene: &Scene,
    vis: &VisBuffer,
    cuts: &LightCuts,
    image: &mut Image,
    dispatch: Dispatch,
    rule: &FrameRule,
) -> CutStats {
    let bound = ConeBound::new(&scene.material).expect("resolve checked the material");
    let ctx = TileCtx {
        cuts,
        bound: &bound,
        material: &scene.material,
        model: LaneModel::of(&scene.material),
        includes_cosine: scene.material.as_brdf().includes_cosine(),
        rule: *rule,
    };
    let eye = scene.camera.position;
    // Squares are fixed in image space (CUT_TILE-aligned, whatever the tile size), and a
    // square's pixels are gathered in row-major image order, so the cuts and the sums do
    // not depend on how the frame is cut into tiles: the same bits for any tile size.
    let squares_x = vis.width.div_ceil(CUT_TILE);
    let scratch = || (TileScratch::default(), Vec::<TilePixel>::new());
    let stats = bands(image, CUT_TILE, scratch, |(sc, pixels), by, y0, band| {
        let mut stats = CutStats::default();
        for sx in 0..squares_x as usize {
            // The squares are the tiles of a CUT_TILE cut of the frame.
            let square = PixelRect::tile(
                by * squares_x as usize + sx,
                CUT_TILE,
                squares_x,
                vis.width,
                vis.height,
            );
            let x0 = square.x0;
            pixels.clear();
            for_each_visible(&scene.mesh, vis, square, y0, |p| {
                let (frame, wo) = frame_and_view(&p.surface, eye, rule);
                pixels.push(TilePixel {
                    at: p.at,
                    x: p.x,
                    y: p.y,
                    frame,
                    wo,
                });
            });
            let mut write = |p: &TilePixel, l: Vec3| band[p.at] += l;
            stats = stats + shade_square(dispatch, &ctx, pixels, CUT_TILE, x0, y0, sc, &mut write);
        }
        stats
    });
    stats.into_iter().fold(CutStats::default(), |a, b| a + b)
}

/// The per-pixel path of [`add_lightcuts`] (the reference).
fn add_per_pixel_cuts(
    scene: &Scene,
    vis: &VisBuffer,
    cuts: &LightCuts,
    image: &mut Image,
    rule: &FrameRule,
) -> CutStats {
    let bound = ConeBound::new(&scene.material).expect("resolve checked the material");
    let eye = scene.camera.position;
    let heap = || BinaryHeap::with_capacity(cuts.cut_max + 1);
    for_each_tile(image, vis, Pass::Adds, None, heap, |heap, rect, band| {
        let mut stats = CutStats::default();
        for_each_visible(&scene.mesh, vis, rect, rect.y0, |p| {
            let (frame, wo) = frame_and_view(&p.surface, eye, rule);
            let (l, n, capped) = cut_radiance(cuts, &bound, &scene.material, &frame, wo, heap);
            band[p.at] += l;
            stats = stats
                + CutStats {
                    pixels: 1,
                    clusters: n as u64,
                    largest: n as u64,
                    capped: capped as u64,
                    tiles: 1,
                };
        });
        stats
    })
}

#[cfg(test)]
mod tests_tile;
