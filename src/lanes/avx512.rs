//! The AVX-512 backend (x86_64 only): AVX-512F + VL with AVX2 + FMA. Eight lanes
//! ([`V8`], `__m256`) use the mask registers of AVX-512VL for compares, compress and masked
//! moves; the wide vectors ([`V16`], `__m512`) carry 16 lanes of the per-lane work (see the
//! module doc of [`super`]: a lane's value has the same bits at 8 and 16 lanes, and sums
//! across lights stay on eight lanes). Every operation is the same IEEE operation per lane
//! as on [`super::Avx2Fma`], so the two give the same bits.

use super::*;
use std::arch::x86_64::*;

/// The AVX-512 instruction set. Only [`Dispatch::choose`] makes one, after detecting
/// AVX-512F, AVX-512VL, AVX2 and FMA.
#[derive(Clone, Copy, Debug)]
pub struct Avx512(pub(super) ());

/// The 16-lane vectors of [`Avx512`]; made only by [`Isa::wide`] of an [`Avx512`].
#[derive(Clone, Copy, Debug)]
pub struct Avx512Wide(());

/// [`F32x8`] of [`Avx512`]. Made only through an [`Avx512`] token.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct V8(__m256);

/// 16 lanes of [`Avx512Wide`]. Made only through an [`Avx512Wide`] token.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct V16(__m512);

// SAFETY (every `unsafe` block of this module): the intrinsics need AVX-512F + VL (and
// AVX2 + FMA), which the existence of a `V8`, `V16`, `Avx512` or `Avx512Wide` value proves
// (see above); memory accesses are bounds-checked before the unaligned loads and stores.

impl Isa for Avx512 {
    type V = V8;
    type I = super::avx2::AI8;
    type D = super::avx2::AD4;
    #[inline(always)]
    fn splat_f64(self, v: f64) -> super::avx2::AD4 {
        unsafe { super::avx2::AD4::splat(v) }
    }
    #[inline(always)]
    fn load_f64(self, s: &[f64]) -> super::avx2::AD4 {
        unsafe { super::avx2::AD4::load(s) }
    }
    #[inline(always)]
    fn i32_to_f64(self, v: super::avx2::AI8, h: usize) -> super::avx2::AD4 {
        unsafe { super::avx2::AD4::from_i32(v, h) }
    }
    #[inline(always)]
    fn f64_to_f32(self, lo: super::avx2::AD4, hi: super::avx2::AD4) -> V8 {
        V8(unsafe { super::avx2::AD4::to_f32(lo, hi) })
    }
    #[inline(always)]
    fn splat_i32(self, v: i32) -> super::avx2::AI8 {
        unsafe { super::avx2::AI8::splat(v) }
    }
    #[inline(always)]
    fn load_i32(self, s: &[i32]) -> super::avx2::AI8 {
        unsafe { super::avx2::AI8::load(s) }
    }
    #[inline(always)]
    fn splat(self, v: f32) -> V8 {
        V8(unsafe { _mm256_set1_ps(v) })
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> V8 {
        let s = &s[..LANES];
        V8(unsafe { _mm256_loadu_ps(s.as_ptr()) })
    }
    fn name(self) -> &'static str {
        "avx512"
    }
    type Wide = Avx512Wide;
    #[inline(always)]
    fn wide(self) -> Avx512Wide {
        Avx512Wide(())
    }
    #[inline(always)]
    fn half(self, w: V16, h: usize) -> V8 {
        unsafe {
            if h == 0 {
                V8(_mm512_castps512_ps256(w.0))
            } else {
                debug_assert_eq!(h, 1);
                // 64-bit extract: AVX-512F (the 32-bit one needs DQ); same bits.
                let hi = _mm512_extractf64x4_pd::<1>(_mm512_castps_pd(w.0));
                V8(_mm256_castpd_ps(hi))
            }
        }
    }
    #[inline(always)]
    fn transpose8(self, rows: [V8; 8]) -> [V8; 8] {
        // SAFETY: an `Avx512` token proves AVX (module doc).
        unsafe { super::avx2::transpose8_m256(rows.map(|v| v.0)) }.map(V8)
    }
}

