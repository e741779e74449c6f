//! The one scalar trait of the crate: `f32`, the renderer's, or `f64`, the reference
//! computations' (quadratures, fits, the f64 shading path). A formula written once over
//! [`Scalar`] has an f32 and an f64 instance that cannot drift apart: the same expression
//! in the same order, with each operation the IEEE one of the type (every method is the
//! standard library's of that name; no fast-math, no libm substitute). The conventions with
//! both forms are written this way (their `f32` and `_f64` names are thin wrappers of one
//! generic body), and so are the analytic models' `eval` ([`crate::brdf::real`], which adds
//! the 3-vector operations). Literals are written in f64 and rounded once to the scalar
//! type ([`Scalar::lit`]); model parameters, stored in f32, are widened exactly
//! ([`Scalar::from_f32`]).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `f32` or `f64` (module doc).
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
    const HALF: Self;
    const ONE: Self;
    const TWO: Self;
    /// pi in this precision.
    const PI: Self;
    /// 1 / pi in this precision.
    const FRAC_1_PI: Self;
    /// `2 pi`.
    const TAU: Self;
    /// `pi / 2`.
    const FRAC_PI_2: Self;
    /// A literal, rounded once to this type.
    fn lit(x: f64) -> Self;
    /// An f32 parameter, widened exactly.
    fn from_f32(x: f32) -> Self;
    /// `n as Self` (round to nearest).
    fn from_usize(n: usize) -> Self;
    /// `self as i64` (towards zero, saturating, NaN to 0).
    fn to_i64(self) -> i64;
    /// `self as usize` (towards zero, saturating, NaN and negatives to 0).
    fn to_usize(self) -> usize;
    fn powf(self, e: Self) -> Self;
    fn powi(self, n: i32) -> Self;
    fn sqrt(self) -> Self;
    fn floor(self) -> Self;
    fn abs(self) -> Self;
    /// The other operand where one is NaN.
    fn max(self, o: Self) -> Self;
    /// The other operand where one is NaN.
    fn min(self, o: Self) -> Self;
    fn clamp(self, lo: Self, hi: Self) -> Self;
    fn acos(self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn sin_cos(self) -> (Self, Self);
    fn rem_euclid(self, m: Self) -> Self;
    fn is_finite(self) -> bool;
}

macro_rules! scalar {
    ($t:ident) => {
        impl Scalar for $t {
            const ZERO: $t = 0.0;
            const HALF: $t = 0.5;
            const ONE: $t = 1.0;
            const TWO: $t = 2.0;
            const PI: $t = std::$t::consts::PI;
            const FRAC_1_PI: $t = std::$t::consts::FRAC_1_PI;
            const TAU: $t = std::$t::consts::TAU;
            const FRAC_PI_2: $t = std::$t::consts::FRAC_PI_2;
            #[inline(always)]
            fn lit(x: f64) -> $t {
                x as $t
            }
            #[inline(always)]
            fn from_f32(x: f32) -> $t {
                x as $t
            }
            #[inline(always)]
            fn powf(self, e: $t) -> $t {
                $t::powf(self, e)
            }
            #[inline(always)]
            fn powi(self, n: i32) -> $t {
                $t::powi(self, n)
            }
            #[inline(always)]
            fn sqrt(self) -> $t {
                $t::sqrt(self)
            }
            #[inline(always)]
            fn from_usize(n: usize) -> $t {
                n as $t
            }
            #[inline(always)]
            fn to_i64(self) -> i64 {
                self as i64
            }
            #[inline(always)]
            fn to_usize(self) -> usize {
                self as usize
            }
            #[inline(always)]
            fn floor(self) -> $t {
                $t::floor(self)
            }
            #[inline(always)]
            fn abs(self) -> $t {
                $t::abs(self)
            }
            #[inline(always)]
            fn max(self, o: $t) -> $t {
                $t::max(self, o)
            }
            #[inline(always)]
            fn min(self, o: $t) -> $t {
                $t::min(self, o)
            }
            #[inline(always)]
            fn clamp(self, lo: $t, hi: $t) -> $t {
                $t::clamp(self, lo, hi)
            }
            #[inline(always)]
            fn acos(self) -> $t {
                $t::acos(self)
            }
            #[inline(always)]
            fn atan2(self, x: $t) -> $t {
                $t::atan2(self, x)
            }
            #[inline(always)]
            fn sin_cos(self) -> ($t, $t) {
                $t::sin_cos(self)
            }
            #[inline(always)]
            fn rem_euclid(self, m: $t) -> $t {
                $t::rem_euclid(self, m)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                $t::is_finite(self)
            }
        }
    };
}

scalar!(f32);
scalar!(f64);

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
