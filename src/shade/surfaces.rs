//! A tile's surfaces, resolved once: what the fast path's kernels read per visible pixel
//! (world position, normal, shading frame, local view), in structure-of-arrays form,
//! computed eight pixels per vector operation ([`TileSurfaces`]).
//!
//! Design rule: the bits of the per-pixel definitions, pixel by pixel. The surface is
//! [`surface_at_index`]'s (`gbuffer.rs`): the exact integer edge values and their f64
//! product with the triangle's `1 / area2` per pixel as
//! [`crate::raster::SetupTriangle::screen_bary`] computes them (that reciprocal once per
//! triangle of a group of pixels, the triangle's values moved into the lanes of its
//! pixels), then in lanes the same IEEE f32 operations in the same order (the
//! perspective division, the source barycentrics, the interpolated position, normal and
//! tangent, glam's unfused sums and `try_normalize`, the flip of back faces, `1 / depth`).
//! The rare pixels the lanes cannot give (a normal that does not normalise, whose fallback
//! is the facet's normal) and every pixel of a mesh with an exact sphere (the f64 ray
//! intersection) are [`surface_at_index`] itself. The frames and views are
//! `pixel_lanes.rs`'s (the scalar [`super::frame_and_view`]'s bits under
//! [`FrameRule::UP`]; that function itself under any other rule). `tests` checks every
//! field bit for bit against [`super::tile_surfaces`] and [`super::frame_and_view`] on
//! every instruction set.
//!
//! (Past 400 lines because the staging, the lane arithmetic and its scalar fallbacks are
//! one definition that must keep `gbuffer.rs`'s bits, and its test is the comparison that
//! says so.)
//!
//! The arrays are the worker's (`tile.rs`, `TileBuffers`), kept across tiles and frames:
//! each tile rewrites every entry it reads, so nothing of an earlier tile or frame shows.

// The staging loops index several per-lane arrays by the lane (or axis) number, which
// reads as the lane arithmetic it is.
#![allow(clippy::needless_range_loop)]

use super::pixel_lanes::{frame_and_view_lanes, PixelLanes};
use super::traverse::for_each_visible_index;
use super::{frame_and_view, surface_at_index, Surface};
use crate::conventions::{FrameRule, ShadingFrame};
use crate::lanes::{F32x8, Isa, LANES, MAX_LANES};
use crate::mesh::Mesh;
use crate::raster::{PixelRect, VisBuffer};
use glam::Vec3;

/// The visible pixels of one tile in row-major order ([`super::for_each_visible`]'s), a
/// pixel per entry: its surface ([`Surface`]'s fields, `[axis][pixel]`), its shading frame
/// and lifted local view ([`super::frame_and_view`]'s), and where it goes in the band.
/// Every array but `at` is padded to a whole number of [`MAX_LANES`] groups; the padding
/// holds the identity frame and view `+z` (finite values, as empty lanes need).
#[derive(Debug, Default)]
pub(super) struct TileSurfaces {
    /// Index of each pixel in its band's rows ([`super::VisiblePixel::at`]).
    pub at: Vec<usize>,
    /// Each pixel's tile-major index in the visibility buffer and its coordinates.
    pixel: Vec<[u32; 3]>,
    pub position: [Vec<f32>; 3],
    pub normal: [Vec<f32>; 3],
    pub tangent: [Vec<f32>; 3],
    pub front_facing: Vec<bool>,
    pub view_depth: Vec<f32>,
    pub t: [Vec<f32>; 3],
    pub b: [Vec<f32>; 3],
    pub n: [Vec<f32>; 3],
    pub wo: [Vec<f32>; 3],
}

/// Rows of the per-triangle values of [`TileSurfaces::resolve_lanes`]: the set-up
/// vertices' 1/w, the source barycentrics of the set-up vertices (`SRC + 3 j + k`), the
/// source triangle's positions, normals and tangents (`P + 3 j + axis` for vertex `j`).
const INV_W: usize = 0;
const SRC: usize = 3;
const P: usize = 12;
const N: usize = 21;
const T: usize = 30;
const ROWS: usize = 39;

