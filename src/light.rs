//! Delta lights: the lighting integral as a sum (thesis 2.3.2, Def. 10).
//!
//! Design rule: every light, whatever its origin (a scene entry or a sample of an
//! environment probe), is reduced per shading point to a unit direction towards the light
//! and an RGB irradiance at normal incidence `E` (W/m^2 for radiometric inputs). The
//! reflected radiance is then `sum_k f(l_k, v) cos(polar_k) E_k`.

use glam::{DVec3, Vec3};

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

/// Smallest squared distance (scene units^2) at which a point light's `1/d^2` falloff is
/// applied: 1e-12, a distance of 1e-6 scene units, a thousandth of the smallest scene scale
/// the stability tests use (1e-3). Closer, the irradiance is held at its value there, so a
/// light almost at a shading point gives a large finite value instead of overflowing f32 to
/// Inf (it did at `d^2 < intensity / f32::MAX`, about 1e-38). The point-light model has no
/// meaning at such distances anyway: a real emitter has a size.
pub const MIN_POINT_DISTANCE2: f32 = 1e-12;

/// The body of [`Light::at`] and [`Light::at_f64`], one definition for both arithmetics:
/// light `$light` seen from point `$p` (vector type `$V`), its stored f32 vectors converted
/// with `$V::from` (the identity for f32).
macro_rules! towards_light {
    ($light:expr, $p:expr, $V:ident) => {
        match *$light {
            Light::Directional {
                to_light,
                irradiance,
            } => ($V::from(to_light), $V::from(irradiance)),
            Light::Point {
                position,
                intensity,
            } => {
                let d = $V::from(position) - $p;
                let d2 = d.length_squared();
                if d2 > 0.0 && d2.is_finite() {
                    (
                        d / d2.sqrt(),
                        $V::from(intensity) / d2.max(MIN_POINT_DISTANCE2.into()),
                    )
                } else {
                    ($V::Y, $V::ZERO)
                }
            }
        }
    };
}

impl Light {
    /// Unit direction towards the light and irradiance at normal incidence at world
    /// point `p`. A point light exactly at `p` gives zero irradiance, and closer than
    /// `sqrt(MIN_POINT_DISTANCE2)` its irradiance is held at `intensity / MIN_POINT_DISTANCE2`
    /// (documented fallbacks; never Inf or NaN for finite inputs).
    #[inline]
    pub fn at(&self, p: Vec3) -> (Vec3, Vec3) {
        towards_light!(self, p, Vec3)
    }

    /// [`Light::at`] in f64 arithmetic (the light's f32 values widened exactly), for the
    /// f64 path ([`crate::shade::ShadingPath::F64NoSkips`]); same formula, same fallbacks.
    #[inline]
    pub fn at_f64(&self, p: DVec3) -> (DVec3, DVec3) {
        towards_light!(self, p, DVec3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_almost_at_the_point_stays_finite() {
        let l = Light::Point {
            position: Vec3::new(1e-20, 0.0, 0.0),
            intensity: Vec3::splat(1e4),
        };
        let (dir, e) = l.at(Vec3::ZERO);
        assert!(dir.is_finite() && e.is_finite(), "{dir} {e}");
        assert_eq!(e, Vec3::splat(1e4 / MIN_POINT_DISTANCE2));
        // Farther than the floor the 1/d^2 law holds exactly as before.
        let l = Light::Point {
            position: Vec3::new(0.0, 2.0, 0.0),
            intensity: Vec3::splat(8.0),
        };
        assert_eq!(l.at(Vec3::ZERO), (Vec3::Y, Vec3::splat(2.0)));
    }
}
