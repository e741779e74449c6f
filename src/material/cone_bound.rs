//! Upper bounds of `f_r(wi, wo) cos(polar_i)` over a cone of incident directions, per
//! material: what adaptive light cuts ([`crate::env::lightcuts`]) need to bound a cluster of
//! lights (Walter et al., "Lightcuts: a scalable approach to illumination", SIGGRAPH 2005,
//! section 4.1: the material term's bound over the cluster's bounding volume).
//!
//! Design rule: one function of the closed [`Material`] enum, dispatched by tag
//! ([`ConeBound::new`] precomputes what a model needs once per frame, [`ConeBound::f_cos_max`]
//! answers per cluster); the models in [`crate::brdf`] know nothing of it. Every bound is
//! *valid* (never below `f cos` anywhere in the cone, up to f32 rounding: the tests check
//! it with a relative slack of 1e-4) and tight when the cone is small, which is what makes a
//! cut converge. Units: 1/sr (the BRDF's), RGB. All directions are in the local shading
//! frame of [`crate::conventions`] (normal +z), away from the surface.
//!
//! # Geometry (derivations)
//! A cone is a unit axis `a` and a half angle `alpha` (its cosine, sine and `sin(alpha/2)`).
//! * **Largest cosine to a direction `d`** ([`max_cos_to`]): with `gamma = angle(a, d)`,
//!   `max_{w in cone} w.d = cos(max(0, gamma - alpha))`; for `d = n` this bounds
//!   `cos(polar_i)`. **Smallest** ([`min_cos_to`]): `cos(min(pi, gamma + alpha))`.
//! * **Half vectors** ([`half_vector_cone`]): `h(wi) = (wi + wo)/|wi + wo|`. For `wi` in the
//!   cone, `|wi + wo| >= m = sqrt(2 + 2 min_cone(wi.wo))`, and radial projection onto the
//!   ball of radius `m` is the nearest-point map onto a convex set, hence 1-Lipschitz:
//!   `m |h(wi) - h(a)| <= |wi - a| <= 2 sin(alpha/2)`. So every half vector lies in the cone
//!   around `h(a)` of chord `2 sin(alpha/2)/m`, half angle
//!   `beta = 2 asin(sin(alpha/2)/m)` (the whole sphere when that is >= 1). When
//!   `wo` is near the cone (`m` near 2) `beta` is close to `alpha/2`, the exact value in the
//!   plane of incidence. `k.h = |wi + wo|/2 >= m/2` too.
//!
//! # Bounds per model (`c_i = max cos(polar_i)` over the cone, zero bound when `c_i <= 0`:
//! every model is zero below the horizon)
//! * Lambert: `albedo/pi c_i`.
//! * Phong: `(kd/pi + ks (e+2)/(2pi) max(0, r'.wi)^e) c_i` with `r'` the mirror of `wo`
//!   (`r.wo = wi.r'`), `max r'.wi` by [`max_cos_to`].
//! * Blinn-Phong: `(kd/pi + ks (e+8)/(8pi) (n.h)_max^e) c_i`, `(n.h)_max` from the half
//!   vectors' cone.
//! * Ashikhmin-Shirley: `e(phi_h) = n_u cos^2 phi_h + n_v sin^2 phi_h >= e_min`, the
//!   smallest over the half vectors' azimuth range (below; `min(n_u, n_v)` when it is every
//!   azimuth), and `n.h <= 1`, so `(n.h)^e <= (n.h)_max^e_min`; `cos(polar_i) / max(n.k1, n.k2) <= min(1, c_i/n.k2)`;
//!   `1/(k.h) <= 2/m`; Schlick's `F` is monotone in `k.h`, so at most its value at `m/2` or at 1;
//!   the diffuse term grows with `n.k1`, so it is at most its value at `c_i`, times `c_i`.
//! * D-BRDF: `c p(h) F(k.h) cos(polar_i) / (a + b - a b)`, `a = cos(polar_i)`,
//!   `b = cos(polar_o)`: `a/(a + b - a b)` grows with `a` (derivative `b/D^2`), so it is at most
//!   its value at `c_i`; `F` as above; `p(h)` is a bilinear (`GL_LINEAR`) blend of the four
//!   table texels around `h` ([`crate::conventions::hemi_bilinear_texels`]), so it is at most
//!   the largest texel whose footprint meets the half vectors' cone: the polar range
//!   `[theta_h - beta, theta_h + beta]` and the azimuth range `phi_h +- asin(sin beta / sin
//!   theta_h)` (all azimuths when the cone holds a pole). Over that box of texel
//!   coordinates, up to 3 texels a side, the bilinear blend's exact maximum (at a corner,
//!   an edge's crossing of a grid line, or a texel centre inside: a bilinear cell has no
//!   interior maximum); a larger box takes its footprint's largest texel, two reads per
//!   row from a sparse table of runs ([`DbrdfBound`]; the all-azimuth case reads a
//!   per-row maximum). That is the bound of the *file* table's lookup; the renderer
//!   evaluates the table derived from it ([`crate::brdf::dbrdf`], "The lookup the renderer
//!   evaluates"), so the file bound is taken over the cone widened by the derived lookup's
//!   reach and scaled by the derivation's `max(k, 1)` (`dbrdf.rs`), and the derived
//!   table's own bound (the octahedral map is `sqrt 6`-Lipschitz from angle to `(u, v)`:
//!   on each face the gnomonic projection onto `|x| + |y| + z = 1` stretches by at most
//!   `sqrt 3`, the projection to `(x, y)` by at most 1, `(x + y, x - y)` by `sqrt 2`; so the
//!   cone lies in the box `(u, v) +- sqrt(6) beta`, `dbrdf_derived.rs`) replaces it where it
//!   is smaller, for small cones.
//! * Lambert + D-BRDF lobe: the sum of the two bounds.
//! * SH data sets and MERL tables have no cone bound here: [`ConeBound::new`] refuses them.
//!
//! Layout: this file holds the geometry and the per-model dispatch; `dbrdf.rs` the D-BRDF
//! file table's bound over the widened cone ([`DbrdfBound`]), `dbrdf_derived.rs` the
//! derived table's own; `tests.rs` the checks over random cones.

