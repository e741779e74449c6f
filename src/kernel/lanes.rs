//! The one SIMD wrapper: eight f32 lanes ([`F32x8`]) on an instruction set chosen once
//! per frame ([`Dispatch::choose`] from a [`KernelPath`]), never per pixel or per call.
//!
//! Two implementations of the same small interface, and no others (there is no AVX-512
//! path yet):
//! - [`Avx2Fma`]: `core::arch` AVX2 + FMA intrinsics on `__m256` (x86_64 only). A value of
//!   its vector type can only come from a token, and the only way to make the token is
//!   [`Dispatch::choose`] after `is_x86_feature_detected!("avx2")` and `("fma")`: holding a
//!   vector proves the CPU runs its instructions, which makes the safe operators sound.
//!   [`Dispatch::run`] calls the kernel inside a `#[target_feature(enable = "avx2,fma")]`
//!   function, so the `#[inline(always)]` kernel code is compiled for AVX2 there.
//! - [`Portable`]: `[f32; 8]` with per-lane loops, for any CPU.
//!
//! Every operation is the IEEE operation per lane, and the two paths give the same bits:
//! [`F32x8::mul_add`] is fused (one rounding) on both, `vfmadd` on [`Avx2Fma`] and
//! [`f32::mul_add`] per lane on [`Portable`] (a hardware FMA where the target has one, else
//! libm's correctly rounded `fmaf`, slower but exact); lane sums, gathers (clamped and
//! truncated indices, NaN to 0), `min`/`max` (the second operand for NaN) and masks follow
//! one rule on both. `tests/golden.rs` renders every golden entry on both paths and
//! requires identical bits; the scalar oracle, another summation order, is held within the
//! kernel tolerances ([`crate::kernel::SH_KERNEL_TOLERANCE`],
//! [`crate::kernel::KERNEL_TOLERANCE`]). A frame takes one path for every tile and thread,
//! so images stay bit-identical across thread counts and tile sizes.

// The portable path's per-lane loops index two or three arrays by the lane number, which
// reads as the lane arithmetic it is.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, AddAssign, Mul, Sub};

/// Number of lanes.
pub const LANES: usize = 8;

/// Eight f32 lanes. Lane order is memory order (`load(s)` puts `s[i]` in lane `i`).
pub trait F32x8:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + AddAssign + Send + Sync
{
    /// `self * b + c` with one rounding, on every path (see the module doc).
    fn mul_add(self, b: Self, c: Self) -> Self;
    /// `c - self * b` with one rounding, on every path.
    fn neg_mul_add(self, b: Self, c: Self) -> Self;
    fn div(self, o: Self) -> Self;
    fn sqrt(self) -> Self;
    fn min(self, o: Self) -> Self;
    fn max(self, o: Self) -> Self;
    /// Largest integer not above each lane.
    fn floor(self) -> Self;
    /// `|self|` per lane.
    fn abs(self) -> Self;
    /// Per lane: `a` where `self > o`, else `b` (`b` for NaN).
    fn select_gt(self, o: Self, a: Self, b: Self) -> Self;
    /// `table[self]` per lane: each lane holds an index as a float, clamped to
    /// `[0, table.len() - 1]` and truncated (so never out of bounds). `table` must not be
    /// empty and shorter than 2^24.
    fn gather(self, table: &[f32]) -> Self;
    /// Bit `i` set where lane `i` is `> o` (false for NaN).
    fn gt_mask(self, o: Self) -> u32;
    /// Lanes of `self` where `self > 0`, else `+0` (NaN gives 0).
    fn positive_part(self) -> Self;
    /// Lanes of `self` where bit `i` of `mask` is set, else `+0`.
    fn keep(self, mask: u32) -> Self;
    /// Lane `i` of `self`.
    fn lane(self, i: usize) -> f32;
    /// Writes the lanes to `out[..8]`.
    fn store(self, out: &mut [f32]);
    /// Writes the lanes whose bit is set in `mask`, in lane order, to `out[at..]`, and
    /// returns how many. `out` must hold at least `at + 8` values (all 8 may be written).
    fn compress_store(self, mask: u32, out: &mut [f32], at: usize) -> usize;
    /// Lane sum in a fixed order `((0+1)+(2+3))+((4+5)+(6+7))`.
    #[inline(always)]
    fn sum(self) -> f32 {
        let mut a = [0.0f32; LANES];
        self.store(&mut a);
        ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))
    }
}

/// An instruction set: makes [`F32x8`] values. Copy tokens; see the module doc.
pub trait Isa: Copy + Send + Sync {
    type V: F32x8;
    fn splat(self, v: f32) -> Self::V;
    /// Lanes `s[0..8]` (panics if `s` is shorter).
    fn load(self, s: &[f32]) -> Self::V;
    #[inline(always)]
    fn zero(self) -> Self::V {
        self.splat(0.0)
    }
    /// Name, for benches and `--stats`.
    fn name(self) -> &'static str;
}

