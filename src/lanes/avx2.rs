//! The AVX2 + FMA backend of [`super::F32x8`]: `core::arch` intrinsics on `__m256`
//! (x86_64 only). Its values exist only on a CPU that runs them (see the module doc of
//! [`super`]).

use super::*;
use std::arch::x86_64::*;

/// The AVX2 + FMA instruction set. Only [`Dispatch::choose`] makes one (module doc).
#[derive(Clone, Copy, Debug)]
pub struct Avx2Fma(pub(super) ());

/// [`F32x8`] of [`Avx2Fma`]. Made only through an [`Avx2Fma`] token, so every
/// operation below runs on a CPU with AVX2 and FMA.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct A8(__m256);

/// [`I32x8`] of [`Avx2Fma`] and of [`super::Avx512`] (whose eight lanes are 256 bits
/// too). Made only through one of their tokens, so every operation runs on a CPU with AVX2.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct AI8(__m256i);

impl AI8 {
    /// # Safety
    /// The CPU must have AVX2 (the caller holds an [`Avx2Fma`] or [`super::Avx512`] token).
    #[inline(always)]
    pub(super) unsafe fn splat(v: i32) -> AI8 {
        AI8(unsafe { _mm256_set1_epi32(v) })
    }
    /// # Safety
    /// As [`AI8::splat`].
    #[inline(always)]
    pub(super) unsafe fn load(s: &[i32]) -> AI8 {
        let s = &s[..LANES];
        AI8(unsafe { _mm256_loadu_si256(s.as_ptr().cast()) })
    }
}

/// [`F64x4`] of [`Avx2Fma`] and of [`super::Avx512`]: `__m256d`, never fused. Made only
/// through one of their tokens, so every operation runs on a CPU with AVX2.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct AD4(__m256d);

impl AD4 {
    /// # Safety
    /// The CPU must have AVX2 (the caller holds an [`Avx2Fma`] or [`super::Avx512`] token).
    #[inline(always)]
    pub(super) unsafe fn splat(v: f64) -> AD4 {
        AD4(unsafe { _mm256_set1_pd(v) })
    }
    /// # Safety
    /// As [`AD4::splat`].
    #[inline(always)]
    pub(super) unsafe fn load(s: &[f64]) -> AD4 {
        let s = &s[..F64_LANES];
        AD4(unsafe { _mm256_loadu_pd(s.as_ptr()) })
    }
    /// [`Isa::i32_to_f64`].
    ///
    /// # Safety
    /// As [`AD4::splat`].
    #[inline(always)]
    pub(super) unsafe fn from_i32(v: AI8, h: usize) -> AD4 {
        unsafe {
            let half = match h {
                0 => _mm256_castsi256_si128(v.0),
                1 => _mm256_extracti128_si256::<1>(v.0),
                _ => panic!("half {h} of eight i32 lanes"),
            };
            AD4(_mm256_cvtepi32_pd(half))
        }
    }
    /// [`Isa::f64_to_f32`] (`vcvtpd2ps` rounds by MXCSR, which Rust leaves at
    /// round-to-nearest-even: the bits of `x as f32`).
    ///
    /// # Safety
    /// As [`AD4::splat`].
    #[inline(always)]
    pub(super) unsafe fn to_f32(lo: AD4, hi: AD4) -> __m256 {
        unsafe { _mm256_set_m128(_mm256_cvtpd_ps(hi.0), _mm256_cvtpd_ps(lo.0)) }
    }
}

impl Add for AD4 {
    type Output = AD4;
    #[inline(always)]
    fn add(self, o: AD4) -> AD4 {
        AD4(unsafe { _mm256_add_pd(self.0, o.0) })
    }
}

impl Sub for AD4 {
    type Output = AD4;
    #[inline(always)]
    fn sub(self, o: AD4) -> AD4 {
        AD4(unsafe { _mm256_sub_pd(self.0, o.0) })
    }
}

impl Mul for AD4 {
    type Output = AD4;
    #[inline(always)]
    fn mul(self, o: AD4) -> AD4 {
        AD4(unsafe { _mm256_mul_pd(self.0, o.0) })
    }
}

impl Div for AD4 {
    type Output = AD4;
    #[inline(always)]
    fn div(self, o: AD4) -> AD4 {
        AD4(unsafe { _mm256_div_pd(self.0, o.0) })
    }
}

