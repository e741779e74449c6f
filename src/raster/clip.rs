//! Homogeneous clipping against the near plane and a guard band (Sutherland-Hodgman).
//!
//! Clip space is glam's reverse-Z infinite perspective: a view-space point at distance
//! `w` in front of the camera has clip `w` = that distance. The planes, each as a signed
//! distance that is >= 0 inside:
//! - near: `w - near`;
//! - guard band: `g_x w - x`, `g_x w + x`, `g_y w - y`, `g_y w + y`, with `g` chosen so the
//!   band is [`GUARD_PIXELS`] beyond the screen on every side. Inside the band, fixed-point
//!   screen coordinates stay small enough that edge functions fit in i64 exactly.
//!
//! Watertightness: an intersection point is always computed from the inside vertex towards
//! the outside one (`t = d_in / (d_in - d_out)`), so two triangles sharing an edge compute
//! bit-identical new vertices on it.

use glam::Vec4;

/// How far beyond the screen edge (pixels) the guard band reaches.
pub const GUARD_PIXELS: f32 = 8192.0;

/// A clipped vertex: its clip-space position and its barycentric coordinates with respect
/// to the original triangle (so attributes can be interpolated from the original vertices).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipVertex {
    pub clip: Vec4,
    pub bary: [f32; 3],
}

/// Clip planes for a `width x height` target with near distance `near`.
#[derive(Clone, Copy, Debug)]
pub struct ClipPlanes {
    pub near: f32,
    pub gx: f32,
    pub gy: f32,
}

impl ClipPlanes {
    pub fn new(near: f32, width: u32, height: u32) -> Self {
        ClipPlanes {
            near,
            gx: 1.0 + 2.0 * GUARD_PIXELS / width as f32,
            gy: 1.0 + 2.0 * GUARD_PIXELS / height as f32,
        }
    }

    /// Signed distances of `p` to the five planes (>= 0 inside).
    #[inline]
    fn distances(&self, p: Vec4) -> [f32; 5] {
        [
            p.w - self.near,
            self.gx * p.w - p.x,
            self.gx * p.w + p.x,
            self.gy * p.w - p.y,
            self.gy * p.w + p.y,
        ]
    }

    /// Bit mask of the planes `p` is outside of (bit k set: plane k distance < 0; a NaN
    /// coordinate counts as outside every plane).
    #[inline]
    pub fn outcode(&self, p: Vec4) -> u32 {
        let d = self.distances(p);
        let mut code = 0;
        for (k, dk) in d.iter().enumerate() {
            if !(*dk >= 0.0) {
                code |= 1 << k;
            }
        }
        code
    }

    /// Clips triangle `v` and appends the resulting convex polygon's vertices to `out`
    /// (cleared first). Returns nothing for a triangle wholly outside; fewer than 3 vertices
    /// in `out` means nothing is left.
    pub fn clip_triangle(&self, v: [Vec4; 3], out: &mut Vec<ClipVertex>) {
        out.clear();
        let mut poly: Vec<ClipVertex> = (0..3)
            .map(|k| {
                let mut bary = [0.0; 3];
                bary[k] = 1.0;
                ClipVertex { clip: v[k], bary }
            })
            .collect();
        let mut next = Vec::with_capacity(9);
        for plane in 0..5 {
            next.clear();
            let n = poly.len();
            for i in 0..n {
                let a = poly[i];
                let b = poly[(i + 1) % n];
                let da = self.distances(a.clip)[plane];
                let db = self.distances(b.clip)[plane];
                let a_in = da >= 0.0;
                let b_in = db >= 0.0;
                if a_in {
                    next.push(a);
                }
                if a_in != b_in {
                    // From the inside vertex towards the outside one: symmetric for a shared edge.
                    let (pin, din, pout, dout) = if a_in { (a, da, b, db) } else { (b, db, a, da) };
                    let t = din / (din - dout);
                    next.push(ClipVertex {
                        clip: pin.clip + (pout.clip - pin.clip) * t,
                        bary: std::array::from_fn(|k| {
                            pin.bary[k] + (pout.bary[k] - pin.bary[k]) * t
                        }),
                    });
                }
            }
            std::mem::swap(&mut poly, &mut next);
            if poly.len() < 3 {
                return;
            }
        }
        out.extend_from_slice(&poly);
    }
}
