//! Octahedral hemisphere tables (the parent module doc, "Octahedral hemisphere tables"):
//! the map from a local direction to `(u, v)` in `[-1, 1]^2`, its inverse, texel centres
//! and the clamp-to-edge `GL_LINEAR` texels of an `n x n` table over it. A derived lookup
//! (the D-BRDF's p(h), [`crate::brdf::dbrdf`]) reaches its texel by multiplications and one
//! division from any positive multiple of the direction: no angle is computed.

use super::Scalar;
use glam::{DVec3, Vec3};

/// Hemispherical octahedral coordinates `(u, v)` in `[-1, 1]^2` of a local direction `d`
/// with `d.z >= 0`, any length (module doc, "Octahedral hemisphere tables"):
/// `(d.x + d.y, d.x - d.y) / (|d.x| + |d.y| + d.z)`. A negative `z` is taken as 0 (the
/// horizon); a zero or non-finite `d` maps to the centre `(0, 0)` (documented fallback).
#[inline]
pub fn hemi_oct_encode(d: Vec3) -> (f32, f32) {
    encode_of(d.x, d.y, d.z)
}

/// f64 twin of [`hemi_oct_encode`].
#[inline]
pub fn hemi_oct_encode_f64(d: DVec3) -> (f64, f64) {
    encode_of(d.x, d.y, d.z)
}

/// [`hemi_oct_encode`] and [`hemi_oct_encode_f64`], written once ([`Scalar`]).
#[inline(always)]
fn encode_of<T: Scalar>(x: T, y: T, z: T) -> (T, T) {
    let r = T::ONE / (x.abs() + y.abs() + z.max(T::ZERO));
    if !r.is_finite() || r <= T::ZERO {
        return (T::ZERO, T::ZERO);
    }
    ((x + y) * r, (x - y) * r)
}

/// The unit local direction (z >= 0) of octahedral coordinates `(u, v)` (clamped to
/// `[-1, 1]`), the inverse of [`hemi_oct_encode_f64`] (module doc).
#[inline]
pub fn hemi_oct_decode_f64(u: f64, v: f64) -> DVec3 {
    let (u, v) = (u.clamp(-1.0, 1.0), v.clamp(-1.0, 1.0));
    let x = 0.5 * (u + v);
    let y = 0.5 * (u - v);
    let z = (1.0 - x.abs() - y.abs()).max(0.0);
    DVec3::new(x, y, z).normalize()
}

/// Octahedral coordinate (`u` or `v`) of the centre of texel `i` of `n`: `-1 + (2 i + 1)/n`.
#[inline]
pub fn hemi_oct_texel_center_f64(i: usize, n: usize) -> f64 {
    -1.0 + (2 * i + 1) as f64 / n as f64
}

/// Continuous texel coordinate of octahedral coordinate `u` in an `n`-texel axis, clamped
/// to the first and last centres: `clamp(u n/2 + (n - 1)/2, 0, n - 1)` (module doc). The
/// D-BRDF's lane kernel computes the same expression per lane, with `u n/2` as
/// `(d.x + d.y) ((n/2) / (|d.x| + |d.y| + d.z))`.
#[inline]
pub fn hemi_oct_texel_coord(u: f32, n: usize) -> f32 {
    texel_coord_of(u, n)
}

/// [`hemi_oct_texel_coord`] at any precision ([`Scalar`]).
#[inline(always)]
fn texel_coord_of<T: Scalar>(u: T, n: usize) -> T {
    let n = T::from_usize(n);
    let c = u * (T::HALF * n) + T::HALF * (n - T::ONE);
    if c.is_finite() {
        c.max(T::ZERO).min(n - T::ONE)
    } else {
        T::ZERO
    }
}

/// The four texels and weights of the `GL_LINEAR` lookup (clamp to edge on both axes) of an
/// `n x n` octahedral hemisphere table at the texel coordinates `(cu, cv)` of
/// [`hemi_oct_texel_coord`]: `i0 = min(floor(cu), n - 2)`, `a = cu - i0`, likewise `j0`,
/// `b`. Returns `[(i0, j0, (1-a)(1-b)), (i0+1, j0, a(1-b)), (i0, j0+1, (1-a)b),
/// (i0+1, j0+1, a b)]`. Panics if `n < 2`.
#[inline]
pub fn hemi_oct_bilinear_texels(cu: f32, cv: f32, n: usize) -> [(usize, usize, f32); 4] {
    oct_bilinear_texels_of(cu, cv, n)
}

/// f64 twin of [`hemi_oct_texel_coord`] and [`hemi_oct_bilinear_texels`] together, for
/// reference computations (quadratures over the table).
#[inline]
pub fn hemi_oct_bilinear_texels_f64(u: f64, v: f64, n: usize) -> [(usize, usize, f64); 4] {
    oct_bilinear_texels_of(texel_coord_of(u, n), texel_coord_of(v, n), n)
}

/// [`hemi_oct_bilinear_texels`] at any precision ([`Scalar`]).
#[inline(always)]
fn oct_bilinear_texels_of<T: Scalar>(cu: T, cv: T, n: usize) -> [(usize, usize, T); 4] {
    assert!(n >= 2, "an octahedral table needs n >= 2");
    let last = T::from_usize(n) - T::TWO;
    let (fu, fv) = (cu.floor().min(last), cv.floor().min(last));
    let (a, b) = (cu - fu, cv - fv);
    let (i0, j0) = (fu.to_usize(), fv.to_usize());
    [
        (i0, j0, (T::ONE - a) * (T::ONE - b)),
        (i0 + 1, j0, a * (T::ONE - b)),
        (i0, j0 + 1, (T::ONE - a) * b),
        (i0 + 1, j0 + 1, a * b),
    ]
}