use super::Material;
use crate::conventions::local_angles;
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, PI};

/// A cone of unit directions in the local shading frame: axis `axis` (unit), half angle
/// `alpha` given by its cosine `cos`, sine `sin` (>= 0) and `sin_half = sin(alpha/2)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    pub axis: Vec3,
    pub cos: f32,
    pub sin: f32,
    pub sin_half: f32,
}

impl Cone {
    /// The cone of half angle `alpha` radians (clamped to [0, pi]) around `axis`
    /// (normalised).
    pub fn new(axis: Vec3, alpha: f32) -> Cone {
        let alpha = alpha.clamp(0.0, PI);
        Cone {
            axis: axis.normalize(),
            cos: alpha.cos(),
            sin: alpha.sin().max(0.0),
            sin_half: (0.5 * alpha).sin(),
        }
    }

    /// The whole sphere.
    pub const SPHERE: Cone = Cone {
        axis: Vec3::Z,
        cos: -1.0,
        sin: 0.0,
        sin_half: 1.0,
    };
}

/// Absolute widening of [`max_cos_to`] and [`min_cos_to`] for the f32 rounding of their
/// few products (a few 1e-7).
const COS_SLACK: f32 = 1e-6;

/// `max_{w in cone} w.d` for a unit `d`: `cos(max(0, angle(axis, d) - alpha))` (module doc),
/// plus `COS_SLACK`, at most 1.
#[inline]
pub fn max_cos_to(cone: &Cone, d: Vec3) -> f32 {
    let c = cone.axis.dot(d).clamp(-1.0, 1.0);
    if c >= cone.cos {
        return 1.0;
    }
    let s = (1.0 - c * c).max(0.0).sqrt();
    (c * cone.cos + s * cone.sin + COS_SLACK).min(1.0)
}

/// `min_{w in cone} w.d` for a unit `d`: `cos(min(pi, angle(axis, d) + alpha))`, minus
/// `COS_SLACK`, at least -1.
#[inline]
pub fn min_cos_to(cone: &Cone, d: Vec3) -> f32 {
    let c = cone.axis.dot(d).clamp(-1.0, 1.0);
    if c <= -cone.cos {
        return -1.0;
    }
    let s = (1.0 - c * c).max(0.0).sqrt();
    (c * cone.cos - s * cone.sin - COS_SLACK).max(-1.0)
}

/// The local angles a cone of half vectors covers: polar angle `theta` and azimuth `phi` of
/// its axis, its half angle `beta` (radians), and the azimuth half-width
/// `asin(sin beta / sin theta)` when the cone holds neither pole (`None`: every azimuth),
/// each widened by `ANGLE_SLACK` for the f32 angles of a lookup.
#[derive(Clone, Copy, Debug)]
pub struct ConeAngles {
    pub theta: f32,
    pub phi: f32,
    pub beta: f32,
    pub azimuth_half_width: Option<f32>,
}

impl ConeAngles {
    /// The angles of `h` (module doc, D-BRDF).
    pub fn of(h: &Cone) -> ConeAngles {
        let (theta, phi) = local_angles(h.axis);
        let beta = h.sin.atan2(h.cos) + ANGLE_SLACK;
        let st = theta.sin();
        let azimuth_half_width = if theta <= beta || theta + beta >= PI || h.sin >= st {
            None
        } else {
            Some((h.sin / st).min(1.0).asin() + ANGLE_SLACK)
        };
        ConeAngles {
            theta,
            phi,
            beta,
            azimuth_half_width,
        }
    }
}

