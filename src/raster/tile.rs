//! Per-tile visibility: the inner loop of the rasterizer.
//!
//! Design rule: this loop is plain integer arithmetic (edge functions stepped by exact i64
//! adds) plus one f64 depth per covered sample; it never looks outside its tile, so tiles
//! can run on any thread in any order. It reads each triangle from a compact record
//! ([`TileTriangle`]: the edge coefficients, two vertices, 1/area, 1/w, bounds), not from
//! the set-up triangle shading reads.
//!
//! A triangle's pixel rectangle in the tile is walked whole when it fits in one
//! [`BLOCK`] x [`BLOCK`] block (most triangles of a dense mesh); a larger one is walked
//! block by block, each block classified first by the exact edge values at its corners
//! (an edge function is affine, so its extremes over a block are at corners): a block
//! outside one edge is skipped, a block inside all three is written without per-pixel
//! tests, the rest are tested per pixel. A triangle whose vertices span at most 64 pixels
//! per axis (`LANE_EXTENT`) is tested eight pixels of a row at a time in i32 lanes
//! ([`crate::lanes::I32x8`], exact at that extent; the walk runs inside
//! [`crate::lanes::Dispatch::run`], so on AVX2 a row's test is three adds, two ors and a
//! sign mask), its row's depths are computed four at a time in f64 lanes
//! ([`crate::lanes::F64x4`], never fused), and only its covered pixels are visited; the
//! depth test is a select, not a branch. A triangle with one pixel of the tile in its
//! bounds (most of a dense mesh's) is tested at that pixel alone. Every covered pixel's
//! edge values and depth are the same integers and the same f64 expression as the
//! per-pixel walk's (one fragment write, `Walk::write`), so the blocks and lanes change
//! nothing but the work done.

use super::setup::{SetupTriangle, HALF, ONE};
use crate::lanes::{F32x8, I32x8, Isa, Kernel, F64_LANES};

/// Edge of the blocks a large triangle is classified by (pixels).
pub const BLOCK: u32 = 8;

/// Pixels of a row tested at once by the lane walk ([`Walk::walk_lanes`]).
const ROW_LANES: usize = 8;

/// Largest extent, per axis, of a triangle's vertices (fixed point: 64 pixels) for which
/// its edge values at every sample the lane walk evaluates fit in `i32`. With `X`, `Y` the
/// extents, edge k is `a (sx - x_i) + b (sy - y_i)` with `|a| <= Y`, `|b| <= X`; the lane
/// walk's samples lie within `X + 7` pixels in x (a row's last lanes may pass the bounds by
/// up to 7 pixels) and `Y + 1` pixel in y (the row after the last) of a vertex, so
/// `|E| <= Y (X + 7 ONE) + X (Y + ONE) <= 2 * 2^28 + 2^25 < 2^30` (and the bias adds at
/// most 1): exact in i32.
const LANE_EXTENT: i64 = 64 * ONE;

/// A set-up triangle as the tile walk reads it: 80 bytes of what the walk needs, against
/// the 224 of a [`SetupTriangle`] (which shading reads), so each bin entry streams fewer
/// cache lines. Built once per triangle, in parallel, by binning ([`TileTriangle::new`]).
///
/// Edge k of the set-up triangle (opposite vertex k, from vertex k+1 to vertex k+2) is
/// evaluated from a vertex on it, `a_k (X - x_o) + b_k (Y - y_o)` with `o` = vertex 1 for
/// edges 0 and 2 and vertex 2 for edge 1: the same integer as the set-up's `a X + b Y + c`
/// (`c = -(a x_o + b y_o)` for any vertex on the edge, no overflow in i64), so coverage and
/// depth keep their bits. Coordinates fit `i32`: the guard band ([`super::clip`]) and the
/// side limit of [`super::rasterize`] bound them by 2^29 in magnitude.
#[derive(Clone, Copy, Debug, Default)]
pub struct TileTriangle {
    /// Fixed-point position of set-up vertex 1 and of vertex 2.
    origin: [[i32; 2]; 2],
    /// The set-up's edge coefficients `a`, `b` (fixed point; `|a|`, `|b|` < 2^30).
    a: [i32; 3],
    b: [i32; 3],
    /// `1 / area2` (f64), the set-up's 1/w at each vertex.
    inv_area: f64,
    inv_w: [f32; 3],
    /// Inclusive pixel bounds: x min, x max, y min, y max.
    bounds: [u32; 4],
    /// Bit k: edge k is top-left (the set-up's `bias[k]`).
    bias: u8,
    /// The vertices' extents are within [`LANE_EXTENT`]: partial blocks take the lane walk.
    lanes: bool,
}

