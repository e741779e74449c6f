//! Measured BRDFs of the RGL material database (Dupuy & Jakob, "An Adaptive
//! Parameterization for Efficient Material Acquisition and Rendering", SIGGRAPH Asia
//! 2018): the `.bsdf` tensor files that Mitsuba 3 (`measured`) and pbrt-v4
//! (`MeasuredBxDF`) read, isotropic and anisotropic, spectral or RGB.
//!
//! Layout: [`tensor`] the file container, [`mod@file`] the fields of a material and the checks
//! made on them, [`warp`] the piecewise-bilinear tables and the 2D warp, [`colour`]
//! spectral samples to linear sRGB, [`writer`] a tabulator of any [`Brdf`] into the
//! format (test files) and [`samples`] the analytic test materials, [`real`] the f32/f64 scalar operations; the evaluation is here.
//!
//! # Evaluation (paper section 5; the arithmetic of both published readers)
//! The table's incident direction `w_t` is the *viewer* (`wo` here; Mitsuba's `si.wi`,
//! pbrt's `wo`), its outgoing direction the light (`wi`); both above the horizon, else 0.
//! Anisotropic files whose `phi_i` axis spans `2 pi / r` (`r` = 2 or 4, the "reduction")
//! are folded first: with `r = 4` both directions are mirrored so that `w_t.x, w_t.y <=
//! 0`; with `r = 2` both are turned by pi about the normal when `w_t.y > 0`. Then, with
//! `m = normalize(wi + wo)`, elevations `theta = 2 asin(|w - z| / 2)`, azimuths
//! `phi = atan2(y, x)`, and the unit-square coordinates `u(theta) = sqrt(2 theta / pi)`,
//! `v(phi) = (phi + pi) / (2 pi)`:
//!
//! - `u_t = (u(theta_t), v(phi_t))`, `u_m = (u(theta_m), v(phi_m'))` with
//!   `phi_m' = phi_m - phi_t` for isotropic files (`phi_i` of at most 2 values), `phi_m`
//!   otherwise, `v` wrapped into [0, 1);
//! - `s = VNDF^-1(u_m | phi_t, theta_t)`, the CDF map of the `vndf` warp ([`warp`]);
//! - `f_r cos(theta_light) = S(s | phi_t, theta_t) * D(u_m) / (4 sigma(u_t))`, `S` the
//!   `spectra` (or `rgb`) interpolant, `D` the `ndf` and `sigma` the projected-area
//!   interpolant; without the `jacobian` flag the factor `D / (4 sigma)` is left out;
//! - `f_r` = that divided by `cos(theta_light) = wi.z`, per RGB channel, clamped at 0.
//!
//! Spectral files are converted to linear sRGB per table node at load ([`colour`]: CIE
//! 1931 2-degree observer, D65 white-balanced); negative stored samples (measurement
//! noise) are clamped to 0 at load. [`Brdf::eval`] computes all of this in f32 (as the
//! published readers do) and [`Brdf::eval_f64`] in f64 from f64 copies of the tables (the
//! converged reference).
//!
//! Isotropic files evaluate through the azimuth difference only (their `ndf` and `sigma`
//! are read at the relative azimuth and the absolute `phi_t` respectively, both constant
//! along azimuth for an isotropic material), so [`Brdf::is_isotropic`] is true for them;
//! the material is shaded in the world-up frame like MERL's (an exact function of the
//! directions).

pub mod colour;
pub mod file;
pub mod real;
pub mod samples;
pub mod tensor;
pub mod warp;
pub mod writer;

#[cfg(test)]
mod tests;

use super::Brdf;
use glam::{DVec3, Vec3};
use real::Real;
use warp::Table;

pub use file::RglError;

/// The tables of one precision.
#[derive(Clone, Debug)]
struct Tables<S> {
    ndf: Table<S>,
    sigma: Table<S>,
    vndf: Table<S>,
    /// Linear sRGB, three channels.
    rgb: Table<S>,
}