/// `min sin^2(phi)` over `|phi - centre| <= half_width` (0 when the interval holds a
/// multiple of pi, else at an end).
#[inline]
fn min_sin2_over(centre: f32, half_width: f32) -> f32 {
    let (lo, hi) = (centre - half_width, centre + half_width);
    if (lo / PI).ceil() <= (hi / PI).floor() {
        return 0.0;
    }
    lo.sin().powi(2).min(hi.sin().powi(2))
}

/// Relative widening of the half vectors' chord, for f32 rounding.
const HALF_CONE_SLACK: f32 = 1e-5;

/// Widening of the half vectors' angular ranges (radians) for the f32 angles of a lookup.
const ANGLE_SLACK: f32 = 1e-4;

/// The half vectors of the cone's directions with `wo` (module doc, "Half vectors"): a cone
/// holding `normalize(wi + wo)` for every `wi` of `cone` (`None`: possibly the whole
/// sphere), and `m/2`, a lower bound of `k.h = |wi + wo|/2` over the cone.
#[inline]
pub fn half_vector_cone(cone: &Cone, wo: Vec3) -> (Option<Cone>, f32) {
    let m2 = 2.0 + 2.0 * min_cos_to(cone, wo);
    let m = m2.max(0.0).sqrt();
    let kh_min = 0.5 * m;
    let sum = cone.axis + wo;
    let len = sum.length();
    if m <= 1e-6 || len <= 1e-6 {
        return (None, kh_min);
    }
    let s = cone.sin_half / m * (1.0 + HALF_CONE_SLACK);
    if s >= 1.0 {
        return (None, kh_min);
    }
    let c = (1.0 - s * s).sqrt();
    let half = Cone {
        axis: sum / len,
        cos: 1.0 - 2.0 * s * s,
        sin: 2.0 * s * c,
        sin_half: s,
    };
    (Some(half), kh_min)
}

/// The largest `cos(polar_i)` over the cone, clamped to [0, 1].
#[inline]
fn max_cos_polar(cone: &Cone) -> f32 {
    max_cos_to(cone, Vec3::Z).clamp(0.0, 1.0)
}

/// The largest `n.h` over the half vectors of `cone` with `wo`, clamped to [0, 1].
#[inline]
fn max_nh(cone: &Cone, wo: Vec3) -> (f32, f32) {
    let (h, kh_min) = half_vector_cone(cone, wo);
    let nh = h.map_or(1.0, |h| max_cos_to(&h, Vec3::Z)).clamp(0.0, 1.0);
    (nh, kh_min)
}

/// Schlick's `F(c) = R_s + (1 - R_s)(1 - c)^5` at most over `c` in `[c_min, 1]`: `F` is
/// monotone in `c`, so the larger of its two end values, per channel.
#[inline]
fn schlick_max(rs: Vec3, c_min: f32) -> Vec3 {
    let m = (1.0 - c_min.clamp(0.0, 1.0)).powi(5);
    (rs + (Vec3::ONE - rs) * m).max(rs)
}

/// The cone bound of one material (module doc), precomputed once per frame.
#[derive(Clone, Debug)]
pub enum ConeBound {
    Lambert { k: Vec3 },
    Phong { kd: Vec3, ks: Vec3, exponent: f32 },
    BlinnPhong { kd: Vec3, ks: Vec3, exponent: f32 },
    AshikhminShirley { m: crate::brdf::AshikhminShirley },
    DBrdf(DbrdfBound),
    LambertDbrdf { kd: Vec3, lobe: DbrdfBound },
}

/// A seeded fault of the bound (tests only): what the tests must catch.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BoundFault {
    #[default]
    None,
    /// The cone ignored: `f cos` at the cone's axis only.
    IgnoreCone,
    /// The cone's half angle halved.
    HalfCone,
}

impl ConeBound {
    /// The bound of `material`; `Err` names the model for SH data sets and MERL tables,
    /// which have none (module doc).
    pub fn new(material: &Material) -> Result<ConeBound, String> {
        Ok(match material {
            Material::Lambert(m) => ConeBound::Lambert { k: m.albedo / PI },
            Material::Phong(m) => ConeBound::Phong {
                kd: m.kd / PI,
                ks: m.ks * ((m.exponent + 2.0) / (2.0 * PI)),
                exponent: m.exponent,
            },
            Material::BlinnPhong(m) => ConeBound::BlinnPhong {
                kd: m.kd / PI,
                ks: m.ks * ((m.exponent + 8.0) / (8.0 * PI)),
                exponent: m.exponent,
            },
            Material::AshikhminShirley(m) => ConeBound::AshikhminShirley { m: *m },
            Material::DBrdf(d) => ConeBound::DBrdf(DbrdfBound::new(d)),
            Material::LambertDbrdf(m) => ConeBound::LambertDbrdf {
                kd: m.rd / PI,
                lobe: DbrdfBound::new(&m.lobe),
            },
            Material::Merl(_) | Material::Rgl(_) | Material::Sh(_) => {
                return Err(format!(
                    "light cuts have no bound of f cos over a cone for {} (Lambert, Phong, \
                     Blinn-Phong, Ashikhmin-Shirley, D-BRDF and Lambert + D-BRDF have one)",
                    material.name()
                ))
            }
        })
    }