impl TileTriangle {
    /// The walk's record of `t`.
    #[inline]
    pub fn new(t: &SetupTriangle) -> TileTriangle {
        let i32_of = |v: i64| {
            debug_assert!(
                v.unsigned_abs() < 1 << 30,
                "fixed-point value {v} out of range"
            );
            v as i32
        };
        TileTriangle {
            origin: [
                [i32_of(t.x[1]), i32_of(t.y[1])],
                [i32_of(t.x[2]), i32_of(t.y[2])],
            ],
            a: t.a.map(i32_of),
            b: t.b.map(i32_of),
            inv_area: 1.0 / t.area2 as f64,
            inv_w: t.inv_w,
            bounds: [t.px_min, t.px_max, t.py_min, t.py_max],
            bias: (t.bias[0] | t.bias[1] << 1 | t.bias[2] << 2) as u8,
            lanes: extent(&t.x) <= LANE_EXTENT && extent(&t.y) <= LANE_EXTENT,
        }
    }
}

/// The pixel rectangle a tile covers (inclusive) and its row stride in the tile buffers.
#[derive(Clone, Copy, Debug)]
pub struct TileTarget {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
    pub stride: u32,
}

/// A fault seeded into the block walk, for the test that compares it with the per-pixel
/// reference (tests/integration/raster_blocks.rs): each must make that test fail.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RasterFault {
    /// A block that straddles an edge is written whole, as if inside all three (a trivial
    /// accept that tests the wrong corner).
    PartialBlockAccepted,
    /// The last column of blocks of a large triangle is never visited (a block loop one
    /// short).
    LastBlockColumnSkipped,
    /// The visibility and depth a reused [`super::VisBuffer`] holds from the previous frame
    /// are not cleared before this frame is resolved into it
    /// ([`super::rasterize_into_with_fault`]).
    PreviousFrameKept,
    /// The small-triangle walk (eight pixels of a row at a time) drops the last pixel of a
    /// row's final, partial group of lanes (its bounds mask one lane short).
    LaneTailSkipped,
    /// The walk's compact record ([`TileTriangle`]) evaluates edge 1 from vertex 1, which
    /// is not on it, instead of vertex 2.
    EdgeOriginWrong,
    /// The one-pixel path (a triangle whose bounds hold one pixel of the tile) writes the
    /// pixel without testing the edges, as if the bounds implied coverage.
    OnePixelUntested,
}

/// The tile's output buffers, row-major with the tile's stride.
pub struct TileBuffers<'a> {
    pub visible: &'a mut [u32],
    pub depth: &'a mut [f32],
    pub coverage: Option<&'a mut [u32]>,
}

/// How a block lies with respect to a triangle.
enum BlockClass {
    /// Outside one edge: no pixel covered.
    Outside,
    /// Inside all three edges: every pixel covered.
    Inside,
    /// Neither: test each pixel.
    Partial,
}

/// One triangle as the walk reads it.
struct Walk {
    ti: u32,
    inv_area: f64,
    q: [f64; 3],
    /// Edge steps per pixel in x and in y.
    step_x: [i64; 3],
    step_y: [i64; 3],
    /// The edge coefficients (fixed point).
    a: [i64; 3],
    b: [i64; 3],
    /// Per edge: the fixed-point point it is evaluated from ([`TileTriangle`]).
    origin: [[i64; 2]; 3],
    /// The set-up's `bias` (1 for a top-left edge).
    bias: [i64; 3],
    /// The vertices' extents are within [`LANE_EXTENT`]: partial blocks take the lane walk.
    lanes: bool,
}

