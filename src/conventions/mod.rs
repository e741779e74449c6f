//! Every coordinate convention of brdfkit lives here; all other modules call these functions.
//!
//! Design rule: no other module computes an angle from a direction, a direction from an
//! angle, a texel centre or a shading frame by itself. If two modules disagree about a
//! convention, one of them is not calling this module.
//!
//! (Past 400 lines because more than half of it is the conventions' own text below, which a
//! GPU porter reads in one place; the code is under 200 lines, and the frame, the
//! octahedral maps and the scalar trait are files of their own.)
//!
//! # World
//! Right-handed, **y up**, metres (any unit works; nothing depends on scale). The default
//! camera looks along -z. The Utah teapot's patch data is z up and is turned to y up on load
//! (`(x, y, z) -> (x, z, -y)`, see `mesh::teapot`).
//!
//! # Names of the spherical angles
//! The thesis (2.1.3, 3.1.2) calls the polar angle phi and the azimuth theta. Because the
//! literature uses both orders, this crate never uses the Greek names in code: it says
//! `polar` (angle from the normal, thesis phi, radians in [0, pi]) and `azimuth` (thesis
//! theta, radians in [0, 2 pi)).
//!
//! # Shading frame (thesis 3.1.2, corrected)
//! A local frame `(t, b, n)` at a surface point: `n` the unit normal, `t` the world up
//! vector (0, 1, 0) projected onto the tangent plane and normalised, `b = n x t` (the
//! world-up frame; isotropic tabulated and anisotropic materials turn or replace `t`, see
//! the two sections on their frames below). The frame
//! is right-handed: `t x b = n`. Local coordinates of a world direction `d` are
//! `(d.t, d.b, d.n)`, so local +z is the normal. The polar angle is `acos(d.n)` and the
//! azimuth is `atan2(d.b, d.t)` wrapped into [0, 2 pi).
//!
//! The thesis computes the azimuth as `acos(a.b / |a||b|)`, which only spans [0, pi]: it
//! folds azimuth `x` and `-x` together, so an anisotropic BRDF renders mirrored on one side.
//! We use the full range.
//!
//! The projected up vector is computed in a cancellation-free form: for a unit `n`,
//! `up - (up.n) n = (-n.x n.y, n.x^2 + n.z^2, -n.z n.y)`, whose length is
//! `s = sqrt(n.x^2 + n.z^2)`, so `t = (-n.x n.y / s, s, -n.z n.y / s)`. This stays accurate
//! for normals within 1e-7 of up, where the textbook form loses every digit.
//! When `s == 0` (n exactly +-up) the frame uses the limit approached from the +z side:
//! `t = (0, 0, -n.y)`. This is a documented, deterministic choice, not a continuous one:
//! no tangent field on the sphere is continuous (hairy-ball theorem).
//!
//! # Frame of isotropic tabulated materials
//! An isotropic BRDF depends on the light and view only through their polar angles and the
//! difference of their azimuths, so its image cannot depend on the tangent. A tabulated
//! lookup can: an SH data set's coefficients are a table over the view's azimuth, the
//! D-BRDF's `p(h)` an octahedral table over the half vector, and each interpolates
//! differently at different azimuths. Near `n = +-y` the world-up tangent turns quickly
//! from pixel to pixel, so there the lookup's error jumps between neighbours (radial streaks
//! on the teapot's lid). Isotropic tabulated materials are therefore shaded in the frame
//! turned about `n` until the view lies at one fixed azimuth ([`FrameRule::view_at`],
//! [`ShadingFrame::turned_to_view`]): the frame is then a function of `n` and the view
//! alone, and the lookup is always made at the same azimuth. For an SH data set that azimuth
//! is the centre of azimuth texel 0 (`pi / nu`), where both filters return the stored
//! texel exactly; for a D-BRDF it is 0. Analytic isotropic models (Lambert, Phong,
//! Blinn-Phong, isotropic Ashikhmin-Shirley, MERL's half-difference lookup) are exact
//! functions of the angles and keep the world-up tangent.
//!
//! # Frame of anisotropic materials
//! An anisotropic material's azimuth 0 is a direction on the object (the grain of brushed
//! metal, a fabric's warp), so it comes from the mesh ([`FrameRule::MESH_TANGENT`]):
//! [`ShadingFrame::from_normal_tangent`] projects the mesh's tangent interpolated at the
//! pixel (`crate::mesh::Mesh::tangents`, barycentric like the normal) onto the tangent
//! plane, `t = normalize(T - n (n.T))`, `b = n x t`. The tangent `T` is, by mesh:
//! - the teapot: per Bezier patch, the derivative that lies in the planes through the y
//!   axis (the profile on the body, rim, lid, knob and bottom; along the tube on the spout
//!   and handle), signed to run upwards (`crate::mesh::teapot`); zero at the knob apex and
//!   the bottom centre, where the patches are degenerate;
//! - an OBJ file with texture coordinates (`vt` for every vertex): the direction of
//!   increasing u, per triangle from its edges and texture-coordinate differences
//!   (Lengyel 2001), averaged per vertex (`crate::mesh::Mesh::compute_tangents_from_texcoords`);
//! - an OBJ file without texture coordinates, and the UV sphere: none. Those pixels use
//!   the world-up frame above (on the UV sphere about +y that is its parametric tangent
//!   up the meridian).
//!
//! Where the interpolated tangent vanishes or is parallel to the normal (its part in the
//! tangent plane below [`MIN_TANGENT_SIN`] of its length: the teapot's poles, a
//! degenerate texture map) the pixel falls back to the world-up frame too. The thesis uses
//! the world-up tangent for everything; a world-up frame makes an anisotropic material's
//! grain a property of the world's up axis, not of the object (it turns when the object
//! turns on its side), and near `n = +-y` it turns quickly from pixel to pixel.
//!
//! A transfer table stores its environment in the world-up frame of its grid: a pixel in a
//! turned frame rotates its coefficients back by the turn before the dot product
//! ([`crate::sh::rotate_about_z`]).
//!
//! # Texels of hemispherical tables (thesis 3.1.3-3.1.4)
//! A table over the hemisphere with `nu` azimuth texels and `nv` polar texels maps
//! texture coordinates `s = azimuth / 2 pi`, `t = polar / (pi / 2)`. Texel `(i, j)` covers
//! `[i/nu, (i+1)/nu) x [j/nv, (j+1)/nv)` and its value belongs to its centre
//! `((i + 1/2)/nu, (j + 1/2)/nv)`, exactly as OpenGL samples a texture (texel (0,0) is the
//! corner at spherical (0,0); its centre is half a texel in). Azimuth wraps (GL_REPEAT),
//! polar clamps (GL_CLAMP_TO_EDGE).
//!
//! # Octahedral hemisphere tables (derived lookups; the functions are in `octahedral.rs`)
//! A square `n x n` table over the upper hemisphere, addressed by the hemispherical
//! octahedral map of a direction `d` (any positive multiple: no normalisation needed):
//! `(u, v) = (d.x + d.y, d.x - d.y) / (|d.x| + |d.y| + d.z)`, in `[-1, 1]^2`
//! ([`hemi_oct_encode`]). It projects `d` centrally onto the octahedron
//! `|x| + |y| + z = 1` and turns the diamond `|x| + |y| <= 1` by 45 degrees onto the
//! square, so the normal is the centre, the horizon the square's boundary and `u = +-v`
//! the planes `y = 0`, `x = 0`. Inverse ([`hemi_oct_decode_f64`]): `x = (u + v)/2`,
//! `y = (u - v)/2`, `z = 1 - |x| - |y|`, normalised. Texel `(i, j)` (i along `u`) is
//! centred at `u = -1 + (2 i + 1)/n`, `v = -1 + (2 j + 1)/n`, values `[j n + i]`, looked
//! up with `GL_LINEAR` semantics and `GL_CLAMP_TO_EDGE` on both axes
//! ([`hemi_oct_bilinear_texels`]): continuous texel coordinates
//! `U = u n/2 + (n - 1)/2` clamped to `[0, n - 1]`, `i0 = min(floor(U), n - 2)`,
//! `a = U - i0`, `i1 = i0 + 1` (the same value as GL's clamp-to-edge blend; `n >= 2`).
//! The map is continuous and needs one reciprocal and no trigonometry, which is why the
//! D-BRDF's lane kernel looks up its `p(h)` this way ([`crate::brdf::dbrdf`]).
//!
//! # Octahedral sphere grids (functions in `sphere_octahedral.rs`)
//! A table over the whole sphere of world directions (the reflection-space radiance tables,
//! [`crate::env::reflection`]) uses the octahedral map with **+y at the centre**:
//! `(u, v) = (d.x, d.z) / (|d.x| + |d.y| + |d.z|)` for `d.y >= 0`, folded to
//! `((1 - |v|) sign u, (1 - |u|) sign v)` for `d.y < 0` (sign of 0 is +1), so -y is the four
//! corners ([`sphere_oct_encode_f64`], inverse [`sphere_oct_decode_f64`]). Values sit on
//! the vertices of a `G x G` grid (`u = -1 + 2 i / G`, both borders included,
//! [`sphere_oct_vertex`]); the border is mirror-symmetric about each edge's midpoint, so
//! bilinear interpolation over the vertices is continuous everywhere.
//!
//! # Light probes (equirectangular, latitude-longitude)
//! Image `u = (col + 1/2) / width`, `v = (row + 1/2) / height` at texel centres. Row 0 is
//! the top of the image, the +y pole: `polar = pi v` measured from +y. The probe azimuth is
//! `2 pi u`, and the direction is
//! `(-sin(polar) sin(2 pi u), cos(polar), sin(polar) cos(2 pi u))`:
//! **column 0 faces +z** (behind the default camera), the image centre (u = 1/2) faces -z
//! (what the default camera looks at), u = 1/4 faces -x and u = 3/4 faces +x, so the image
//! reads left to right as a viewer turning clockwise seen from above, like a panorama.
//! A probe rotation of `r` radians turns the environment about +y by `r` (right-handed).
//!
//! # Departures from the thesis, in one place (for a GPU porter)
//! A GPU build that reproduces the golden images must follow these, not the thesis's text:
//! 1. **Azimuth** spans [0, 2 pi) through `atan2(d.b, d.t)`; the thesis's `acos` folds
//!    mirror directions together (see "Shading frame" above).
//! 2. **Frame at the poles**: for a normal exactly +-y the tangent is the limit from the +z
//!    side, `t = (0, 0, -n.y)`; the thesis leaves it undefined (see above).
//! 3. **Probe texel solid angles** are exact, `(2 pi / W)(cos(pi j / H) - cos(pi (j+1) / H))`
//!    for row `j`; the thesis's MATLAB (`linspace(-pi/2, pi/2, M)`) puts the first and last
//!    rows on the poles, where its `cos(latitude)` weight is zero, and spaces rows by
//!    `pi / (M - 1)`, not `pi / M` ([`crate::env::probe`]).
//! 4. **Luminance** for importance sampling and median cut is Rec. 709 / sRGB,
//!    `0.2126 R + 0.7152 G + 0.0722 B`; the thesis uses `0.2125 / 0.7154 / 0.0721`
//!    ([`crate::env::luminance`]: it moves sample positions, never total power).
//! 5. **Negative probe texels** (lossy DWAB ringing around bright sources) are set to 0
//!    channel by channel on load and their mass (radiance x solid angle) is taken from the
//!    nearby positive texels, so the probe keeps its local signed integral
//!    ([`crate::env::probe`]); the thesis's probes had none.
//! 6. **Phong and Blinn-Phong are energy-normalised**: `k_s (a + 2) / (2 pi) cos^a` and
//!    `k_s (a + 8) / (8 pi) (n.h)^a` (with `k_d / pi`), not the thesis's unnormalised lobes
//!    (Defs. 3, 4; [`crate::brdf::phong`], [`crate::brdf::blinn_phong`]).
//! 7. **D-BRDF normalisation**, which the thesis does not state: read as a microfacet BRDF
//!    with shadowing `G = ab / (a + b - ab)`, the model has `c = 1/4` and `p(h)` normalised
//!    over projected area, `integral p(h) (h.n) dω_h = 1`, enforced exactly for the file
//!    table's bilinear lookup and kept (to 1e-5) by the octahedral table the renderer
//!    derives from it and evaluates (derivation in [`crate::brdf::dbrdf`]).
//! 8. **View direction lifted above the horizon**: a view direction less than
//!    [`crate::shade::MIN_VIEW_COS`] above the tangent plane (interpolated normals at
//!    silhouettes) is moved to that height at the same azimuth before any lookup.
//! 9. **SH basis**: real, orthonormal over the full sphere, **without** the Condon-Shortley
//!    phase (`Y_11 = +sqrt(3/(4 pi)) x`), index `k = l^2 + l + m`, in the local shading
//!    frame ([`crate::sh::basis`]); evaluated by a normalised recurrence instead of the
//!    thesis's factorials (Def. 11), which overflow f32 near l = 17. Coefficient tables are
//!    sampled like GL textures (texel centres, azimuth `GL_REPEAT`, polar
//!    `GL_CLAMP_TO_EDGE`; see above).
//! 10. **Isotropic tabulated materials in the view-aligned frame**: an isotropic SH data
//!     set (file attribute `brdfkit.isotropic`), an isotropic D-BRDF or Lambert + D-BRDF
//!     lobe is shaded in the frame turned about the normal until the view lies at azimuth
//!     `pi / nu` (SH; the centre of azimuth texel 0) or 0 (D-BRDF), the transfer term's
//!     coefficients turned back into the world-up frame ("Frame of isotropic tabulated
//!     materials" above); the thesis uses one frame for every material, and its tables'
//!     interpolation then depends on the tangent (streaks where the tangent turns fast).
//!     Anisotropic materials take azimuth 0 from the mesh's tangent ("Frame of anisotropic
//!     materials"), not from world up.

