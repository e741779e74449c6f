//! Triangle setup: projection to fixed-point screen coordinates and integer edge functions.
//!
//! Screen space: x right, y down, pixel `(px, py)` covers `[px, px+1) x [py, py+1)` and is
//! sampled at its centre `(px + 1/2, py + 1/2)`. Coordinates are snapped to
//! [`SUBPIXEL_BITS`] bits of sub-pixel precision; edge functions are then evaluated exactly
//! in i64, so coverage does not depend on the order of operations or on the tile size.
//!
//! Fill rule (top-left, as Direct3D and OpenGL implementations): a pixel centre exactly on
//! an edge belongs to the triangle only if the edge is a top edge (horizontal, with the
//! triangle below it) or a left edge. Two triangles sharing an edge therefore never both
//! cover a centre on it, and never both miss it: a closed mesh covers each pixel once.

use super::clip::ClipVertex;

/// Sub-pixel precision of snapped vertex coordinates (8 bits: 1/256 pixel).
pub const SUBPIXEL_BITS: u32 = 8;
/// One pixel in fixed-point units.
pub const ONE: i64 = 1 << SUBPIXEL_BITS;
/// Half a pixel in fixed-point units (the sample offset of a pixel centre).
pub const HALF: i64 = ONE / 2;

/// A triangle ready to rasterize, oriented so that its (doubled) area is positive.
#[derive(Clone, Copy, Debug)]
pub struct SetupTriangle {
    /// Fixed-point screen positions.
    pub x: [i64; 3],
    pub y: [i64; 3],
    /// Edge function k (opposite vertex k) is `a[k] * X + b[k] * Y + c[k]` at fixed-point
    /// sample position (X, Y); it is the doubled signed area of (edge, sample).
    pub a: [i64; 3],
    pub b: [i64; 3],
    pub c: [i64; 3],
    /// 1 for top-left edges, 0 otherwise: a sample is inside when `E + bias > 0` for all k.
    pub bias: [i64; 3],
    /// Doubled area in fixed-point units squared (> 0).
    pub area2: i64,
    /// 1/w at each vertex (w = view distance), for depth and perspective-correct weights.
    pub inv_w: [f32; 3],
    /// Barycentric coordinates of each vertex with respect to the source triangle.
    pub src_bary: [[f32; 3]; 3],
    /// Index of the source triangle in the mesh.
    pub source: u32,
    /// True when the source triangle faces the camera (counter-clockwise on screen in a
    /// y-up view, the usual convention for outward-facing meshes).
    pub front_facing: bool,
    /// Pixel bounds (inclusive) of the samples the triangle can cover, clamped to the target.
    pub px_min: u32,
    pub py_min: u32,
    pub px_max: u32,
    pub py_max: u32,
}

/// Fixed-point screen position of a clip-space point for a `width x height` target.
/// The point must be inside the guard band (see `clip`), which bounds the result.
#[inline]
pub fn snap(clip: glam::Vec4, width: u32, height: u32) -> (i64, i64) {
    let inv_w = 1.0 / clip.w as f64;
    let sx = (clip.x as f64 * inv_w * 0.5 + 0.5) * width as f64;
    let sy = (0.5 - clip.y as f64 * inv_w * 0.5) * height as f64;
    (round_to_i64(sx * ONE as f64), round_to_i64(sy * ONE as f64))
}

/// `v.round() as i64` (half away from zero; saturating, NaN to 0), without the libm call
/// `f64::round` is on the baseline x86-64 target (no SSE4.1 rounding instruction): the
/// truncation `t` and the remainder `v - t` are exact for `|v| < 2^63` (the remainder's
/// bits are a subset of `v`'s), so stepping `t` away from zero where `|v - t| >= 1/2`
/// gives the same integer bit for bit; beyond that range both saturate. Branch-free: the
/// step is a compare's 0 or 1, since whether a snapped coordinate rounds up is no pattern a
/// branch predictor learns (two mispredicted branches per coordinate made snapping a
/// vertex cost ten times its arithmetic).
#[inline]
pub fn round_to_i64(v: f64) -> i64 {
    let t = v as i64;
    let frac = v - t as f64;
    t.saturating_add((frac >= 0.5) as i64 - (frac <= -0.5) as i64)
}

/// Edge function from `(x0, y0)` to `(x1, y1)` evaluated at `(px, py)` (all fixed-point):
/// positive on the inside of a positively oriented triangle. The reference form used by
/// tests: no incremental stepping.
#[inline]
pub fn edge(x0: i64, y0: i64, x1: i64, y1: i64, px: i64, py: i64) -> i64 {
    (x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)
}

