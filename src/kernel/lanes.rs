//! The one SIMD wrapper: eight f32 lanes as a plain array whose per-lane loops the
//! compiler vectorizes (SSE2 everywhere; AVX2 in the functions `multiversion` compiles
//! for it). Every operation is the IEEE operation per lane, in the same order on every
//! path: no fused multiply-add (Rust never contracts `a * b + c`), no reassociation, so
//! the SIMD paths give the same bits as a scalar loop over the lanes.

use std::ops::{Add, AddAssign, Mul, Sub};

/// Number of lanes.
pub const LANES: usize = 8;

/// Eight f32 lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct F32x8(pub [f32; LANES]);

impl F32x8 {
    #[inline(always)]
    pub fn splat(v: f32) -> Self {
        F32x8([v; LANES])
    }
    #[inline(always)]
    pub fn from_slice(s: &[f32]) -> Self {
        let mut a = [0.0; LANES];
        a.copy_from_slice(&s[..LANES]);
        F32x8(a)
    }
    /// `self` where `mask > 0`, else 0 (per lane).
    #[inline(always)]
    pub fn select_positive(self, mask: F32x8) -> Self {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = if mask.0[i] > 0.0 { self.0[i] } else { 0.0 };
        }
        F32x8(r)
    }
    /// Lane sum in a fixed order ((0+1)+(2+3))+((4+5)+(6+7)).
    #[inline(always)]
    pub fn sum(self) -> f32 {
        let a = self.0;
        ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))
    }
    #[inline(always)]
    pub fn any_nonzero(self) -> bool {
        self.0.iter().any(|&v| v != 0.0)
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for F32x8 {
            type Output = F32x8;
            #[inline(always)]
            fn $f(self, o: F32x8) -> F32x8 {
                let mut r = [0.0; LANES];
                for i in 0..LANES {
                    r[i] = self.0[i] $op o.0[i];
                }
                F32x8(r)
            }
        }
        impl $tr<f32> for F32x8 {
            type Output = F32x8;
            #[inline(always)]
            fn $f(self, o: f32) -> F32x8 {
                let mut r = [0.0; LANES];
                for i in 0..LANES {
                    r[i] = self.0[i] $op o;
                }
                F32x8(r)
            }
        }
    };
}
binop!(Add, add, +);
binop!(Sub, sub, -);
binop!(Mul, mul, *);

impl AddAssign for F32x8 {
    #[inline(always)]
    fn add_assign(&mut self, o: F32x8) {
        for i in 0..LANES {
            self.0[i] += o.0[i];
        }
    }
}