mod frame;
mod octahedral;
mod scalar;
mod sphere_octahedral;

pub use frame::*;
pub use octahedral::*;
pub use scalar::{floor_f32, Scalar};
pub use sphere_octahedral::*;

use glam::{DVec3, Vec3};
use std::f32::consts::{PI, TAU};

/// The world up vector, +y.
pub const UP: Vec3 = Vec3::Y;

/// Polar angle and azimuth of a unit direction given in local shading coordinates.
///
/// Returns `(polar, azimuth)` in radians, polar in [0, pi] (acos of the clamped z, so a
/// slightly non-unit input never gives NaN), azimuth in [0, 2 pi).
///
/// At the pole (x = y = 0, any z) the azimuth is not defined, and the result is what
/// IEEE `atan2` gives for signed zeros, wrapped: 0 when x is +0 (y = +0 or -0; the value
/// may be -0.0, which equals 0) and pi when x is -0. Which zero a computed local
/// direction carries depends on the rounding of its dot products, so code that must not
/// depend on it treats the pole itself (a table's azimuth-independent row, SH terms with
/// m = 0 only).
#[inline]
pub fn local_angles(l: Vec3) -> (f32, f32) {
    angles_of(l.x, l.y, l.z)
}

/// [`local_angles`] and [`local_angles_f64`], written once ([`Scalar`]).
#[inline(always)]
fn angles_of<T: Scalar>(x: T, y: T, z: T) -> (T, T) {
    let polar = z.clamp(-T::ONE, T::ONE).acos();
    (polar, wrap(y.atan2(x)))
}