/// Work to run on the instruction set [`Dispatch`] picked: `run` must be
/// `#[inline(always)]` (and so must everything it calls in its hot loops), so that it is
/// compiled inside the dispatcher's `target_feature` function.
pub trait Kernel {
    type Out;
    fn run<S: Isa>(self, s: S) -> Self::Out;
}

/// Which kernel path a frame should take: the user's (or a test's) choice, resolved to a
/// [`Dispatch`] by [`Dispatch::choose`]. In scene files `render.kernel`, on the command
/// line `--kernel`.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Deserialize,
    serde::Serialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum KernelPath {
    /// The best path this CPU runs: AVX2 + FMA where detected, else portable.
    #[default]
    Auto,
    /// `[f32; 8]` per-lane loops, on any CPU.
    Portable,
    /// AVX2 + FMA intrinsics (x86_64 CPUs that have both).
    Avx2,
}

impl KernelPath {
    /// Every explicit path, in order.
    pub const EXPLICIT: [KernelPath; 2] = [KernelPath::Portable, KernelPath::Avx2];

    /// The name used in scene files, on the command line and in golden manifests.
    pub fn name(self) -> &'static str {
        match self {
            KernelPath::Auto => "auto",
            KernelPath::Portable => "portable",
            KernelPath::Avx2 => "avx2",
        }
    }

    /// The explicit paths this CPU runs, in [`KernelPath::EXPLICIT`] order.
    pub fn available() -> Vec<KernelPath> {
        KernelPath::EXPLICIT
            .into_iter()
            .filter(|p| Dispatch::choose(*p).is_some())
            .collect()
    }
}

/// The instruction set chosen for a frame.
#[derive(Clone, Copy, Debug)]
pub enum Dispatch {
    #[cfg(target_arch = "x86_64")]
    Avx2Fma(Avx2Fma),
    Portable(Portable),
}

impl Dispatch {
    /// The best instruction set of this CPU (AVX2 + FMA, else portable):
    /// `choose(KernelPath::Auto)`. Cheap, but call it once per frame, not per pixel.
    pub fn detect() -> Dispatch {
        Dispatch::choose(KernelPath::Auto).expect("auto always has a path")
    }