/// Whether the edge from `(x0, y0)` to `(x1, y1)` of a positively oriented triangle is a
/// top or left edge (screen y down; positive orientation is clockwise as seen on screen).
#[inline]
pub fn is_top_left(x0: i64, y0: i64, x1: i64, y1: i64) -> bool {
    let (dx, dy) = (x1 - x0, y1 - y0);
    dy < 0 || (dy == 0 && dx > 0)
}

/// Sets up one (clipped) triangle. Returns `None` for zero-area triangles and, when
/// `cull_back`, for back-facing ones, and for triangles that cover no pixel centre's box.
pub fn setup(
    v: [ClipVertex; 3],
    source: u32,
    width: u32,
    height: u32,
    cull_back: bool,
) -> Option<SetupTriangle> {
    let p = v.map(|cv| snap(cv.clip, width, height));
    setup_snapped(
        p,
        v.map(|cv| cv.clip.w),
        v.map(|cv| cv.bary),
        source,
        width,
        height,
        cull_back,
    )
}

/// The cheap rejections of [`setup_snapped`]: `None` for a zero-area triangle, a back
/// face when `cull_back`, and a triangle whose bounds hold no pixel centre of the target;
/// otherwise the signed doubled area (negative: front-facing) and the inclusive pixel
/// bounds `[x_min, x_max, y_min, y_max]` of the samples it can cover. The rasterizer's
/// first set-up pass keeps only the triangles this accepts (most of a dense mesh's are
/// rejected here), and [`setup_snapped`] starts with it.
#[inline]
pub fn covered_bounds(
    p: [(i64, i64); 3],
    width: u32,
    height: u32,
    cull_back: bool,
) -> Option<(i64, [i64; 4])> {
    let area2 = edge(p[0].0, p[0].1, p[1].0, p[1].1, p[2].0, p[2].1);
    if area2 == 0 {
        return None;
    }
    // Positive area (screen y down) is clockwise on screen: a back face for a
    // counter-clockwise-outward mesh.
    let front_facing = area2 < 0;
    if cull_back && !front_facing {
        return None;
    }
    let [px0, px1, py0, py1] = centre_bounds(p, width, height);
    if px0 > px1 || py0 > py1 {
        return None;
    }
    Some((area2, [px0, px1, py0, py1]))
}

/// The pixels whose centre (`px ONE + HALF`) lies in the bounding box of the snapped
/// vertices `p`, clamped to the image: `[px0, px1, py0, py1]`, inclusive (empty where
/// `px0 > px1` or `py0 > py1`). Integers only, no branch.
#[inline(always)]
fn centre_bounds(p: [(i64, i64); 3], width: u32, height: u32) -> [i64; 4] {
    let x = p.map(|q| q.0);
    let y = p.map(|q| q.1);
    let (xmin, xmax) = (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]));
    let (ymin, ymax) = (y[0].min(y[1]).min(y[2]), y[0].max(y[1]).max(y[2]));
    let lo = |m: i64| (m - HALF + ONE - 1).div_euclid(ONE);
    let hi = |m: i64| (m - HALF).div_euclid(ONE);
    [
        lo(xmin).max(0),
        hi(xmax).min(width as i64 - 1),
        lo(ymin).max(0),
        hi(ymax).min(height as i64 - 1),
    ]
}

/// `covered_bounds(p, width, height, cull_back).is_some()` without branches: the
/// rasterizer's first set-up pass asks it of every triangle of the mesh, and whether a
/// small triangle of a dense mesh holds a pixel centre, or faces the camera, is no pattern a
/// branch predictor learns (the same integers and comparisons, combined with `&`).
#[inline]
pub fn covers_a_centre(p: [(i64, i64); 3], width: u32, height: u32, cull_back: bool) -> bool {
    let area2 = edge(p[0].0, p[0].1, p[1].0, p[1].1, p[2].0, p[2].1);
    let [px0, px1, py0, py1] = centre_bounds(p, width, height);
    (area2 != 0) & !(cull_back & (area2 > 0)) & (px0 <= px1) & (py0 <= py1)
}