/// Unit local direction from `(polar, azimuth)`: `(sin p cos a, sin p sin a, cos p)`.
#[inline]
pub fn local_direction(polar: f32, azimuth: f32) -> Vec3 {
    Vec3::from(direction_of(polar, azimuth))
}

/// f64 twin of [`local_direction`], for reference computations.
#[inline]
pub fn local_direction_f64(polar: f64, azimuth: f64) -> DVec3 {
    DVec3::from(direction_of(polar, azimuth))
}

/// [`local_direction`] and [`local_direction_f64`], written once ([`Scalar`]).
#[inline(always)]
fn direction_of<T: Scalar>(polar: T, azimuth: T) -> [T; 3] {
    let (sp, cp) = polar.sin_cos();
    let (sa, ca) = azimuth.sin_cos();
    [sp * ca, sp * sa, cp]
}

/// Wraps an angle in radians into [0, 2 pi). Values that round up to exactly 2 pi map to 0.
#[inline]
pub fn wrap_azimuth(a: f32) -> f32 {
    wrap(a)
}

/// [`wrap_azimuth`] at any precision ([`Scalar`]).
#[inline(always)]
fn wrap<T: Scalar>(a: T) -> T {
    let w = a.rem_euclid(T::TAU);
    if w >= T::TAU {
        T::ZERO
    } else {
        w
    }
}