    /// The instruction set of `path`; `None` when this CPU cannot run it (AVX2 without
    /// AVX2 and FMA detected, or on another architecture). Never `None` for
    /// [`KernelPath::Auto`] or [`KernelPath::Portable`].
    pub fn choose(path: KernelPath) -> Option<Dispatch> {
        #[cfg(target_arch = "x86_64")]
        let avx2 = || {
            (is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"))
                .then_some(Dispatch::Avx2Fma(Avx2Fma(())))
        };
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = || None;
        match path {
            KernelPath::Auto => Some(avx2().unwrap_or(Dispatch::Portable(Portable))),
            KernelPath::Portable => Some(Dispatch::Portable(Portable)),
            KernelPath::Avx2 => avx2(),
        }
    }

    /// The portable path, on any CPU (tests compare it with the detected one).
    pub fn portable() -> Dispatch {
        Dispatch::Portable(Portable)
    }

    /// The explicit path this dispatch runs.
    pub fn path(self) -> KernelPath {
        match self {
            #[cfg(target_arch = "x86_64")]
            Dispatch::Avx2Fma(_) => KernelPath::Avx2,
            Dispatch::Portable(_) => KernelPath::Portable,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            #[cfg(target_arch = "x86_64")]
            Dispatch::Avx2Fma(s) => s.name(),
            Dispatch::Portable(s) => s.name(),
        }
    }

    /// Runs `k` on this instruction set.
    #[inline]
    pub fn run<K: Kernel>(self, k: K) -> K::Out {
        match self {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: an `Avx2Fma` token exists only where AVX2 and FMA were detected.
            Dispatch::Avx2Fma(s) => unsafe { run_avx2(s, k) },
            Dispatch::Portable(s) => k.run(s),
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma")]
unsafe fn run_avx2<K: Kernel>(s: Avx2Fma, k: K) -> K::Out {
    k.run(s)
}

/// Lane index lists for [`F32x8::compress_store`]: entry `mask` lists the set bits of
/// `mask` in increasing order, padded with 0.
const COMPRESS: [[u32; LANES]; 256] = {
    let mut t = [[0u32; LANES]; 256];
    let mut m = 0;
    while m < 256 {
        let (mut i, mut n) = (0, 0);
        while i < LANES {
            if m & (1 << i) != 0 {
                t[m][n] = i as u32;
                n += 1;
            }
            i += 1;
        }
        m += 1;
    }
    t
};

// ---------------------------------------------------------------------------------------
// Portable: [f32; 8].

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

impl Isa for Portable {
    type V = P8;
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
    fn mul_add(self, b: P8, c: P8) -> P8 {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = self.0[i].mul_add(b.0[i], c.0[i]);
        }
        P8(r)
    }
    #[inline(always)]
    fn neg_mul_add(self, b: P8, c: P8) -> P8 {
        // `-(a b) + c` with one rounding, as `vfnmadd`: negating `a` is exact.
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = (-self.0[i]).mul_add(b.0[i], c.0[i]);
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

// ---------------------------------------------------------------------------------------
// AVX2 + FMA: __m256.

#[cfg(target_arch = "x86_64")]
pub use avx::{Avx2Fma, A8};

#[cfg(target_arch = "x86_64")]
mod avx {
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

    // SAFETY (every `unsafe` block of this module): the intrinsics need AVX (+ FMA for the
    // fused ones), which the existence of an `A8` or `Avx2Fma` value proves (see above);
    // memory accesses are bounds-checked before the unaligned loads and stores.

    impl Isa for Avx2Fma {
        type V = A8;
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
        fn mul_add(self, b: A8, c: A8) -> A8 {
            A8(unsafe { _mm256_fmadd_ps(self.0, b.0, c.0) })
        }
        #[inline(always)]
        fn neg_mul_add(self, b: A8, c: A8) -> A8 {
            A8(unsafe { _mm256_fnmadd_ps(self.0, b.0, c.0) })
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
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Probe(Vec<f32>, Vec<f32>);
    impl Kernel for Probe {
        type Out = (Vec<f32>, f32, u32, Vec<f32>);
        #[inline(always)]
        fn run<S: Isa>(self, s: S) -> Self::Out {
            let a = s.load(&self.0);
            let b = s.load(&self.1);
            let mut out = vec![0.0; 16];
            let r = (a * b + a - b).max(s.splat(-1.0)).min(s.splat(10.0));
            r.store(&mut out);
            let n = a.compress_store(a.gt_mask(s.zero()), &mut out, 8);
            let mut packed = out[8..8 + n].to_vec();
            packed.push(a.keep(0b1010_0101).sum());
            (
                out[..8].to_vec(),
                a.positive_part().sum(),
                b.gt_mask(a),
                packed,
            )
        }
    }

    #[test]
    fn every_dispatch_path_computes_the_same_lanes() {
        let a = vec![1.0, -2.0, 3.0, -4.0, 5.0, 0.0, 7.0, -0.5];
        let b = vec![0.5, 1.0, -1.0, 2.0, 2.0, 3.0, 0.25, 1.0];
        let want = Dispatch::portable().run(Probe(a.clone(), b.clone()));
        let got = Dispatch::detect().run(Probe(a.clone(), b.clone()));
        assert_eq!(want, got);
        let lanes: Vec<f32> = (0..8)
            .map(|i| (a[i] * b[i] + a[i] - b[i]).clamp(-1.0, 10.0))
            .collect();
        assert_eq!(want.0, lanes);
        assert_eq!(want.1, 16.0);
        assert_eq!(want.2, 0b1010_1010);
        assert_eq!(want.3, vec![1.0, 3.0, 5.0, 7.0, 3.5]);
    }

    struct Fused(f32, f32, f32);
    impl Kernel for Fused {
        type Out = (f32, f32);
        #[inline(always)]
        fn run<S: Isa>(self, s: S) -> (f32, f32) {
            let (a, b, c) = (s.splat(self.0), s.splat(self.1), s.splat(self.2));
            (a.mul_add(b, c).lane(3), a.neg_mul_add(b, c).lane(5))
        }
    }

    #[test]
    fn mul_add_rounds_once_on_every_path() {
        // (1 + 2^-12)^2 = 1 + 2^-11 + 2^-24: the 2^-24 is lost if the product is rounded
        // before the add.
        let a = 1.0 + f32::powi(2.0, -12);
        let c = -(1.0 + f32::powi(2.0, -11));
        let want = (f32::powi(2.0, -24), -f32::powi(2.0, -24));
        assert_ne!(a * a + c, want.0, "the case must tell fused from unfused");
        for path in KernelPath::available() {
            let d = Dispatch::choose(path).unwrap();
            let got = d.run(Fused(a, a, c));
            assert_eq!(got.0, want.0, "{}: mul_add", path.name());
            let got = d.run(Fused(a, a, -c));
            assert_eq!(got.1, want.1, "{}: neg_mul_add", path.name());
        }
    }

    #[test]
    fn auto_and_portable_always_have_a_path() {
        assert!(Dispatch::choose(KernelPath::Auto).is_some());
        assert_eq!(
            Dispatch::choose(KernelPath::Portable).map(Dispatch::path),
            Some(KernelPath::Portable)
        );
        assert!(KernelPath::available().contains(&KernelPath::Portable));
    }
}
