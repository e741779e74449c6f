//! One formula for f32 and f64: the 3-vector operations an analytic model's `eval` uses,
//! implemented for glam's `Vec3` (f32) and `DVec3` (f64), over the crate's one scalar trait
//! ([`Scalar`], which the conventions use too), so a model writes its formula once, generic
//! over [`Vector3`], and [`super::Brdf::eval`] and [`super::Brdf::eval_f64`] are the two
//! instances of it.
//!
//! Design rule: every method is the type's own operation (`f32::powf`, `Vec3::dot`,
//! `Vec3::normalize_or_zero`, ...), called in the order the formula is written, so the f32
//! instance computes exactly the bits the hand-written f32 body did and the f64 instance
//! the f64 body's. Literals are written in f64 and rounded once to the scalar type
//! ([`Scalar::lit`]); model parameters, stored in f32, are widened exactly
//! ([`Vector3::from_vec3`], [`Scalar::from_f32`]).

pub use crate::conventions::Scalar;
use glam::{DVec3, Vec3};
use std::ops::{Add, Div, Mul, Sub};

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
