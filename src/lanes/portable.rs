//! The portable backend of [`super::F32x8`]: `[f32; 8]` with per-lane loops, for any CPU,
//! giving the same bits as the AVX2 backend (fused multiply-add per f32 lane; f64 lanes
//! never fused).

use super::*;

/// The portable instruction set (any CPU).
#[derive(Clone, Copy, Debug)]
pub struct Portable;

/// [`F32x8`] of [`Portable`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct P8(pub [f32; LANES]);

#[inline(always)]
fn map2(a: P8, b: P8, f: impl Fn(f32, f32) -> f32) -> P8 {
    let mut r = [0.0; LANES];
    for i in 0..LANES {
        r[i] = f(a.0[i], b.0[i]);
    }
    P8(r)
}

/// [`I32x8`] of [`Portable`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct PI8(pub [i32; LANES]);

impl I32x8 for PI8 {
    #[inline(always)]
    fn add(self, o: PI8) -> PI8 {
        PI8(std::array::from_fn(|i| self.0[i].wrapping_add(o.0[i])))
    }
    #[inline(always)]
    fn or(self, o: PI8) -> PI8 {
        PI8(std::array::from_fn(|i| self.0[i] | o.0[i]))
    }
    #[inline(always)]
    fn sign_mask(self) -> u32 {
        let mut m = 0;
        for i in 0..LANES {
            m |= ((self.0[i] as u32) >> 31) << i;
        }
        m
    }
}

/// [`F64x4`] of [`Portable`]: scalar f64 per lane, never fused.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct PD4(pub [f64; F64_LANES]);