/// A group of up to [`LANES`] pixels staged for [`TileSurfaces::resolve_lanes`]: per lane
/// its screen barycentrics, 1/w and the slot of its triangle, and the values of each of the
/// group's distinct triangles (`tri[slot][row]`, rows as the constants above); a row of the
/// group as lanes is [`Stage::row`].
struct Stage {
    screen: [[f32; LANES]; 3],
    depth: [f32; LANES],
    slot: [f32; LANES],
    tri: [[f32; ROWS]; LANES],
    /// Number of distinct triangles (slots).
    slots: usize,
}

impl Stage {
    /// Row `r` of the per-triangle values, lane by lane (each lane its triangle's; values
    /// moved, never computed). `slot` is [`Stage::slot`] as lanes.
    #[inline(always)]
    fn row<S: Isa>(&self, s: S, slot: S::V, r: usize) -> S::V {
        let mut v = s.splat(self.tri[0][r]);
        for d in 1..self.slots {
            v = slot.select_gt(s.splat(d as f32 - 0.5), s.splat(self.tri[d][r]), v);
        }
        v
    }
}

impl TileSurfaces {
    /// Number of pixels.
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.at.len()
    }

    /// Empties it, keeping its memory.
    pub fn clear(&mut self) {
        self.at.clear();
        self.pixel.clear();
    }

    /// Resolves the visible pixels of tile `rect` of `vis` (rasterized from `mesh`): their
    /// surfaces, and their frames and local views seen from `eye` under `rule`, on the
    /// instruction set `s`. Every entry read afterwards is rewritten.
    #[inline(always)]
    pub fn resolve<S: Isa>(
        &mut self,
        s: S,
        mesh: &Mesh,
        vis: &VisBuffer,
        rect: PixelRect,
        eye: Vec3,
        rule: &FrameRule,
    ) {
        self.clear();
        for_each_visible_index(vis, rect, rect.y0, |at, i, x, y| {
            self.at.push(at);
            self.pixel.push([i as u32, x, y]);
        });
        let count = self.len();
        let padded = count.div_ceil(MAX_LANES) * MAX_LANES;
        for v in self
            .position
            .iter_mut()
            .chain(&mut self.normal)
            .chain(&mut self.tangent)
            .chain(&mut self.t)
            .chain(&mut self.b)
            .chain(&mut self.n)
            .chain(&mut self.wo)
            .chain([&mut self.view_depth])
        {
            v.resize(padded, 0.0);
        }
        self.front_facing.resize(padded, true);
        if mesh.exact_sphere.is_some() && vis.rays.is_some() {
            // The f64 ray intersection, pixel by pixel.
            for k in 0..count {
                let [i, x, y] = self.pixel[k];
                let surf = surface_at_index(mesh, vis, i as usize, x, y).expect("visible");
                self.set_surface(k, &surf);
            }
        } else {
            for o in (0..count).step_by(LANES) {
                self.resolve_lanes(s, mesh, vis, o, (count - o).min(LANES));
            }
        }
        // Padding: a surface at the origin facing +z (overwritten below by the identity
        // frame; what it holds only needs to be finite).
        for p in count..padded {
            self.set_surface(
                p,
                &Surface {
                    position: Vec3::ZERO,
                    normal: Vec3::Z,
                    front_facing: true,
                    view_depth: 0.0,
                    tangent: Vec3::ZERO,
                },
            );
        }
        self.frames(s, count, eye, rule);
    }

    /// The frames and lifted views of the first `count` pixels (the rest padding): in lanes
    /// under [`FrameRule::UP`] (`pixel_lanes.rs`), else [`super::frame_and_view`] per
    /// pixel; the identity frame and `+z` in the padding.
    #[inline(always)]
    fn frames<S: Isa>(&mut self, s: S, count: usize, eye: Vec3, rule: &FrameRule) {
        let padded = self.position[0].len();
        if *rule == FrameRule::UP {
            for o in (0..padded).step_by(LANES) {
                let (nrm, pos) = (load3(s, &self.normal, o), load3(s, &self.position, o));
                let (t, b, n, wo) = frame_and_view_lanes(s, nrm, pos, eye);
                for a in 0..3 {
                    t[a].store(&mut self.t[a][o..]);
                    b[a].store(&mut self.b[a][o..]);
                    n[a].store(&mut self.n[a][o..]);
                    wo[a].store(&mut self.wo[a][o..]);
                }
            }
        } else {
            for k in 0..count {
                let (f, wo) = frame_and_view(&self.surface(k), eye, rule);
                self.set_frame(k, &f, wo);
            }
        }
        for p in count..padded {
            let identity = ShadingFrame {
                t: Vec3::X,
                b: Vec3::Y,
                n: Vec3::Z,
            };
            self.set_frame(p, &identity, Vec3::Z);
        }
    }

    /// Pixels `o .. o + count` (`count <= LANES`), no exact sphere: [`surface_at_index`]
    /// in lanes (module doc).
    #[inline(always)]
    fn resolve_lanes<S: Isa>(
        &mut self,
        s: S,
        mesh: &Mesh,
        vis: &VisBuffer,
        o: usize,
        count: usize,
    ) {
        let mut st = Stage {
            screen: [[0.0; LANES]; 3],
            depth: [0.0; LANES],
            slot: [0.0; LANES],
            tri: [[0.0; ROWS]; LANES],
            slots: 0,
        };
        let mut ids = [u32::MAX; LANES];
        // 1 / (doubled area) of each slot's triangle: SetupTriangle::screen_bary's, once.
        let mut inv_area = [0.0f64; LANES];
        let mut sign = [1.0f32; LANES];
        let tangents = !mesh.tangents.is_empty();
        for p in 0..count {
            let [i, x, y] = self.pixel[o + p];
            let id = vis.visible[i as usize];
            let t = &vis.triangles[id as usize];
            // Pixels of one triangle are mostly neighbours: the last slot first.
            let slot = match ids[..st.slots].iter().rposition(|&d| d == id) {
                Some(d) => d,
                None => {
                    let d = st.slots;
                    st.slots += 1;
                    ids[d] = id;
                    inv_area[d] = 1.0 / t.area2 as f64;
                    let tri = mesh.triangles[t.source as usize];
                    let row = &mut st.tri[d];
                    for j in 0..3 {
                        row[INV_W + j] = t.inv_w[j];
                        let v = tri[j] as usize;
                        for a in 0..3 {
                            row[SRC + 3 * j + a] = t.src_bary[j][a];
                            row[P + 3 * j + a] = mesh.positions[v][a];
                            row[N + 3 * j + a] = mesh.normals[v][a];
                            if tangents {
                                row[T + 3 * j + a] = mesh.tangents[v][a];
                            }
                        }
                    }
                    d
                }
            };
            // SetupTriangle::screen_bary: the exact edge values times 1 / area2, in f64.
            let e = t.edges_at(x, y);
            for j in 0..3 {
                st.screen[j][p] = (e[j] as f64 * inv_area[slot]) as f32;
            }
            st.slot[p] = slot as f32;
            st.depth[p] = vis.depth[i as usize];
            sign[p] = if t.front_facing { 1.0 } else { -1.0 };
            self.front_facing[o + p] = t.front_facing;
        }
        // No closure and no `std::array::from_fn` does arithmetic here: one not inlined
        // would not be compiled for `s`'s instruction set.
        let st = &st;
        let slot = s.load(&st.slot);
        let (zero, one) = (s.zero(), s.splat(1.0));
        // SetupTriangle::perspective_bary: q = s / w, normalised by its sum where positive.
        let sb = [
            s.load(&st.screen[0]),
            s.load(&st.screen[1]),
            s.load(&st.screen[2]),
        ];
        let q = [
            sb[0] * st.row(s, slot, INV_W),
            sb[1] * st.row(s, slot, INV_W + 1),
            sb[2] * st.row(s, slot, INV_W + 2),
        ];
        let sum = (q[0] + q[1]) + q[2];
        let w = [
            sum.select_gt(zero, q[0].div(sum), sb[0]),
            sum.select_gt(zero, q[1].div(sum), sb[1]),
            sum.select_gt(zero, q[2].div(sum), sb[2]),
        ];
        // SetupTriangle::source_bary, then the vertices' values interpolated.
        let bary = weighted3(s, st, slot, SRC, &w);
        let position = weighted3(s, st, slot, P, &bary);
        let nrm = weighted3(s, st, slot, N, &bary);
        // try_normalize: `v * (1 / |v|)` where that reciprocal is finite and positive.
        let len2 = (nrm[0] * nrm[0] + nrm[1] * nrm[1]) + nrm[2] * nrm[2];
        let rcp = one.div(len2.sqrt());
        let ok = s.splat(f32::INFINITY).gt_mask(rcp) & rcp.gt_mask(zero);
        let sign = s.load(&sign);
        for a in 0..3 {
            position[a].store(&mut self.position[a][o..]);
            (nrm[a] * rcp * sign).store(&mut self.normal[a][o..]);
        }
        if tangents {
            let tangent = weighted3(s, st, slot, T, &bary);
            for a in 0..3 {
                tangent[a].store(&mut self.tangent[a][o..]);
            }
        } else {
            for a in 0..3 {
                zero.store(&mut self.tangent[a][o..]);
            }
        }
        one.div(s.load(&st.depth)).store(&mut self.view_depth[o..]);
        // The normal's fallbacks (the facet normal, else +y): the scalar definition.
        let fallback = !ok & ((1u32 << count) - 1);
        for p in (0..count).filter(|p| fallback >> p & 1 == 1) {
            let [i, x, y] = self.pixel[o + p];
            let surf = surface_at_index(mesh, vis, i as usize, x, y).expect("visible");
            self.set_surface(o + p, &surf);
        }
    }

    /// **Test only**: `surfaces` as if resolved (their frames and views from `eye` under
    /// `rule` computed as [`TileSurfaces::resolve`] computes them), each `at` its index.
    #[cfg(test)]
    pub fn of_surfaces<S: Isa>(s: S, surfaces: &[Surface], eye: Vec3, rule: &FrameRule) -> Self {
        let count = surfaces.len();
        let padded = count.div_ceil(MAX_LANES) * MAX_LANES;
        let mut out = TileSurfaces {
            at: (0..count).collect(),
            pixel: vec![[0; 3]; count],
            front_facing: vec![true; padded],
            view_depth: vec![0.0; padded],
            ..TileSurfaces::default()
        };
        for v in out
            .position
            .iter_mut()
            .chain(&mut out.normal)
            .chain(&mut out.tangent)
            .chain(&mut out.t)
            .chain(&mut out.b)
            .chain(&mut out.n)
            .chain(&mut out.wo)
        {
            v.resize(padded, 0.0);
        }
        for (k, surf) in surfaces.iter().enumerate() {
            out.set_surface(k, surf);
        }
        out.frames(s, count, eye, rule);
        out
    }

    /// Entry `k`'s surface fields from `surf`.
    #[inline(always)]
    fn set_surface(&mut self, k: usize, surf: &Surface) {
        for a in 0..3 {
            self.position[a][k] = surf.position[a];
            self.normal[a][k] = surf.normal[a];
            self.tangent[a][k] = surf.tangent[a];
        }
        self.front_facing[k] = surf.front_facing;
        self.view_depth[k] = surf.view_depth;
    }

    /// Entry `k`'s frame and view.
    #[inline(always)]
    fn set_frame(&mut self, k: usize, f: &ShadingFrame, wo: Vec3) {
        for a in 0..3 {
            self.t[a][k] = f.t[a];
            self.b[a][k] = f.b[a];
            self.n[a][k] = f.n[a];
            self.wo[a][k] = wo[a];
        }
    }

    /// Pixel `k`'s surface.
    #[inline(always)]
    pub fn surface(&self, k: usize) -> Surface {
        let v = |m: &[Vec<f32>; 3]| Vec3::new(m[0][k], m[1][k], m[2][k]);
        Surface {
            position: v(&self.position),
            normal: v(&self.normal),
            front_facing: self.front_facing[k],
            view_depth: self.view_depth[k],
            tangent: v(&self.tangent),
        }
    }

    /// Pixel `k`'s shading frame and lifted local view ([`super::frame_and_view`]'s).
    #[inline(always)]
    pub fn frame_and_view(&self, k: usize) -> (ShadingFrame, Vec3) {
        let v = |m: &[Vec<f32>; 3]| Vec3::new(m[0][k], m[1][k], m[2][k]);
        let f = ShadingFrame {
            t: v(&self.t),
            b: v(&self.b),
            n: v(&self.n),
        };
        (f, v(&self.wo))
    }

    /// Pixel `k`'s world position.
    #[inline(always)]
    pub fn position(&self, k: usize) -> Vec3 {
        Vec3::new(
            self.position[0][k],
            self.position[1][k],
            self.position[2][k],
        )
    }

    /// Pixel `k`'s world normal.
    #[inline(always)]
    pub fn normal(&self, k: usize) -> Vec3 {
        Vec3::new(self.normal[0][k], self.normal[1][k], self.normal[2][k])
    }

    /// The frames and views of pixels `o .. o + count` (`count <=` [`MAX_LANES`], `o` a
    /// multiple of [`LANES`]) as lanes.
    #[inline(always)]
    pub fn lanes(&self, o: usize, count: usize) -> PixelLanes<'_> {
        debug_assert!(count <= MAX_LANES && o.is_multiple_of(LANES));
        fn at(m: &[Vec<f32>; 3], o: usize) -> [&[f32]; 3] {
            [&m[0][o..], &m[1][o..], &m[2][o..]]
        }
        PixelLanes {
            t: at(&self.t, o),
            b: at(&self.b, o),
            n: at(&self.n, o),
            wo: at(&self.wo, o),
            present: (1u32 << count) - 1,
        }
    }
}