impl Width for Avx512Wide {
    type V = V16;
    const N: usize = 16;
    #[inline(always)]
    fn splat(self, v: f32) -> V16 {
        V16(unsafe { _mm512_set1_ps(v) })
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> V16 {
        let s = &s[..16];
        V16(unsafe { _mm512_loadu_ps(s.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, v: V16, out: &mut [f32]) {
        let out = &mut out[..16];
        unsafe { _mm512_storeu_ps(out.as_mut_ptr(), v.0) }
    }
    #[inline(always)]
    fn load_groups(self, s: &[f32], at: [usize; 2]) -> V16 {
        let (lo, hi) = (&s[at[0]..at[0] + LANES], &s[at[1]..at[1] + LANES]);
        unsafe {
            let lo = _mm256_castps_pd(_mm256_loadu_ps(lo.as_ptr()));
            let hi = _mm256_castps_pd(_mm256_loadu_ps(hi.as_ptr()));
            // 64-bit insert: AVX-512F (the 32-bit one needs DQ); same bits.
            let v = _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(lo), hi);
            V16(_mm512_castpd_ps(v))
        }
    }
    #[inline(always)]
    fn gt_mask(self, v: V16, o: V16) -> u32 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_GT_OQ>(v.0, o.0) as u32 }
    }
    #[inline(always)]
    fn compress_store(self, v: V16, mask: u32, out: &mut [f32], at: usize) -> usize {
        let out = &mut out[at..at + 16];
        let m = (mask & 0xffff) as u16;
        unsafe {
            // In a register, then one full store, as the eight-lane form.
            let c = _mm512_maskz_compress_ps(m, v.0);
            _mm512_storeu_ps(out.as_mut_ptr(), c);
        }
        m.count_ones() as usize
    }
}

macro_rules! op {
    ($ty:ident, $tr:ident, $f:ident, $intr:ident) => {
        impl $tr for $ty {
            type Output = $ty;
            #[inline(always)]
            fn $f(self, o: $ty) -> $ty {
                $ty(unsafe { $intr(self.0, o.0) })
            }
        }
    };
}
op!(V8, Add, add, _mm256_add_ps);
op!(V8, Sub, sub, _mm256_sub_ps);
op!(V8, Mul, mul, _mm256_mul_ps);
op!(V16, Add, add, _mm512_add_ps);
op!(V16, Sub, sub, _mm512_sub_ps);
op!(V16, Mul, mul, _mm512_mul_ps);

impl AddAssign for V8 {
    #[inline(always)]
    fn add_assign(&mut self, o: V8) {
        *self = *self + o;
    }
}

impl AddAssign for V16 {
    #[inline(always)]
    fn add_assign(&mut self, o: V16) {
        *self = *self + o;
    }
}

impl Arith for V8 {
    #[inline(always)]
    fn fma(self, b: V8, c: V8) -> V8 {
        V8(unsafe { _mm256_fmadd_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_fma(self, b: V8, c: V8) -> V8 {
        V8(unsafe { _mm256_fnmadd_ps(self.0, b.0, c.0) })
    }
}

impl Arith for V16 {
    #[inline(always)]
    fn fma(self, b: V16, c: V16) -> V16 {
        V16(unsafe { _mm512_fmadd_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_fma(self, b: V16, c: V16) -> V16 {
        V16(unsafe { _mm512_fnmadd_ps(self.0, b.0, c.0) })
    }
}

impl F32x8 for V8 {
    #[inline(always)]
    fn floor(self) -> V8 {
        V8(unsafe { _mm256_floor_ps(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> V8 {
        V8(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    #[inline(always)]
    fn select_gt(self, o: V8, a: V8, b: V8) -> V8 {
        unsafe {
            let m = _mm256_cmp_ps_mask::<_CMP_GT_OQ>(self.0, o.0);
            V8(_mm256_mask_blend_ps(m, b.0, a.0))
        }
    }
    #[inline(always)]
    fn gather(self, table: &[f32]) -> V8 {
        assert!(!table.is_empty() && table.len() < 1 << 24);
        unsafe {
            let hi = _mm256_set1_ps((table.len() - 1) as f32);
            // maxps returns the second operand for NaN: NaN indices become 0.
            let k = _mm256_min_ps(_mm256_max_ps(self.0, _mm256_setzero_ps()), hi);
            let idx = _mm256_cvttps_epi32(k);
            // In bounds: 0 <= idx <= len - 1 by the clamp above.
            V8(_mm256_i32gather_ps::<4>(table.as_ptr(), idx))
        }
    }
    #[inline(always)]
    fn div(self, o: V8) -> V8 {
        V8(unsafe { _mm256_div_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> V8 {
        V8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn min(self, o: V8) -> V8 {
        V8(unsafe { _mm256_min_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn max(self, o: V8) -> V8 {
        V8(unsafe { _mm256_max_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn gt_mask(self, o: V8) -> u32 {
        unsafe { _mm256_cmp_ps_mask::<_CMP_GT_OQ>(self.0, o.0) as u32 }
    }
    #[inline(always)]
    fn positive_part(self) -> V8 {
        unsafe {
            let m = _mm256_cmp_ps_mask::<_CMP_GT_OQ>(self.0, _mm256_setzero_ps());
            V8(_mm256_maskz_mov_ps(m, self.0))
        }
    }
    #[inline(always)]
    fn keep(self, mask: u32) -> V8 {
        V8(unsafe { _mm256_maskz_mov_ps(mask as u8, self.0) })
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
        let m = (mask & 0xff) as u8;
        unsafe {
            // Compress in a register, then one full store (the lanes past the count are
            // zero): the memory form of vcompressps is slow on some cores.
            let v = _mm256_maskz_compress_ps(m, self.0);
            _mm256_storeu_ps(out.as_mut_ptr(), v);
        }
        m.count_ones() as usize
    }
}
