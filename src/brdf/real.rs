//! One formula for f32 and f64: the scalar and 3-vector operations an analytic model's
//! `eval` uses, implemented for glam's `Vec3` (f32) and `DVec3` (f64), so a model writes its
//! formula once, generic over [`Vector3`], and [`super::Brdf::eval`] and
//! [`super::Brdf::eval_f64`] are the two instances of it.
//!
//! Design rule: every method is the type's own operation (`f32::powf`, `Vec3::dot`,
//! `Vec3::normalize_or_zero`, ...), called in the order the formula is written, so the f32
//! instance computes exactly the bits the hand-written f32 body did and the f64 instance
//! the f64 body's. Literals are written in f64 and rounded once to the scalar type
//! ([`Scalar::lit`]); model parameters, stored in f32, are widened exactly
//! ([`Vector3::from_vec3`], [`Scalar::from_f32`]).

use glam::{DVec3, Vec3};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// `f32` or `f64`.
pub trait Scalar:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    const ZERO: Self;
    const ONE: Self;
    /// pi in this precision.
    const PI: Self;
    /// 1 / pi in this precision.
    const FRAC_1_PI: Self;
    /// A literal, rounded once to this type.
    fn lit(x: f64) -> Self;
    /// An f32 parameter, widened exactly.
    fn from_f32(x: f32) -> Self;
    fn powf(self, e: Self) -> Self;
    fn powi(self, n: i32) -> Self;
    fn sqrt(self) -> Self;
    fn max(self, o: Self) -> Self;
    fn min(self, o: Self) -> Self;
    fn clamp(self, lo: Self, hi: Self) -> Self;
}

/// `Vec3` (f32) or `DVec3` (f64), with scalar type [`Vector3::S`].
pub trait Vector3:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<Self::S, Output = Self>
    + Div<Self::S, Output = Self>
{
    type S: Scalar;
    const ZERO: Self;
    const ONE: Self;
    fn new(x: Self::S, y: Self::S, z: Self::S) -> Self;
    fn x(self) -> Self::S;
    fn y(self) -> Self::S;
    fn z(self) -> Self::S;
    /// An f32 parameter, widened exactly.
    fn from_vec3(v: Vec3) -> Self;
    fn dot(self, o: Self) -> Self::S;
    fn length(self) -> Self::S;
    fn normalize_or_zero(self) -> Self;
}

macro_rules! scalar {
    ($t:ident) => {
        impl Scalar for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const PI: Self = std::$t::consts::PI;
            const FRAC_1_PI: Self = std::$t::consts::FRAC_1_PI;
            #[inline(always)]
            fn lit(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn from_f32(x: f32) -> Self {
                x as $t
            }
            #[inline(always)]
            fn powf(self, e: Self) -> Self {
                $t::powf(self, e)
            }
            #[inline(always)]
            fn powi(self, n: i32) -> Self {
                $t::powi(self, n)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $t::sqrt(self)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                $t::max(self, o)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                $t::min(self, o)
            }
            #[inline(always)]
            fn clamp(self, lo: Self, hi: Self) -> Self {
                $t::clamp(self, lo, hi)
            }
        }
    };
}
scalar!(f32);
scalar!(f64);

macro_rules! vector {
    ($v:ident, $t:ident, $widen:expr) => {
        impl Vector3 for $v {
            type S = $t;
            const ZERO: Self = $v::ZERO;
            const ONE: Self = $v::ONE;
            #[inline(always)]
            fn new(x: $t, y: $t, z: $t) -> Self {
                $v::new(x, y, z)
            }
            #[inline(always)]
            fn x(self) -> $t {
                self.x
            }
            #[inline(always)]
            fn y(self) -> $t {
                self.y
            }
            #[inline(always)]
            fn z(self) -> $t {
                self.z
            }
            #[inline(always)]
            fn from_vec3(v: Vec3) -> Self {
                $widen(v)
            }
            #[inline(always)]
            fn dot(self, o: Self) -> $t {
                $v::dot(self, o)
            }
            #[inline(always)]
            fn length(self) -> $t {
                $v::length(self)
            }
            #[inline(always)]
            fn normalize_or_zero(self) -> Self {
                $v::normalize_or_zero(self)
            }
        }
    };
}
vector!(Vec3, f32, |v: Vec3| v);
vector!(DVec3, f64, |v: Vec3| v.as_dvec3());

#[cfg(test)]
mod tests {
    use super::*;

    /// The literals the models use round to the same value as the f32 literal would (a
    /// double rounding through f64 could differ in principle; a changed guard value would
    /// change bits).
    #[test]
    fn literals_round_like_f32_literals() {
        let pairs: [(f64, f32); 8] = [
            (1e-6, 1e-6),
            (0.5, 0.5),
            (2.0, 2.0),
            (8.0, 8.0),
            (23.0, 23.0),
            (28.0, 28.0),
            (1.0, 1.0),
            (0.0, 0.0),
        ];
        for (wide, narrow) in pairs {
            assert_eq!(
                <f32 as Scalar>::lit(wide).to_bits(),
                narrow.to_bits(),
                "{wide}"
            );
        }
    }
}
