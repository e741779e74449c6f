//! Delta lights: the lighting integral as a sum (thesis 2.3.2, Def. 10).
//!
//! Design rule: every light, whatever its origin (a scene entry or a sample of an
//! environment probe), is reduced per shading point to a unit direction towards the light
//! and an RGB irradiance at normal incidence `E` (W/m^2 for radiometric inputs). The
//! reflected radiance is then `sum_k f(l_k, v) cos(polar_k) E_k`.

use glam::Vec3;

/// A delta light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Infinitely far light. `to_light` is the unit direction from the surface towards the
    /// light; `irradiance` is RGB irradiance at normal incidence (W/m^2).
    Directional { to_light: Vec3, irradiance: Vec3 },
    /// Isotropic point light at `position` with RGB radiant intensity (W/sr): irradiance at
    /// normal incidence falls off as `intensity / d^2`.
    Point { position: Vec3, intensity: Vec3 },
}

impl Light {
    /// Unit direction towards the light and irradiance at normal incidence at world
    /// point `p`. A point light exactly at `p` gives zero irradiance (documented fallback).
    #[inline]
    pub fn at(&self, p: Vec3) -> (Vec3, Vec3) {
        match *self {
            Light::Directional {
                to_light,
                irradiance,
            } => (to_light, irradiance),
            Light::Point {
                position,
                intensity,
            } => {
                let d = position - p;
                let d2 = d.length_squared();
                if d2 > 0.0 && d2.is_finite() {
                    (d / d2.sqrt(), intensity / d2)
                } else {
                    (Vec3::Y, Vec3::ZERO)
                }
            }
        }
    }
}