/// [`setup`] of a triangle whose vertices are already snapped ([`snap`]): `p` the
/// fixed-point positions, `w` the clip w of each vertex, `src_bary` each vertex's
/// barycentric coordinates in the source triangle. The rasterizer snaps each mesh vertex
/// once and sets up the triangles no plane clips from those (a vertex's snap is a function
/// of its clip position alone, so the result is the same bits as [`setup`]'s). The cheap
/// rejections come first ([`covered_bounds`]: area, facing, no pixel centre in the
/// bounds: most triangles of a dense mesh), before the edge functions and 1/w.
#[inline]
pub fn setup_snapped(
    mut p: [(i64, i64); 3],
    mut w: [f32; 3],
    mut src_bary: [[f32; 3]; 3],
    source: u32,
    width: u32,
    height: u32,
    cull_back: bool,
) -> Option<SetupTriangle> {
    let (area2, [px0, px1, py0, py1]) = covered_bounds(p, width, height, cull_back)?;
    let front_facing = area2 < 0;
    if area2 < 0 {
        p.swap(1, 2);
        w.swap(1, 2);
        src_bary.swap(1, 2);
    }
    let inv_w = w.map(|w| 1.0 / w);
    let area2 = area2.abs();
    let x = p.map(|q| q.0);
    let y = p.map(|q| q.1);
    let mut a = [0; 3];
    let mut b = [0; 3];
    let mut c = [0; 3];
    let mut bias = [0; 3];
    for k in 0..3 {
        // Edge k runs from vertex k+1 to vertex k+2 (opposite vertex k).
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        a[k] = -(y[j] - y[i]);
        b[k] = x[j] - x[i];
        c[k] = -(b[k] * y[i]) - a[k] * x[i];
        bias[k] = is_top_left(x[i], y[i], x[j], y[j]) as i64;
    }
    Some(SetupTriangle {
        x,
        y,
        a,
        b,
        c,
        bias,
        area2,
        inv_w,
        src_bary,
        source,
        front_facing,
        px_min: px0 as u32,
        py_min: py0 as u32,
        px_max: px1 as u32,
        py_max: py1 as u32,
    })
}

impl SetupTriangle {
    /// Edge function values at the centre of pixel `(px, py)`.
    #[inline]
    pub fn edges_at(&self, px: u32, py: u32) -> [i64; 3] {
        let sx = px as i64 * ONE + HALF;
        let sy = py as i64 * ONE + HALF;
        std::array::from_fn(|k| self.a[k] * sx + self.b[k] * sy + self.c[k])
    }

    /// Screen-space (linear) barycentric weights at pixel `(px, py)`, f64 division of the
    /// exact integer edge values.
    #[inline]
    pub fn screen_bary(&self, px: u32, py: u32) -> [f32; 3] {
        let e = self.edges_at(px, py);
        let inv = 1.0 / self.area2 as f64;
        e.map(|v| (v as f64 * inv) as f32)
    }

    /// Perspective-correct weights of the three setup vertices at `(px, py)`.
    #[inline]
    pub fn perspective_bary(&self, px: u32, py: u32) -> [f32; 3] {
        let s = self.screen_bary(px, py);
        let q = [
            s[0] * self.inv_w[0],
            s[1] * self.inv_w[1],
            s[2] * self.inv_w[2],
        ];
        let sum = q[0] + q[1] + q[2];
        if sum > 0.0 {
            q.map(|v| v / sum)
        } else {
            s
        }
    }

    /// Interpolated 1/w at pixel `(px, py)` (affine in screen space): larger is nearer.
    #[inline]
    pub fn depth_at(&self, px: u32, py: u32) -> f32 {
        let s = self.screen_bary(px, py);
        s[0] * self.inv_w[0] + s[1] * self.inv_w[1] + s[2] * self.inv_w[2]
    }

    /// Perspective-correct barycentric coordinates with respect to the *source* triangle.
    #[inline]
    pub fn source_bary(&self, px: u32, py: u32) -> [f32; 3] {
        let w = self.perspective_bary(px, py);
        std::array::from_fn(|k| {
            w[0] * self.src_bary[0][k] + w[1] * self.src_bary[1][k] + w[2] * self.src_bary[2][k]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::round_to_i64;

    #[test]
    fn round_to_i64_is_f64_round_as_i64() {
        let mut v = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            4503599627370495.5,
            -4503599627370495.5,
            4503599627370497.0,
            9.2e18,
            -9.2e18,
            9.3e18,
            -9.3e18,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            255.49999999999997,
            255.5,
        ];
        // Seeded values across the snapped range (x 256, guard band) and at half-integers.
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let u = (x >> 11) as f64 / (1u64 << 53) as f64;
            v.push((u - 0.5) * 2.0e7);
            v.push(((u - 0.5) * 2.0e6).floor() + 0.5);
        }
        for &v in &v {
            assert_eq!(round_to_i64(v), v.round() as i64, "{v:e}");
        }
    }
}
