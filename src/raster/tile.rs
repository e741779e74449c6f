//! Per-tile visibility: the inner loop of the rasterizer.
//!
//! Design rule: this loop is plain integer arithmetic (edge functions stepped by exact i64
//! adds) plus one f64 depth per covered sample; it never looks outside its tile, so tiles
//! can run on any thread in any order.

use super::setup::{SetupTriangle, ONE};
use super::NO_TRIANGLE;

/// The pixel rectangle a tile covers (inclusive) and its row stride in the tile buffers.
#[derive(Clone, Copy, Debug)]
pub struct TileTarget {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
    pub stride: u32,
}

/// Resolves visibility for the triangles `bin` (indices into `tris`, increasing) in one tile.
/// `visible`, `depth` (and `coverage`) are the tile's buffers, row-major with `stride`.
pub fn resolve(
    tile: &TileTarget,
    tris: &[SetupTriangle],
    bin: &[u32],
    visible: &mut [u32],
    depth: &mut [f32],
    mut coverage: Option<&mut [u32]>,
) {
    for &ti in bin {
        let t = &tris[ti as usize];
        let x0 = t.px_min.max(tile.x0);
        let x1 = t.px_max.min(tile.x1);
        let y0 = t.py_min.max(tile.y0);
        let y1 = t.py_max.min(tile.y1);
        if x0 > x1 || y0 > y1 {
            continue;
        }
        let inv_area = 1.0 / t.area2 as f64;
        let q = t.inv_w.map(|v| v as f64);
        // Inside <=> E + bias > 0 <=> (E + bias - 1) >= 0 for all three edges.
        let step_x = t.a.map(|a| a * ONE);
        let step_y = t.b.map(|b| b * ONE);
        let mut row = t.edges_at(x0, y0);
        for (r, bias) in row.iter_mut().zip(t.bias) {
            *r += bias - 1;
        }
        for py in y0..=y1 {
            let mut e = row;
            let base = ((py - tile.y0) * tile.stride) as usize;
            for px in x0..=x1 {
                if (e[0] | e[1] | e[2]) >= 0 {
                    let i = base + (px - tile.x0) as usize;
                    // Undo the bias to get the exact edge values for interpolation.
                    let w0 = (e[0] - t.bias[0] + 1) as f64;
                    let w1 = (e[1] - t.bias[1] + 1) as f64;
                    let w2 = (e[2] - t.bias[2] + 1) as f64;
                    let z = ((w0 * q[0] + w1 * q[1] + w2 * q[2]) * inv_area) as f32;
                    if z > depth[i] {
                        depth[i] = z;
                        visible[i] = ti;
                    }
                    if let Some(c) = coverage.as_deref_mut() {
                        c[i] += 1;
                    }
                }
                for k in 0..3 {
                    e[k] += step_x[k];
                }
            }
            for k in 0..3 {
                row[k] += step_y[k];
            }
        }
    }
    let _ = NO_TRIANGLE;
}