/// Texture coordinates `(s, t)` of a hemispherical table for local angles
/// (thesis 3.1.4): `s = azimuth / 2 pi`, `t = polar / (pi / 2)`.
#[inline]
pub fn hemi_texcoord(polar: f32, azimuth: f32) -> (f32, f32) {
    (azimuth / TAU, polar / (0.5 * PI))
}

/// Centre of texel `i` of `n` along one axis, in texture coordinates: `(i + 1/2) / n`.
#[inline]
pub fn texel_center(i: usize, n: usize) -> f32 {
    texel_center_of(i, n)
}

/// f64 twin of [`texel_center`].
#[inline]
pub fn texel_center_f64(i: usize, n: usize) -> f64 {
    texel_center_of(i, n)
}

/// [`texel_center`] and [`texel_center_f64`], written once ([`Scalar`]).
#[inline(always)]
fn texel_center_of<T: Scalar>(i: usize, n: usize) -> T {
    (T::from_usize(i) + T::HALF) / T::from_usize(n)
}

/// Local angles `(polar, azimuth)` at the centre of texel `(i, j)` of an `nu x nv`
/// hemispherical table (i along azimuth, j along polar), f64.
#[inline]
pub fn hemi_texel_angles_f64(i: usize, j: usize, nu: usize, nv: usize) -> (f64, f64) {
    let azimuth = texel_center_f64(i, nu) * std::f64::consts::TAU;
    let polar = texel_center_f64(j, nv) * std::f64::consts::FRAC_PI_2;
    (polar, azimuth)
}

