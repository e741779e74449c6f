//! Octahedral map of the whole sphere, +y at the centre (the parent module doc, "Octahedral
//! sphere grids"): a world direction `d` to `(u, v)` in `[-1, 1]^2` and back. The upper
//! hemisphere (`d.y >= 0`) is the diamond `|u| + |v| <= 1`, the lower one the four corner
//! triangles folded out of it (Praun & Hoppe 2003, "Spherical parametrization and
//! remeshing"; Cigolle et al. 2014, "A survey of efficient representations for independent
//! unit vectors"). The square's border is mirror-symmetric about each edge's midpoint:
//! `(u, 1)` and `(-u, 1)` are the same direction (likewise on the other three edges), so a
//! table on the *vertices* of a `G x G` grid whose border nodes hold their direction's value
//! interpolates bilinearly without a seam.

use super::Scalar;
use glam::{DVec3, Vec3};

/// `+1` for `x >= 0` (also `+0` and `-0`), else `-1`: the fold's sign.
#[inline(always)]
fn sign_nonneg<S: Scalar>(x: S) -> S {
    if x >= S::ZERO {
        S::ONE
    } else {
        -S::ONE
    }
}

/// [`sphere_oct_encode_f64`] of `(x, y, z)` in either precision: the one body of it and of
/// [`sphere_oct_encode`].
#[inline(always)]
fn sphere_oct_encode_of<S: Scalar>(x: S, y: S, z: S) -> (S, S) {
    let s = x.abs() + y.abs() + z.abs();
    if !(s.is_finite() && s > S::ZERO) {
        return (S::ZERO, S::ZERO);
    }
    let (p, q) = (x / s, z / s);
    if y >= S::ZERO {
        (p, q)
    } else {
        (
            (S::ONE - q.abs()) * sign_nonneg(p),
            (S::ONE - p.abs()) * sign_nonneg(q),
        )
    }
}

/// Octahedral coordinates `(u, v)` in `[-1, 1]^2` of a world direction `d` (any positive
/// length; module doc): `(d.x, d.z) / (|d.x| + |d.y| + |d.z|)`, folded when `d.y < 0`. A
/// zero or non-finite `d` maps to the centre `(0, 0)` (+y; documented fallback).
#[inline]
pub fn sphere_oct_encode_f64(d: DVec3) -> (f64, f64) {
    sphere_oct_encode_of(d.x, d.y, d.z)
}

/// f32 form of [`sphere_oct_encode_f64`] (the same expression in f32), for per-pixel lookups.
#[inline]
pub fn sphere_oct_encode(d: Vec3) -> (f32, f32) {
    sphere_oct_encode_of(d.x, d.y, d.z)
}

/// The unit world direction of octahedral coordinates `(u, v)` (clamped to `[-1, 1]`), the
/// inverse of [`sphere_oct_encode_f64`].
#[inline]
pub fn sphere_oct_decode_f64(u: f64, v: f64) -> DVec3 {
    let (u, v) = (u.clamp(-1.0, 1.0), v.clamp(-1.0, 1.0));
    let y = 1.0 - u.abs() - v.abs();
    let (x, z) = if y >= 0.0 {
        (u, v)
    } else {
        (
            (1.0 - v.abs()) * sign_nonneg(u),
            (1.0 - u.abs()) * sign_nonneg(v),
        )
    };
    DVec3::new(x, y, z).normalize()
}

/// Octahedral coordinate of vertex `i` of a grid of `g` cells per side (`g + 1` vertices,
/// both borders included): `-1 + 2 i / g`.
#[inline]
pub fn sphere_oct_vertex(i: usize, g: usize) -> f64 {
    -1.0 + 2.0 * i as f64 / g as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_inverts_decode_and_the_border_is_mirror_symmetric() {
        let g = 16;
        for i in 0..=g {
            for j in 0..=g {
                let (u, v) = (sphere_oct_vertex(i, g), sphere_oct_vertex(j, g));
                let d = sphere_oct_decode_f64(u, v);
                assert!((d.length() - 1.0).abs() < 1e-12);
                let (eu, ev) = sphere_oct_encode_f64(d);
                let back = sphere_oct_decode_f64(eu, ev);
                assert!((back - d).length() < 1e-12, "{i} {j}: {d} -> {back}");
                let (fu, fv) = sphere_oct_encode(d.as_vec3());
                assert!((fu as f64 - eu).abs() < 1e-6 && (fv as f64 - ev).abs() < 1e-6);
            }
        }
        for k in 0..=g {
            let a = sphere_oct_vertex(k, g);
            for (p, q) in [((a, 1.0), (-a, 1.0)), ((1.0, a), (1.0, -a))] {
                let (d0, d1) = (
                    sphere_oct_decode_f64(p.0, p.1),
                    sphere_oct_decode_f64(q.0, q.1),
                );
                assert!((d0 - d1).length() < 1e-12, "{p:?} {q:?}");
            }
        }
        assert_eq!(sphere_oct_decode_f64(0.0, 0.0), DVec3::Y);
        assert!((sphere_oct_decode_f64(1.0, 1.0) + DVec3::Y).length() < 1e-12);
        assert!((sphere_oct_decode_f64(1.0, 0.0) - DVec3::X).length() < 1e-12);
        assert!((sphere_oct_decode_f64(0.0, 1.0) - DVec3::Z).length() < 1e-12);
    }
}
