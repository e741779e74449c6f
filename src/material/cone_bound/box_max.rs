//! The exact largest bilinear blend of a table over a box of texel coordinates: the search
//! both D-BRDF table bounds use (the file's table, `dbrdf.rs`, and the derived one,
//! `dbrdf_derived.rs`).

/// The exact largest bilinear `p` over the box `[u0, u1] x [v0, v1]` of texel
/// coordinates: inside a cell the blend is bilinear, with no interior maximum, and on
/// a cell edge it is linear, so the maximum is at a box corner, where a box edge
/// crosses a grid line, or at a texel centre inside; every such point is a pair of
/// candidates `{u0, integers in (u0, u1), u1} x {v0, integers in (v0, v1), v1}`.
pub(super) fn box_max(
    u0: f32,
    u1: f32,
    v0: f32,
    v1: f32,
    bilinear: impl Fn(f32, f32) -> f32,
) -> f32 {
    let axis = |a: f32, b: f32| {
        let first = a.floor() as i64 + 1;
        let last = b.ceil() as i64 - 1;
        std::iter::once(a)
            .chain((first..=last).map(|k| k as f32))
            .chain(std::iter::once(b))
    };
    let mut best = 0.0f32;
    for v in axis(v0, v1) {
        for u in axis(u0, u1) {
            best = best.max(bilinear(u, v));
        }
    }
    best
}