    /// An upper bound of `f_r(wi, wo) cos(polar_i)` (RGB, 1/sr) over every `wi` of `cone`
    /// for the unit view `wo` (above the horizon), local frame (module doc).
    #[inline]
    pub fn f_cos_max(&self, cone: &Cone, wo: Vec3) -> Vec3 {
        let ci = max_cos_polar(cone);
        if ci <= 0.0 {
            return Vec3::ZERO;
        }
        match self {
            ConeBound::Lambert { k } => *k * ci,
            ConeBound::Phong { kd, ks, exponent } => {
                let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
                let rv = max_cos_to(cone, mirror).clamp(0.0, 1.0);
                (*kd + *ks * rv.powf(*exponent)) * ci
            }
            ConeBound::BlinnPhong { kd, ks, exponent } => {
                let (nh, _) = max_nh(cone, wo);
                (*kd + *ks * nh.powf(*exponent)) * ci
            }
            ConeBound::AshikhminShirley { m } => {
                let (h, kh_min) = half_vector_cone(cone, wo);
                let nh = h.map_or(1.0, |h| max_cos_to(&h, Vec3::Z)).clamp(0.0, 1.0);
                // The smallest exponent over the half vectors' azimuths (module doc).
                let e_min = match h.map(|h| ConeAngles::of(&h)) {
                    Some(ConeAngles {
                        phi,
                        azimuth_half_width: Some(w),
                        ..
                    }) => {
                        if m.nv >= m.nu {
                            m.nu + (m.nv - m.nu) * min_sin2_over(phi, w)
                        } else {
                            let cos2 = min_sin2_over(phi + FRAC_PI_2, w);
                            m.nv + (m.nu - m.nv) * cos2
                        }
                    }
                    _ => m.nu.min(m.nv),
                };
                let n2 = wo.z.min(1.0);
                let five = |x: f32| 1.0 - (1.0 - 0.5 * x).powi(5);
                let diffuse = m.rd
                    * (28.0 / (23.0 * PI))
                    * (Vec3::ONE - m.rs).max(Vec3::ZERO)
                    * five(ci)
                    * five(n2)
                    * ci;
                let norm = ((m.nu + 1.0) * (m.nv + 1.0)).sqrt() / (8.0 * PI);
                let cos_ratio = if n2 > 0.0 { (ci / n2).min(1.0) } else { 1.0 };
                let spec = norm * nh.powf(e_min) / kh_min.clamp(1e-6, 1.0) * cos_ratio;
                diffuse + schlick_max(m.rs, kh_min) * spec
            }
            ConeBound::DBrdf(d) => {
                let (h, kh_min) = half_vector_cone(cone, wo);
                d.f_cos_max(ci, wo, h.as_ref(), kh_min)
            }
            ConeBound::LambertDbrdf { kd, lobe } => {
                let (h, kh_min) = half_vector_cone(cone, wo);
                *kd * ci + lobe.f_cos_max(ci, wo, h.as_ref(), kh_min)
            }
        }
    }

    /// [`ConeBound::f_cos_max`] with a seeded fault (tests only); `material` evaluates `f`
    /// for [`BoundFault::IgnoreCone`].
    #[doc(hidden)]
    pub fn f_cos_max_with_fault(
        &self,
        material: &Material,
        cone: &Cone,
        wo: Vec3,
        fault: BoundFault,
    ) -> Vec3 {
        match fault {
            BoundFault::None => self.f_cos_max(cone, wo),
            BoundFault::IgnoreCone => {
                let a = cone.axis;
                if a.z > 0.0 {
                    material.eval(a, wo) * a.z
                } else {
                    Vec3::ZERO
                }
            }
            BoundFault::HalfCone => {
                let alpha = cone.sin.atan2(cone.cos);
                self.f_cos_max(&Cone::new(cone.axis, 0.5 * alpha), wo)
            }
        }
    }
}

mod box_max;
mod dbrdf;
mod dbrdf_derived;
pub use dbrdf::DbrdfBound;

#[cfg(test)]
mod tests;