impl Add for PD4 {
    type Output = PD4;
    #[inline(always)]
    fn add(self, o: PD4) -> PD4 {
        PD4(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
}

impl Sub for PD4 {
    type Output = PD4;
    #[inline(always)]
    fn sub(self, o: PD4) -> PD4 {
        PD4(std::array::from_fn(|i| self.0[i] - o.0[i]))
    }
}

impl Mul for PD4 {
    type Output = PD4;
    #[inline(always)]
    fn mul(self, o: PD4) -> PD4 {
        PD4(std::array::from_fn(|i| self.0[i] * o.0[i]))
    }
}

impl Div for PD4 {
    type Output = PD4;
    #[inline(always)]
    fn div(self, o: PD4) -> PD4 {
        PD4(std::array::from_fn(|i| self.0[i] / o.0[i]))
    }
}

impl F64x4 for PD4 {
    #[inline(always)]
    fn sqrt(self) -> PD4 {
        PD4(self.0.map(f64::sqrt))
    }
    #[inline(always)]
    fn min(self, o: PD4) -> PD4 {
        PD4(std::array::from_fn(|i| {
            if self.0[i] < o.0[i] {
                self.0[i]
            } else {
                o.0[i]
            }
        }))
    }
    #[inline(always)]
    fn max(self, o: PD4) -> PD4 {
        PD4(std::array::from_fn(|i| {
            if self.0[i] > o.0[i] {
                self.0[i]
            } else {
                o.0[i]
            }
        }))
    }
    #[inline(always)]
    fn select_gt(self, o: PD4, a: PD4, b: PD4) -> PD4 {
        PD4(std::array::from_fn(|i| {
            if self.0[i] > o.0[i] {
                a.0[i]
            } else {
                b.0[i]
            }
        }))
    }
    #[inline(always)]
    fn gt_mask(self, o: PD4) -> u32 {
        let mut m = 0;
        for i in 0..F64_LANES {
            m |= u32::from(self.0[i] > o.0[i]) << i;
        }
        m
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f64 {
        self.0[i]
    }
    #[inline(always)]
    fn store(self, out: &mut [f64]) {
        out[..F64_LANES].copy_from_slice(&self.0);
    }
}

impl Isa for Portable {
    type V = P8;
    type I = PI8;
    type D = PD4;
    #[inline(always)]
    fn splat_f64(self, v: f64) -> PD4 {
        PD4([v; F64_LANES])
    }
    #[inline(always)]
    fn load_f64(self, s: &[f64]) -> PD4 {
        let mut a = [0.0; F64_LANES];
        a.copy_from_slice(&s[..F64_LANES]);
        PD4(a)
    }
    #[inline(always)]
    fn i32_to_f64(self, v: PI8, h: usize) -> PD4 {
        assert!(h < 2, "half {h} of eight i32 lanes");
        PD4(std::array::from_fn(|i| v.0[4 * h + i] as f64))
    }
    #[inline(always)]
    fn f64_to_f32(self, lo: PD4, hi: PD4) -> P8 {
        P8(std::array::from_fn(|i| {
            if i < F64_LANES {
                lo.0[i] as f32
            } else {
                hi.0[i - F64_LANES] as f32
            }
        }))
    }
    #[inline(always)]
    fn splat_i32(self, v: i32) -> PI8 {
        PI8([v; LANES])
    }
    #[inline(always)]
    fn load_i32(self, s: &[i32]) -> PI8 {
        let mut a = [0; LANES];
        a.copy_from_slice(&s[..LANES]);
        PI8(a)
    }
    #[inline(always)]
    fn splat(self, v: f32) -> P8 {
        P8([v; LANES])
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> P8 {
        let mut a = [0.0; LANES];
        a.copy_from_slice(&s[..LANES]);
        P8(a)
    }
    fn name(self) -> &'static str {
        "portable"
    }
    type Wide = Narrow<Portable>;
    #[inline(always)]
    fn wide(self) -> Narrow<Portable> {
        Narrow(self)
    }
    #[inline(always)]
    fn half(self, w: P8, h: usize) -> P8 {
        debug_assert_eq!(h, 0);
        w
    }
    #[inline(always)]
    fn transpose8(self, rows: [P8; 8]) -> [P8; 8] {
        std::array::from_fn(|i| P8(std::array::from_fn(|j| rows[j].0[i])))
    }
}

impl Add for P8 {
    type Output = P8;
    #[inline(always)]
    fn add(self, o: P8) -> P8 {
        map2(self, o, |a, b| a + b)
    }
}
impl Sub for P8 {
    type Output = P8;
    #[inline(always)]
    fn sub(self, o: P8) -> P8 {
        map2(self, o, |a, b| a - b)
    }
}
impl Mul for P8 {
    type Output = P8;
    #[inline(always)]
    fn mul(self, o: P8) -> P8 {
        map2(self, o, |a, b| a * b)
    }
}
impl AddAssign for P8 {
    #[inline(always)]
    fn add_assign(&mut self, o: P8) {
        *self = *self + o;
    }
}

impl Arith for P8 {
    #[inline(always)]
    fn fma(self, b: P8, c: P8) -> P8 {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = self.0[i].mul_add(b.0[i], c.0[i]);
        }
        P8(r)
    }
    #[inline(always)]
    fn neg_fma(self, b: P8, c: P8) -> P8 {
        // `-(a b) + c` with one rounding, as `vfnmadd`: negating `a` is exact.
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = (-self.0[i]).mul_add(b.0[i], c.0[i]);
        }
        P8(r)
    }
}

impl F32x8 for P8 {
    #[inline(always)]
    fn floor(self) -> P8 {
        P8(self.0.map(f32::floor))
    }
    #[inline(always)]
    fn abs(self) -> P8 {
        P8(self.0.map(f32::abs))
    }
    #[inline(always)]
    fn select_gt(self, o: P8, a: P8, b: P8) -> P8 {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = if self.0[i] > o.0[i] { a.0[i] } else { b.0[i] };
        }
        P8(r)
    }
    #[inline(always)]
    fn gather(self, table: &[f32]) -> P8 {
        assert!(!table.is_empty() && table.len() < 1 << 24);
        let hi = (table.len() - 1) as f32;
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            // `max` first: a NaN index becomes 0, as `maxps` does below.
            let k = if self.0[i] > 0.0 { self.0[i] } else { 0.0 };
            let k = if k < hi { k } else { hi };
            r[i] = table[k as usize];
        }
        P8(r)
    }
    #[inline(always)]
    fn div(self, o: P8) -> P8 {
        map2(self, o, |a, b| a / b)
    }
    #[inline(always)]
    fn sqrt(self) -> P8 {
        P8(self.0.map(f32::sqrt))
    }
    #[inline(always)]
    fn min(self, o: P8) -> P8 {
        // Same NaN rule as `minps`: the second operand when either is NaN.
        map2(self, o, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    fn max(self, o: P8) -> P8 {
        map2(self, o, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn gt_mask(self, o: P8) -> u32 {
        (0..LANES).fold(0, |m, i| m | (((self.0[i] > o.0[i]) as u32) << i))
    }
    #[inline(always)]
    fn positive_part(self) -> P8 {
        P8(self.0.map(|v| if v > 0.0 { v } else { 0.0 }))
    }
    #[inline(always)]
    fn keep(self, mask: u32) -> P8 {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            if mask & (1 << i) != 0 {
                r[i] = self.0[i];
            }
        }
        P8(r)
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.0[i]
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        out[..LANES].copy_from_slice(&self.0);
    }
    #[inline(always)]
    fn compress_store(self, mask: u32, out: &mut [f32], at: usize) -> usize {
        let out = &mut out[at..at + LANES];
        let idx = &COMPRESS[(mask & 0xff) as usize];
        let n = (mask & 0xff).count_ones() as usize;
        for k in 0..LANES {
            out[k] = self.0[idx[k] as usize];
        }
        n
    }
}