impl Walk {
    #[inline(always)]
    fn new(t: &TileTriangle, ti: u32, fault: Option<RasterFault>) -> Self {
        let [v1, v2] = t.origin.map(|o| o.map(i64::from));
        let o1 = if fault == Some(RasterFault::EdgeOriginWrong) {
            v1
        } else {
            v2
        };
        Walk {
            ti,
            inv_area: t.inv_area,
            q: t.inv_w.map(|v| v as f64),
            a: t.a.map(i64::from),
            b: t.b.map(i64::from),
            step_x: t.a.map(|a| a as i64 * ONE),
            step_y: t.b.map(|b| b as i64 * ONE),
            origin: [v1, o1, v1],
            bias: [0, 1, 2].map(|k| (t.bias >> k & 1) as i64),
            lanes: t.lanes,
        }
    }

    /// [`Walk::walk`] with tests, for a triangle whose extents are within [`LANE_EXTENT`]:
    /// each row's pixels are tested [`ROW_LANES`] at a time with i32 edge values (exact,
    /// see [`LANE_EXTENT`]) in the lanes of `s` ([`I32x8`]: per row three adds, two ors and
    /// a sign mask), and only the covered pixels are visited, with the same exact edge values and
    /// the same f64 depth expression as [`Walk::walk`].
    #[inline(always)]
    fn walk_lanes<S: Isa>(
        &self,
        s: S,
        tile: &TileTarget,
        (x0, y0, x1, y1): (u32, u32, u32, u32),
        out: &mut TileBuffers,
        fault: Option<RasterFault>,
    ) {
        let step_x = self.step_x.map(|s| s as i32);
        let step_y = self.step_y.map(|s| s as i32);
        // Lane j's offset from a row's first pixel, per edge.
        let off: [[i32; ROW_LANES]; 3] =
            std::array::from_fn(|k| std::array::from_fn(|j| j as i32 * step_x[k]));
        let off_lanes: [S::I; 3] = std::array::from_fn(|k| s.load_i32(&off[k]));
        // Biased to exact edge value: + 1 - bias.
        let unbias = self.bias.map(|b| (1 - b) as i32);
        for cx in (x0..=x1).step_by(ROW_LANES) {
            let mut n = (x1 - cx + 1).min(ROW_LANES as u32);
            if fault == Some(RasterFault::LaneTailSkipped) && n < ROW_LANES as u32 {
                n -= 1;
            }
            let in_bounds = (1u32 << n) - 1;
            let mut row = self.biased_at(cx, y0).map(|e| e as i32);
            for py in y0..=y1 {
                // Per lane: a sample is outside when one of its biased edge values is
                // negative, so the or of the three has its sign bit set.
                let v = [0, 1, 2].map(|k| s.splat_i32(row[k]).add(off_lanes[k]));
                let outside = v[0].or(v[1]).or(v[2]).sign_mask();
                let mut mask = !outside & in_bounds;
                if mask != 0 {
                    let base = ((py - tile.y0) * tile.stride + (cx - tile.x0)) as usize;
                    // The exact edge values of the row's lanes, and their depths.
                    let exact =
                        [0, 1, 2].map(|k| s.splat_i32(row[k] + unbias[k]).add(off_lanes[k]));
                    let mut z = [0.0f32; ROW_LANES];
                    self.depths(s, exact, n > F64_LANES as u32).store(&mut z);
                    while mask != 0 {
                        let j = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        self.put(base + j, z[j], out);
                    }
                }
                for (r, step) in row.iter_mut().zip(step_y) {
                    *r += step;
                }
            }
        }
    }

    /// Biased edge values at the centre of pixel `(px, py)`: a sample is inside when all
    /// three are >= 0 (inside <=> E + bias > 0 <=> E + bias - 1 >= 0).
    #[inline(always)]
    fn biased_at(&self, px: u32, py: u32) -> [i64; 3] {
        let sx = px as i64 * ONE + HALF;
        let sy = py as i64 * ONE + HALF;
        std::array::from_fn(|k| {
            let [ox, oy] = self.origin[k];
            self.a[k] * (sx - ox) + self.b[k] * (sy - oy) + self.bias[k] - 1
        })
    }