/// Texel of an `nu x nv` hemispherical table that OpenGL's `GL_NEAREST` filter returns at
/// texture coordinates `(s, t)` (azimuth `GL_REPEAT`, polar `GL_CLAMP_TO_EDGE`):
/// `i = floor(fract(s) nu)`, `j = clamp(floor(t nv), 0, nv - 1)`. A coordinate exactly on a
/// texel edge selects the texel above the edge (floor). Non-finite coordinates map to texel
/// 0 (documented fallback). Panics if `nu` or `nv` is 0.
#[inline]
pub fn hemi_nearest_texel(s: f32, t: f32, nu: usize, nv: usize) -> (usize, usize) {
    assert!(nu > 0 && nv > 0, "empty table");
    let sf = s - floor_f32(s);
    let i = if sf.is_finite() {
        ((sf * nu as f32) as usize).min(nu - 1)
    } else {
        0
    };
    let tj = floor_f32(t * nv as f32);
    let j = if tj.is_finite() && tj > 0.0 {
        (tj as usize).min(nv - 1)
    } else {
        0
    };
    (i, j)
}

/// The four texels and weights that OpenGL's `GL_LINEAR` filter blends at texture
/// coordinates `(s, t)` of an `nu x nv` hemispherical table: `u = s nu - 1/2`,
/// `i0 = floor(u)`, `alpha = u - i0`, `i1 = i0 + 1`, both wrapped mod `nu` (`GL_REPEAT`);
/// likewise `v = t nv - 1/2` with `j0, j1` clamped to `[0, nv - 1]` (`GL_CLAMP_TO_EDGE`).
/// Returns `[(i0, j0, (1-a)(1-b)), (i1, j0, a(1-b)), (i0, j1, (1-a)b), (i1, j1, a b)]`; the
/// weights sum to 1. Non-finite coordinates are treated as 0 (documented fallback).
/// Panics if `nu` or `nv` is 0.
///
/// Inlined into the kernels (per pixel on the packed paths), where `floor` is one
/// instruction; the wrap takes no integer division when `u` is already in range (always,
/// for `s` in `[0, 1)`, but for the half texel below 0).
#[inline(always)]
pub fn hemi_bilinear_texels(s: f32, t: f32, nu: usize, nv: usize) -> [(usize, usize, f32); 4] {
    bilinear_texels_of(s, t, nu, nv)
}