impl F64x4 for AD4 {
    #[inline(always)]
    fn sqrt(self) -> AD4 {
        AD4(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn min(self, o: AD4) -> AD4 {
        // `vminpd` returns the second operand unless the first is less: the documented rule.
        AD4(unsafe { _mm256_min_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn max(self, o: AD4) -> AD4 {
        AD4(unsafe { _mm256_max_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn select_gt(self, o: AD4, a: AD4, b: AD4) -> AD4 {
        unsafe {
            let m = _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0);
            AD4(_mm256_blendv_pd(b.0, a.0, m))
        }
    }
    #[inline(always)]
    fn gt_mask(self, o: AD4) -> u32 {
        (unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0)) }) as u32
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f64 {
        let mut a = [0.0; F64_LANES];
        self.store(&mut a);
        a[i]
    }
    #[inline(always)]
    fn store(self, out: &mut [f64]) {
        let out = &mut out[..F64_LANES];
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) }
    }
}

impl I32x8 for AI8 {
    #[inline(always)]
    fn add(self, o: AI8) -> AI8 {
        AI8(unsafe { _mm256_add_epi32(self.0, o.0) })
    }
    #[inline(always)]
    fn or(self, o: AI8) -> AI8 {
        AI8(unsafe { _mm256_or_si256(self.0, o.0) })
    }
    #[inline(always)]
    fn sign_mask(self) -> u32 {
        // The sign bit of each 32-bit lane, read as a float's (no value is computed).
        (unsafe { _mm256_movemask_ps(_mm256_castsi256_ps(self.0)) }) as u32
    }
}

// SAFETY (every `unsafe` block of this module): the intrinsics need AVX (+ FMA for the
// fused ones, AVX2 for the integer ones), which the existence of an `A8`, `AI8`, `AD4` or
// `Avx2Fma` value proves (see above; an `AI8` or `AD4` comes only from the `unsafe` constructors,
// whose callers hold an `Avx2Fma` or `Avx512` token);
// memory accesses are bounds-checked before the unaligned loads and stores.

impl Isa for Avx2Fma {
    type V = A8;
    type I = AI8;
    type D = AD4;
    #[inline(always)]
    fn splat_f64(self, v: f64) -> AD4 {
        unsafe { AD4::splat(v) }
    }
    #[inline(always)]
    fn load_f64(self, s: &[f64]) -> AD4 {
        unsafe { AD4::load(s) }
    }
    #[inline(always)]
    fn i32_to_f64(self, v: AI8, h: usize) -> AD4 {
        unsafe { AD4::from_i32(v, h) }
    }
    #[inline(always)]
    fn f64_to_f32(self, lo: AD4, hi: AD4) -> A8 {
        A8(unsafe { AD4::to_f32(lo, hi) })
    }
    #[inline(always)]
    fn splat_i32(self, v: i32) -> AI8 {
        unsafe { AI8::splat(v) }
    }
    #[inline(always)]
    fn load_i32(self, s: &[i32]) -> AI8 {
        unsafe { AI8::load(s) }
    }
    #[inline(always)]
    fn splat(self, v: f32) -> A8 {
        A8(unsafe { _mm256_set1_ps(v) })
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> A8 {
        let s = &s[..LANES];
        A8(unsafe { _mm256_loadu_ps(s.as_ptr()) })
    }
    fn name(self) -> &'static str {
        "avx2+fma"
    }
    type Wide = Narrow<Avx2Fma>;
    #[inline(always)]
    fn wide(self) -> Narrow<Avx2Fma> {
        Narrow(self)
    }
    #[inline(always)]
    fn half(self, w: A8, h: usize) -> A8 {
        debug_assert_eq!(h, 0);
        w
    }
    #[inline(always)]
    fn transpose8(self, rows: [A8; 8]) -> [A8; 8] {
        // SAFETY: an `Avx2Fma` token proves AVX (module doc).
        unsafe { transpose8_m256(rows.map(|v| v.0)) }.map(A8)
    }
}

/// The 8 x 8 transpose of `__m256` rows ([`Isa::transpose8`]): lane `j` of result `i` is
/// lane `i` of `r[j]`, by unpacks, shuffles and 128-bit permutes (values moved, never
/// computed). Shared by this backend and the AVX-512 one, whose eight lanes are `__m256`
/// too.
///
/// # Safety
/// The CPU must have AVX (the caller holds an [`Avx2Fma`] or [`super::Avx512`] token).
#[inline(always)]
pub(super) unsafe fn transpose8_m256(r: [__m256; 8]) -> [__m256; 8] {
    unsafe {
        // Pairs of rows interleaved, then pairs of pairs, then the 128-bit halves.
        let t0 = _mm256_unpacklo_ps(r[0], r[1]);
        let t1 = _mm256_unpackhi_ps(r[0], r[1]);
        let t2 = _mm256_unpacklo_ps(r[2], r[3]);
        let t3 = _mm256_unpackhi_ps(r[2], r[3]);
        let t4 = _mm256_unpacklo_ps(r[4], r[5]);
        let t5 = _mm256_unpackhi_ps(r[4], r[5]);
        let t6 = _mm256_unpacklo_ps(r[6], r[7]);
        let t7 = _mm256_unpackhi_ps(r[6], r[7]);
        let u0 = _mm256_shuffle_ps::<0x44>(t0, t2);
        let u1 = _mm256_shuffle_ps::<0xee>(t0, t2);
        let u2 = _mm256_shuffle_ps::<0x44>(t1, t3);
        let u3 = _mm256_shuffle_ps::<0xee>(t1, t3);
        let u4 = _mm256_shuffle_ps::<0x44>(t4, t6);
        let u5 = _mm256_shuffle_ps::<0xee>(t4, t6);
        let u6 = _mm256_shuffle_ps::<0x44>(t5, t7);
        let u7 = _mm256_shuffle_ps::<0xee>(t5, t7);
        [
            _mm256_permute2f128_ps::<0x20>(u0, u4),
            _mm256_permute2f128_ps::<0x20>(u1, u5),
            _mm256_permute2f128_ps::<0x20>(u2, u6),
            _mm256_permute2f128_ps::<0x20>(u3, u7),
            _mm256_permute2f128_ps::<0x31>(u0, u4),
            _mm256_permute2f128_ps::<0x31>(u1, u5),
            _mm256_permute2f128_ps::<0x31>(u2, u6),
            _mm256_permute2f128_ps::<0x31>(u3, u7),
        ]
    }
}

macro_rules! op {
    ($tr:ident, $f:ident, $intr:ident) => {
        impl $tr for A8 {
            type Output = A8;
            #[inline(always)]
            fn $f(self, o: A8) -> A8 {
                A8(unsafe { $intr(self.0, o.0) })
            }
        }
    };
}
op!(Add, add, _mm256_add_ps);
op!(Sub, sub, _mm256_sub_ps);
op!(Mul, mul, _mm256_mul_ps);

impl AddAssign for A8 {
    #[inline(always)]
    fn add_assign(&mut self, o: A8) {
        *self = *self + o;
    }
}

impl Arith for A8 {
    #[inline(always)]
    fn fma(self, b: A8, c: A8) -> A8 {
        A8(unsafe { _mm256_fmadd_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_fma(self, b: A8, c: A8) -> A8 {
        A8(unsafe { _mm256_fnmadd_ps(self.0, b.0, c.0) })
    }
}

impl F32x8 for A8 {
    #[inline(always)]
    fn floor(self) -> A8 {
        A8(unsafe { _mm256_floor_ps(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> A8 {
        A8(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    #[inline(always)]
    fn select_gt(self, o: A8, a: A8, b: A8) -> A8 {
        unsafe {
            let m = _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0);
            A8(_mm256_blendv_ps(b.0, a.0, m))
        }
    }
    #[inline(always)]
    fn gather(self, table: &[f32]) -> A8 {
        assert!(!table.is_empty() && table.len() < 1 << 24);
        unsafe {
            let hi = _mm256_set1_ps((table.len() - 1) as f32);
            // maxps returns the second operand for NaN: NaN indices become 0.
            let k = _mm256_min_ps(_mm256_max_ps(self.0, _mm256_setzero_ps()), hi);
            let idx = _mm256_cvttps_epi32(k);
            // In bounds: 0 <= idx <= len - 1 by the clamp above.
            A8(_mm256_i32gather_ps::<4>(table.as_ptr(), idx))
        }
    }
    #[inline(always)]
    fn div(self, o: A8) -> A8 {
        A8(unsafe { _mm256_div_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> A8 {
        A8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn min(self, o: A8) -> A8 {
        A8(unsafe { _mm256_min_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn max(self, o: A8) -> A8 {
        A8(unsafe { _mm256_max_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn gt_mask(self, o: A8) -> u32 {
        unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0)) as u32 }
    }
    #[inline(always)]
    fn positive_part(self) -> A8 {
        unsafe {
            let m = _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, _mm256_setzero_ps());
            A8(_mm256_and_ps(self.0, m))
        }
    }
    #[inline(always)]
    fn keep(self, mask: u32) -> A8 {
        unsafe {
            let bits = _mm256_set1_epi32(mask as i32);
            let sel = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let m = _mm256_cmpeq_epi32(_mm256_and_si256(bits, sel), sel);
            A8(_mm256_and_ps(self.0, _mm256_castsi256_ps(m)))
        }
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        let mut a = [0.0f32; LANES];
        self.store(&mut a);
        a[i]
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..LANES];
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn compress_store(self, mask: u32, out: &mut [f32], at: usize) -> usize {
        let out = &mut out[at..at + LANES];
        let m = (mask & 0xff) as usize;
        unsafe {
            let idx = _mm256_loadu_si256(COMPRESS[m].as_ptr() as *const __m256i);
            let v = _mm256_permutevar8x32_ps(self.0, idx);
            _mm256_storeu_ps(out.as_mut_ptr(), v);
        }
        m.count_ones() as usize
    }
}