    /// The exact edge values of biased ones ([`Walk::biased_at`]), the bias undone, converted
    /// to f64 as the per-pixel reference converts them.
    #[inline(always)]
    fn exact(&self, e: [i64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| (e[k] - self.bias[k] + 1) as f64)
    }

    /// The fragment write every walk shares: the depth (interpolated 1/w) at a covered
    /// sample of exact edge values `w` (each edge's doubled signed area, fixed point
    /// squared), `(w0 q0 + w1 q1 + w2 q2) * (1 / area2)` in f64, unfused and in this order
    /// (the per-pixel reference's expression), rounded to f32; then the nearer test
    /// (larger 1/w wins, a tie keeps the earlier triangle) and the coverage count at
    /// index `i` of the tile buffers.
    #[inline(always)]
    fn write(&self, i: usize, [w0, w1, w2]: [f64; 3], out: &mut TileBuffers) {
        let q = self.q;
        self.put(
            i,
            ((w0 * q[0] + w1 * q[1] + w2 * q[2]) * self.inv_area) as f32,
            out,
        );
    }

    /// [`Walk::write`]'s depth for a row's eight lanes of exact edge values `e` (i32, see
    /// [`LANE_EXTENT`]), four at a time in f64 lanes ([`crate::lanes::F64x4`]: never fused,
    /// so each lane has the bits of the scalar expression); lanes 4..8 only when `high`
    /// (else they repeat lanes 0..4).
    #[inline(always)]
    fn depths<S: Isa>(&self, s: S, e: [S::I; 3], high: bool) -> S::V {
        let q = self.q.map(|q| s.splat_f64(q));
        let inv_area = s.splat_f64(self.inv_area);
        let half = |h: usize| {
            let w = e.map(|e| s.i32_to_f64(e, h));
            (w[0] * q[0] + w[1] * q[1] + w[2] * q[2]) * inv_area
        };
        let lo = half(0);
        let hi = if high { half(1) } else { lo };
        s.f64_to_f32(lo, hi)
    }

    /// The nearer test and coverage count of a fragment of depth `z` (1/w) at index `i`
    /// of the tile buffers ([`Walk::write`]).
    #[inline(always)]
    fn put(&self, i: usize, z: f32, out: &mut TileBuffers) {
        // Selects, not a branch: which of two overlapping triangles is nearer is no
        // pattern a branch predictor learns.
        let (d, v) = (out.depth[i], out.visible[i]);
        let nearer = z > d;
        out.depth[i] = std::hint::select_unpredictable(nearer, z, d);
        out.visible[i] = std::hint::select_unpredictable(nearer, self.ti, v);
        if let Some(c) = out.coverage.as_deref_mut() {
            c[i] += 1;
        }
    }