/// [`hemi_bilinear_texels`] and [`hemi_bilinear_texels_f64`], written once ([`Scalar`]).
#[inline(always)]
fn bilinear_texels_of<T: Scalar>(s: T, t: T, nu: usize, nv: usize) -> [(usize, usize, T); 4] {
    assert!(nu > 0 && nv > 0, "empty table");
    let s = if s.is_finite() { s } else { T::ZERO };
    let t = if t.is_finite() { t } else { T::ZERO };
    let u = s * T::from_usize(nu) - T::HALF;
    let v = t * T::from_usize(nv) - T::HALF;
    let (uf, vf) = (u.floor(), v.floor());
    let (a, b) = (u - uf, v - vf);
    let ui = uf.to_i64();
    let i0 = if (0..nu as i64).contains(&ui) {
        ui as usize
    } else {
        ui.rem_euclid(nu as i64) as usize
    };
    let i1 = if i0 + 1 == nu { 0 } else { i0 + 1 };
    let j0 = vf.to_i64().clamp(0, nv as i64 - 1) as usize;
    let j1 = (vf.to_i64() + 1).clamp(0, nv as i64 - 1) as usize;
    [
        (i0, j0, (T::ONE - a) * (T::ONE - b)),
        (i1, j0, a * (T::ONE - b)),
        (i0, j1, (T::ONE - a) * b),
        (i1, j1, a * b),
    ]
}

/// f64 twin of [`local_angles`] for a unit local direction: `(polar, azimuth)`, polar by
/// `acos` of the clamped z, azimuth `atan2(y, x)` wrapped into [0, 2 pi).
#[inline]
pub fn local_angles_f64(l: DVec3) -> (f64, f64) {
    angles_of(l.x, l.y, l.z)
}

/// f64 twin of [`hemi_bilinear_texels`] for the texture coordinates `(s, t)` of f64 angles
/// (`s = azimuth / 2 pi`, `t = polar / (pi/2)`): the same texels, weights in f64.
#[inline]
pub fn hemi_bilinear_texels_f64(s: f64, t: f64, nu: usize, nv: usize) -> [(usize, usize, f64); 4] {
    bilinear_texels_of(s, t, nu, nv)
}