/// `(v0 w0 + v1 w1) + v2 w2` per axis (glam's `Vec3` sums, left to right), the vertex
/// values `v_j[axis]` in rows `r + 3 j + axis` of `st`, the weights `w` per lane.
#[inline(always)]
fn weighted3<S: Isa>(s: S, st: &Stage, slot: S::V, r: usize, w: &[S::V; 3]) -> [S::V; 3] {
    [
        weighted(s, st, slot, r, w),
        weighted(s, st, slot, r + 1, w),
        weighted(s, st, slot, r + 2, w),
    ]
}

/// One axis of [`weighted3`]: rows `r`, `r + 3`, `r + 6`.
#[inline(always)]
fn weighted<S: Isa>(s: S, st: &Stage, slot: S::V, r: usize, w: &[S::V; 3]) -> S::V {
    let v = [
        st.row(s, slot, r),
        st.row(s, slot, r + 3),
        st.row(s, slot, r + 6),
    ];
    (v[0] * w[0] + v[1] * w[1]) + v[2] * w[2]
}

/// Lanes `o .. o + 8` of the three axes of `m`.
#[inline(always)]
fn load3<S: Isa>(s: S, m: &[Vec<f32>; 3], o: usize) -> [S::V; 3] {
    [s.load(&m[0][o..]), s.load(&m[1][o..]), s.load(&m[2][o..])]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::{Dispatch, Kernel, KernelPath};
    use crate::scene::{Scene, SceneFile};
    use crate::shade::tile_surfaces;
    use std::path::Path;

    /// Every occupied tile of a frame resolved: each pixel's `at`, surface, frame and view,
    /// and the padding's frames and views.
    type Resolved = (
        Vec<(usize, Surface, ShadingFrame, Vec3)>,
        Vec<(ShadingFrame, Vec3)>,
    );

    struct Resolve<'a>(&'a Scene, &'a VisBuffer, FrameRule);
    impl Kernel for Resolve<'_> {
        type Out = Resolved;
        fn run<S: Isa>(self, s: S) -> Resolved {
            let Resolve(scene, vis, rule) = self;
            // One buffer for every tile, as a worker keeps it.
            let mut tile = TileSurfaces::default();
            let (mut out, mut padding) = (Vec::new(), Vec::new());
            for t in (0..vis.tile_occupied.len()).filter(|&t| vis.tile_occupied[t]) {
                let eye = scene.camera.position;
                tile.resolve(s, &scene.mesh, vis, vis.tile_rect(t), eye, &rule);
                for k in 0..tile.len() {
                    let (f, wo) = tile.frame_and_view(k);
                    out.push((tile.at[k], tile.surface(k), f, wo));
                }
                for k in tile.len()..tile.t[0].len() {
                    padding.push(tile.frame_and_view(k));
                }
            }
            (out, padding)
        }
    }

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    /// `scene`'s surfaces resolved on every instruction set are the per-pixel definitions'
    /// ([`tile_surfaces`], [`frame_and_view`]) bit for bit; returns how many pixels.
    fn same_bits(what: &str, scene: &Scene, rule: FrameRule) -> usize {
        let vis = crate::render::rasterize(scene, false);
        let eye = scene.camera.position;
        let mut expected = Vec::new();
        let mut one = Vec::new();
        for t in (0..vis.tile_occupied.len()).filter(|&t| vis.tile_occupied[t]) {
            tile_surfaces(&scene.mesh, &vis, vis.tile_rect(t), &mut one);
            expected.extend(one.iter().map(|&(at, surf)| {
                let (f, wo) = frame_and_view(&surf, eye, &rule);
                (at, surf, f, wo)
            }));
        }
        assert!(!expected.is_empty(), "{what}: nothing visible");
        for path in KernelPath::available() {
            let (got, padding) = Dispatch::choose(path)
                .unwrap()
                .run(Resolve(scene, &vis, rule));
            let what = format!("{what} on {}", path.name());
            assert_eq!(got.len(), expected.len(), "{what}");
            for ((at, s, f, wo), (e_at, e, ef, ewo)) in got.iter().zip(&expected) {
                let px = format!("{what} at {e_at}: {e:?}");
                assert_eq!(at, e_at, "{px}");
                assert_eq!(bits(s.position), bits(e.position), "position {px}");
                assert_eq!(bits(s.normal), bits(e.normal), "normal {px}");
                assert_eq!(bits(s.tangent), bits(e.tangent), "tangent {px}");
                assert_eq!(s.front_facing, e.front_facing, "facing {px}");
                assert_eq!(s.view_depth.to_bits(), e.view_depth.to_bits(), "depth {px}");
                assert_eq!(bits(f.t), bits(ef.t), "t {px}");
                assert_eq!(bits(f.b), bits(ef.b), "b {px}");
                assert_eq!(bits(f.n), bits(ef.n), "n {px}");
                assert_eq!(bits(*wo), bits(*ewo), "wo {px}");
            }
            for (f, wo) in padding {
                assert_eq!((f.t, f.b, f.n, wo), (Vec3::X, Vec3::Y, Vec3::Z, Vec3::Z));
            }
        }
        expected.len()
    }

    /// The default teapot (two-sided: back faces seen inside) at 200 x 150 in tiles of
    /// `tile_size`.
    fn teapot(tile_size: u32) -> Scene {
        let mut s = Scene::default_scene();
        (s.render.width, s.render.height, s.render.tile_size) = (200, 150, tile_size);
        s
    }

    #[test]
    fn resolved_surfaces_have_the_per_pixel_bits() {
        let turned = FrameRule {
            view_azimuth: Some((0.6, 0.8)),
            ..FrameRule::UP
        };
        let scene = teapot(16);
        assert!(!scene.mesh.tangents.is_empty(), "the teapot has tangents");
        same_bits("teapot", &scene, FrameRule::UP);
        same_bits("teapot, tiles of 8", &teapot(8), FrameRule::UP);
        same_bits("teapot, mesh tangents", &scene, FrameRule::MESH_TANGENT);
        same_bits("teapot, view-aligned", &scene, turned);
        // No tangents; and normals that do not normalise (zero, infinite, NaN) at every
        // seventh vertex: the facet normal's fallback, pixel by pixel.
        let mut broken = scene.clone();
        let mesh = std::sync::Arc::make_mut(&mut broken.mesh);
        mesh.tangents.clear();
        for (v, n) in mesh
            .normals
            .iter_mut()
            .enumerate()
            .filter(|(v, _)| v % 7 == 0)
        {
            *n = [Vec3::ZERO, Vec3::INFINITY, Vec3::NAN][v % 3];
        }
        same_bits("teapot, broken normals", &broken, FrameRule::UP);
        // The exact sphere: the f64 ray intersection.
        let text =
            "[mesh]\nsource = \"sphere\"\nsegments = 24\n[render]\nwidth = 64\nheight = 48\n";
        let file = SceneFile::parse(text).unwrap();
        let sphere = Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
        assert!(sphere.mesh.exact_sphere.is_some());
        same_bits("sphere", &sphere, FrameRule::UP);
    }
}
