//! The one scalar trait of the crate: `f32`, the renderer's, or `f64`, the reference
//! computations' (quadratures, fits, the f64 shading path). A formula written once over
//! [`Scalar`] has an f32 and an f64 instance that cannot drift apart: the same expression
//! in the same order, with each operation the IEEE one of the type (every method is the
//! standard library's of that name; no fast-math, no libm substitute; one exception,
//! `floor`, is computed inline with the standard one's bits for every input, [`floor_f32`]). The conventions with
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
    /// The bits of the standard library's `floor` for every input, without its call
    /// ([`floor_f32`]).
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

/// `x.floor()`'s bits for every f32 `x` (infinities, NaN, -0.0 included), computed inline:
/// on the baseline x86-64 target (SSE2, no `roundss`) the standard library's `floor` is a
/// call into `floorf`, which profiles of the lookups that take a texel's integer part showed
/// at 4-6% of a frame. The same function as [`Scalar::floor`] of `f32`.
#[inline(always)]
pub fn floor_f32(x: f32) -> f32 {
    <f32 as Scalar>::floor(x)
}

macro_rules! scalar {
    ($t:ident, $i:ident) => {
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
                // Below 2^(mantissa bits) in magnitude, truncation through $i is exact;
                // every float at or above it, infinities too, is its own floor, and NaN
                // stays NaN.
                const LIMIT: $t = (1u64 << ($t::MANTISSA_DIGITS - 1)) as $t;
                if !(self.abs() < LIMIT) {
                    return self;
                }
                let t = self as $i as $t;
                if t == self {
                    // Integers keep their own bits (-0.0 stays -0.0).
                    self
                } else if t > self {
                    t - 1.0
                } else {
                    t
                }
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

scalar!(f32, i32);
scalar!(f64, i64);

#[cfg(test)]
mod tests {
    use super::*;

    /// The inline floor against the standard library's on the cases that matter (signed
    /// zeros, integers, halves, the limits of exact truncation, infinities, NaN) and on a
    /// sweep of bit patterns, in both precisions.
    #[test]
    fn inline_floor_has_the_standard_floors_bits() {
        let mut xs: Vec<f64> = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.5,
            -1.5,
            2.0 - f64::EPSILON,
            -(2.0 - f64::EPSILON),
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            4.5e15,
            -4.5e15 - 0.5,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ];
        // Bit patterns spread over every exponent, both signs.
        let mut k: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..200_000 {
            k ^= k << 13;
            k ^= k >> 7;
            k ^= k << 17;
            xs.push(f64::from_bits(k));
            xs.push(f32::from_bits(k as u32) as f64);
        }
        for &x in &xs {
            let (a, b) = (<f64 as Scalar>::floor(x), f64::floor(x));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "f64 {x:e}"
            );
            let x = x as f32;
            let (a, b) = (floor_f32(x), f32::floor(x));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "f32 {x:e}"
            );
        }
        // A seeded fault: truncation alone differs below zero (so the sweep can fail).
        assert_ne!(
            (-0.5f32 as i32 as f32).to_bits(),
            f32::floor(-0.5).to_bits()
        );
    }

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