/// A measured BRDF read from an RGL `.bsdf` file (module doc).
#[derive(Clone, Debug)]
pub struct RglBrdf {
    name: String,
    /// The file's `description` field (lossy UTF-8).
    pub description: String,
    /// `phi_i` has at most two values.
    pub isotropic: bool,
    /// The `jacobian` flag: the `D / (4 sigma)` factor applies.
    pub jacobian: bool,
    /// The azimuthal symmetry of an anisotropic file: 1 (none), 2 or 4; 1 when isotropic.
    pub reduction: u32,
    /// The wavelengths (nm) of a spectral file; `None` for an RGB file.
    pub wavelengths: Option<Vec<f32>>,
    t32: Tables<f32>,
    t64: Tables<f64>,
}

#[inline]
fn theta2u<S: Real>(theta: S) -> S {
    (theta * (S::lit(2.0) / S::PI)).sqrt()
}

#[inline]
fn phi2u<S: Real>(phi: S) -> S {
    (phi + S::PI) * (S::ONE / (S::lit(2.0) * S::PI))
}

/// Polar angle of a unit vector, stable near the pole: `2 asin(|d - z| / 2)`.
#[inline]
fn elevation<S: Real>(d: [S; 3]) -> S {
    let dz = d[2] - S::ONE;
    let dist = (d[0] * d[0] + d[1] * d[1] + dz * dz).sqrt();
    S::lit(2.0) * (S::lit(0.5) * dist).min(S::ONE).asin()
}

#[inline]
fn normalize<S: Real>(v: [S; 3]) -> Option<[S; 3]> {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if l > S::ZERO {
        Some([v[0] / l, v[1] / l, v[2] / l])
    } else {
        None
    }
}

/// `a` with the sign flipped unless `s` is negative (Dr.Jit's `mulsign_neg`).
#[inline]
fn mulsign_neg<S: Real>(a: S, s: S) -> S {
    if s.is_sign_negative() {
        a
    } else {
        -a
    }
}

impl RglBrdf {
    /// `f_r(wi, wo)` (module doc) in the precision of `t`; `light` = `wi`, `view` = `wo`.
    fn eval_in<S: Real>(&self, t: &Tables<S>, light: [S; 3], view: [S; 3]) -> [S; 3] {
        let zero = [S::ZERO; 3];
        let (Some(mut wl), Some(mut wt)) = (normalize(light), normalize(view)) else {
            return zero;
        };
        if !(wl[2] > S::ZERO && wt[2] > S::ZERO) {
            return zero;
        }
        let cos_light = wl[2];
        if self.reduction >= 2 {
            let sy = wt[1];
            let sx = if self.reduction == 4 { wt[0] } else { sy };
            wt[0] = mulsign_neg(wt[0], sx);
            wt[1] = mulsign_neg(wt[1], sy);
            wl[0] = mulsign_neg(wl[0], sx);
            wl[1] = mulsign_neg(wl[1], sy);
        }
        let Some(m) = normalize([wt[0] + wl[0], wt[1] + wl[1], wt[2] + wl[2]]) else {
            return zero;
        };
        let theta_t = elevation(wt);
        let phi_t = wt[1].atan2(wt[0]);
        let theta_m = elevation(m);
        let phi_m = m[1].atan2(m[0]);
        let ut = (theta2u(theta_t), phi2u(phi_t));
        let mut vm = phi2u(if self.isotropic { phi_m - phi_t } else { phi_m });
        vm = vm - vm.floor();
        let um = (theta2u(theta_m), vm);
        let params = [phi_t, theta_t];
        let (sx, sy) = t.vndf.invert(um.0, um.1, &params);
        let mut scale = S::ONE / cos_light;
        if self.jacobian {
            let d = t.ndf.eval(um.0, um.1, &[], 0);
            let sigma = t.sigma.eval(ut.0, ut.1, &[], 0);
            scale = scale * d / (S::lit(4.0) * sigma);
        }
        let mut out = zero;
        for (c, o) in out.iter_mut().enumerate() {
            *o = (t.rgb.eval(sx, sy, &params, c) * scale).max(S::ZERO);
        }
        out
    }
}

impl Brdf for RglBrdf {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        Vec3::from(self.eval_in(&self.t32, wi.to_array(), wo.to_array()))
    }

    fn eval_f64(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        DVec3::from(self.eval_in(&self.t64, wi.to_array(), wo.to_array()))
    }

    fn name(&self) -> &str {
        &self.name
    }

    /// True for isotropic files (module doc).
    fn is_isotropic(&self) -> bool {
        self.isotropic
    }
}