/// Exact solid angle (steradians) of texel row `j` of an `nu x nv` hemispherical table:
/// `(2 pi / nu) (cos(polar_top) - cos(polar_bottom))` with polar edges `j pi/(2 nv)` and
/// `(j + 1) pi/(2 nv)`. The whole table sums to 2 pi.
#[inline]
pub fn hemi_texel_solid_angle(j: usize, nu: usize, nv: usize) -> f64 {
    let h = std::f64::consts::FRAC_PI_2 / nv as f64;
    (std::f64::consts::TAU / nu as f64) * ((j as f64 * h).cos() - ((j + 1) as f64 * h).cos())
}

/// World direction of probe image coordinates `(u, v)` in [0, 1]^2 (see the module doc),
/// before any probe rotation. f64 because probe integration accumulates in f64.
#[inline]
pub fn probe_direction(u: f64, v: f64) -> DVec3 {
    let polar = std::f64::consts::PI * v;
    let az = std::f64::consts::TAU * u;
    let (sp, cp) = polar.sin_cos();
    let (sa, ca) = az.sin_cos();
    DVec3::new(-sp * sa, cp, sp * ca)
}

/// Probe image coordinates `(u, v)` of a world direction, the inverse of
/// [`probe_direction`]: `u` in [0, 1), `v` in [0, 1]. A zero direction gives (0, 0).
#[inline]
pub fn probe_uv(d: DVec3) -> (f64, f64) {
    let d = d.try_normalize().unwrap_or(DVec3::Y);
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
    // d.x = -sin(p) sin(a), d.z = sin(p) cos(a)  =>  a = atan2(-d.x, d.z)
    let mut u = (-d.x).atan2(d.z) / std::f64::consts::TAU;
    if u < 0.0 {
        u += 1.0;
    }
    if u >= 1.0 {
        u = 0.0;
    }
    (u, v)
}

/// Exact solid angle (steradians) of one texel in row `row` of a `width x height`
/// equirectangular probe: `(2 pi / width) (cos(polar_top) - cos(polar_bottom))`.
///
/// Unlike the thesis's `cos(linspace(-pi/2, pi/2, M))` weight, which is zero on the pole
/// rows, this is the true area, positive for every row, and the rows sum to 4 pi.
#[inline]
pub fn probe_texel_solid_angle(row: usize, width: usize, height: usize) -> f64 {
    let pi = std::f64::consts::PI;
    let top = pi * row as f64 / height as f64;
    let bottom = pi * (row + 1) as f64 / height as f64;
    (std::f64::consts::TAU / width as f64) * (top.cos() - bottom.cos())
}

/// Rotates a world direction about +y by `angle` radians, right-handed (counter-clockwise
/// seen from above): `(x cos a + z sin a, y, -x sin a + z cos a)`, so +z turns towards +x
/// for a positive angle. This is the probe rotation of the module doc: a probe rotated by
/// `r` maps texel direction `d` to `rotate_about_up(d, r)`, and a world direction `w` reads
/// the texel at `probe_uv(rotate_about_up(w, -r))`.
#[inline]
pub fn rotate_about_up(d: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    DVec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c)
}

/// Texel `(row, col)` of a `width x height` equirectangular probe containing image
/// coordinates `(u, v)`: `col = floor(u width)`, `row = floor(v height)`, each clamped to
/// the image, so `v = 1` (the -y pole) belongs to the last row. Inverse of the texel centres of the
/// module doc: `probe_texel((col + 1/2)/width, (row + 1/2)/height) = (row, col)`.
#[inline]
pub fn probe_texel(u: f64, v: f64, width: usize, height: usize) -> (usize, usize) {
    let col = ((u * width as f64).floor().max(0.0) as usize).min(width.saturating_sub(1));
    let row = ((v * height as f64).floor().max(0.0) as usize).min(height.saturating_sub(1));
    (row, col)
}

#[cfg(test)]
mod tests;