    /// Classifies the block of pixels `x0..=x1` x `y0..=y1` by its corners.
    #[inline(always)]
    fn classify(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> BlockClass {
        let e = self.biased_at(x0, y0);
        let (nx, ny) = ((x1 - x0) as i64, (y1 - y0) as i64);
        let mut inside = true;
        for ((e, sx), sy) in e.into_iter().zip(self.step_x).zip(self.step_y) {
            let (dx, dy) = (sx * nx, sy * ny);
            let hi = e + dx.max(0) + dy.max(0);
            if hi < 0 {
                return BlockClass::Outside;
            }
            let lo = e + dx.min(0) + dy.min(0);
            inside &= lo >= 0;
        }
        if inside {
            BlockClass::Inside
        } else {
            BlockClass::Partial
        }
    }

    /// Writes the covered pixels of `x0..=x1` x `y0..=y1`; with `TEST` false every pixel
    /// is covered (a block classified inside).
    #[inline(always)]
    fn walk<const TEST: bool>(
        &self,
        tile: &TileTarget,
        (x0, y0, x1, y1): (u32, u32, u32, u32),
        out: &mut TileBuffers,
    ) {
        let mut row = self.biased_at(x0, y0);
        for py in y0..=y1 {
            let mut e = row;
            let base = ((py - tile.y0) * tile.stride) as usize;
            for px in x0..=x1 {
                if !TEST || (e[0] | e[1] | e[2]) >= 0 {
                    let i = base + (px - tile.x0) as usize;
                    self.write(i, self.exact(e), out);
                }
                for (e, step) in e.iter_mut().zip(self.step_x) {
                    *e += step;
                }
            }
            for (r, step) in row.iter_mut().zip(self.step_y) {
                *r += step;
            }
        }
    }
}

/// Largest minus smallest of three fixed-point coordinates.
#[inline(always)]
fn extent(v: &[i64; 3]) -> i64 {
    v[0].max(v[1]).max(v[2]) - v[0].min(v[1]).min(v[2])
}

/// Resolves visibility for the triangles `bin` (indices into `tris`, the walk's records of
/// the set-up triangles, increasing) in one
/// tile: per pixel the nearest triangle (largest 1/w; ties keep the earlier triangle) and,
/// when `out.coverage` is given, the number of triangles covering it.
#[inline(always)]
pub fn resolve<S: Isa>(
    s: S,
    tile: &TileTarget,
    tris: &[TileTriangle],
    bin: &[u32],
    out: &mut TileBuffers,
    fault: Option<RasterFault>,
) {
    for &ti in bin {
        let t = &tris[ti as usize];
        let [px_min, px_max, py_min, py_max] = t.bounds;
        let x0 = px_min.max(tile.x0);
        let x1 = px_max.min(tile.x1);
        let y0 = py_min.max(tile.y0);
        let y1 = py_max.min(tile.y1);
        if x0 > x1 || y0 > y1 {
            continue;
        }
        let walk = Walk::new(t, ti, fault);
        if x0 == x1 && y0 == y1 {
            // One pixel of the tile in the bounds (most triangles of a dense mesh): its
            // edge values straight from the origins, no stepping, no lanes.
            let e = walk.biased_at(x0, y0);
            if (e[0] | e[1] | e[2]) >= 0 || fault == Some(RasterFault::OnePixelUntested) {
                let i = ((y0 - tile.y0) * tile.stride + (x0 - tile.x0)) as usize;
                walk.write(i, walk.exact(e), out);
            }
            continue;
        }
        if x1 - x0 < BLOCK && y1 - y0 < BLOCK {
            if walk.lanes {
                walk.walk_lanes(s, tile, (x0, y0, x1, y1), out, fault);
            } else {
                walk.walk::<true>(tile, (x0, y0, x1, y1), out);
            }
            continue;
        }
        let last_bx = x0 + (x1 - x0) / BLOCK * BLOCK;
        for by in (y0..=y1).step_by(BLOCK as usize) {
            let by1 = (by + BLOCK - 1).min(y1);
            for bx in (x0..=x1).step_by(BLOCK as usize) {
                if fault == Some(RasterFault::LastBlockColumnSkipped) && bx == last_bx {
                    continue;
                }
                let bx1 = (bx + BLOCK - 1).min(x1);
                let rect = (bx, by, bx1, by1);
                match walk.classify(bx, by, bx1, by1) {
                    BlockClass::Outside => {}
                    BlockClass::Inside => walk.walk::<false>(tile, rect, out),
                    BlockClass::Partial => {
                        if fault == Some(RasterFault::PartialBlockAccepted) {
                            walk.walk::<false>(tile, rect, out);
                        } else if walk.lanes {
                            walk.walk_lanes(s, tile, rect, out, fault);
                        } else {
                            walk.walk::<true>(tile, rect, out);
                        }
                    }
                }
            }
        }
    }
}

/// One tile's [`resolve`] as a lane [`Kernel`], so that
/// [`crate::lanes::Dispatch::run`] compiles the walk for the frame's instruction set.
pub struct ResolveTile<'a, 'b> {
    pub tile: &'a TileTarget,
    pub tris: &'a [TileTriangle],
    pub bin: &'a [u32],
    pub out: &'a mut TileBuffers<'b>,
    pub fault: Option<RasterFault>,
}

impl Kernel for ResolveTile<'_, '_> {
    type Out = ();
    #[inline(always)]
    fn run<S: Isa>(self, s: S) {
        resolve(s, self.tile, self.tris, self.bin, self.out, self.fault);
    }
}
