//! The one SIMD wrapper: eight f32 lanes ([`F32x8`]), eight i32 lanes ([`I32x8`], for the
//! rasterizer's edge functions), four f64 lanes ([`F64x4`], for work that must give the
//! bits of scalar f64 code: depths, bakes), and the widest vectors of the same instruction set
//! ([`Isa::Wide`], [`Width`]), on an instruction set chosen once per frame
//! ([`Dispatch::choose`] from a [`KernelPath`]), never per pixel or per call.
//!
//! Three implementations of the same small interface, and no others:
//! - [`Avx512`]: AVX-512F + VL (with AVX2 + FMA). Its eight lanes are `__m256` with
//!   mask-register compares, compress and masked moves ([`V8`]); its wide vectors are 16
//!   lanes of `__m512` ([`V16`]), used where the work is per lane (the SH recurrence over
//!   16 lights, 16 pixels of the pixel-packed path, multiply-add peaks).
//! - [`Avx2Fma`]: `core::arch` AVX2 + FMA intrinsics on `__m256` (x86_64 only); its wide
//!   vectors are its eight lanes ([`Narrow`]).
//! - [`Portable`]: `[f32; 8]` with per-lane loops, for any CPU (wide: [`Narrow`]).
//!
//! (Past 400 lines because it is the interface and its dispatch together: the traits each
//! implementation fills in, with every method's contract, and the one place that chooses
//! among them; each implementation is a file of its own.)
//!
//! A value of an x86 path's vector type can only come from a token, and the only way to
//! make the token is [`Dispatch::choose`] after `is_x86_feature_detected!` of the path's
//! features: holding a vector proves the CPU runs its instructions, which makes the safe
//! operators sound. [`Dispatch::run`] calls the kernel inside a `#[target_feature]`
//! function of the path, so the `#[inline(always)]` kernel code is compiled for it there.
//!
//! Every operation is the IEEE operation per lane, and the paths give the same bits:
//! [`Arith::fma`] ([`F32x8::mul_add`]) is fused (one rounding) on all, `vfmadd` on the x86 paths and
//! [`f32::mul_add`] per lane on [`Portable`] (a hardware FMA where the target has one, else
//! libm's correctly rounded `fmaf`, slower but exact); lane sums, gathers (clamped and
//! truncated indices, NaN to 0), `min`/`max` (the second operand for NaN) and masks follow
//! one rule on all. Wide vectors never change a per-pixel sum's order: they compute per-lane
//! values (one light's or one pixel's), and every sum across lights stays on eight lanes in
//! light order (16 lanes are split into two halves, [`Isa::half`], accumulated one after
//! the other), so a pixel's arithmetic is the same at any width.
//! `tests/integration/golden.rs` renders every golden entry on every path and requires
//! identical bits; the scalar oracle, another
//! summation order, is held within the kernel tolerances
//! ([`crate::kernel::SH_KERNEL_TOLERANCE`], [`crate::kernel::KERNEL_TOLERANCE`]). A frame
//! takes one path for every tile and thread, so images stay bit-identical across thread
//! counts and tile sizes.

// The portable path's per-lane loops index two or three arrays by the lane number, which
// reads as the lane arithmetic it is.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, AddAssign, Div, Mul, Sub};

/// Number of lanes.
pub const LANES: usize = 8;

/// Lane arithmetic at any width (the eight lanes of [`F32x8`], the sixteen of a wide
/// vector, [`Width`]): the IEEE operation per lane, so a lane's result never depends on
/// the width it was computed at.
pub trait Arith:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + AddAssign + Send + Sync
{
    /// `self * b + c` with one rounding, on every path (see the module doc).
    fn fma(self, b: Self, c: Self) -> Self;
    /// `c - self * b` with one rounding, on every path.
    fn neg_fma(self, b: Self, c: Self) -> Self;
}

/// Eight f32 lanes. Lane order is memory order (`load(s)` puts `s[i]` in lane `i`).
pub trait F32x8: Arith {
    /// `self * b + c` with one rounding, on every path: [`Arith::fma`].
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        self.fma(b, c)
    }
    /// `c - self * b` with one rounding, on every path: [`Arith::neg_fma`].
    #[inline(always)]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        self.neg_fma(b, c)
    }
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

/// Eight i32 lanes, for integer work in lanes (the rasterizer's edge functions). Lane
/// order is memory order. Every operation is the two's-complement one per lane, the same
/// bits on every path; the caller keeps sums in range (a wrapped lane is not an error but
/// is a wrong edge value).
pub trait I32x8: Copy {
    /// Lane-wise wrapping sum.
    fn add(self, o: Self) -> Self;
    /// Lane-wise bitwise or.
    fn or(self, o: Self) -> Self;
    /// Bit `i` set where lane `i` is negative (its sign bit).
    fn sign_mask(self) -> u32;
}

/// Number of f64 lanes.
pub const F64_LANES: usize = 4;

/// Four f64 lanes, for work that must give exactly the bits of scalar f64 code. Lane order
/// is memory order. Every operation is the IEEE operation per lane with one rounding each
/// and **no fused multiply-add** on any path, so lane `i` of `a * b + c` has the bits of
/// the scalar `a[i] * b[i] + c[i]` (Rust never fuses it), on every path.
pub trait F64x4:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Send
    + Sync
{
    /// Correctly rounded square root per lane ([`f64::sqrt`]'s bits).
    fn sqrt(self) -> Self;
    /// Per lane: `self` where `self < o`, else `o` (so `o` for NaN and for two zeros;
    /// scalar code keeps its bits with `if a < b { a } else { b }`, not [`f64::min`]).
    fn min(self, o: Self) -> Self;
    /// Per lane: `self` where `self > o`, else `o` (as [`F64x4::min`]).
    fn max(self, o: Self) -> Self;
    /// Per lane: `a` where `self > o`, else `b` (`b` for NaN).
    fn select_gt(self, o: Self, a: Self, b: Self) -> Self;
    /// Bit `i` set where lane `i` is `> o` (false for NaN).
    fn gt_mask(self, o: Self) -> u32;
    /// Lane `i` of `self`.
    fn lane(self, i: usize) -> f64;
    /// Writes the lanes to `out[..4]`.
    fn store(self, out: &mut [f64]);
    /// Lane sum in the fixed order `(0 + 1) + (2 + 3)`.
    #[inline(always)]
    fn sum(self) -> f64 {
        let mut a = [0.0f64; F64_LANES];
        self.store(&mut a);
        (a[0] + a[1]) + (a[2] + a[3])
    }
}

/// An instruction set: makes [`F32x8`] (and [`I32x8`], [`F64x4`]) values. Copy tokens; see the module doc.
pub trait Isa: Copy + Send + Sync {
    type V: F32x8;
    /// Its eight i32 lanes.
    type I: I32x8;
    fn splat_i32(self, v: i32) -> Self::I;
    /// Lanes `s[0..8]` (panics if `s` is shorter).
    fn load_i32(self, s: &[i32]) -> Self::I;
    /// Its four f64 lanes.
    type D: F64x4;
    fn splat_f64(self, v: f64) -> Self::D;
    /// Lanes `s[0..4]` (panics if `s` is shorter).
    fn load_f64(self, s: &[f64]) -> Self::D;
    /// Lanes `4 h .. 4 h + 4` of `v` as f64 (exact; `h` is 0 or 1, else it panics).
    fn i32_to_f64(self, v: Self::I, h: usize) -> Self::D;
    /// Eight f32 lanes, `lo`'s four then `hi`'s, each rounded to nearest (the bits of
    /// `x as f32`).
    fn f64_to_f32(self, lo: Self::D, hi: Self::D) -> Self::V;
    fn splat(self, v: f32) -> Self::V;
    /// Lanes `s[0..8]` (panics if `s` is shorter).
    fn load(self, s: &[f32]) -> Self::V;
    #[inline(always)]
    fn zero(self) -> Self::V {
        self.splat(0.0)
    }
    /// Name, for benches and `--stats`.
    fn name(self) -> &'static str;
    /// The widest vectors of this instruction set ([`Width::N`] lanes, a multiple of
    /// [`LANES`]): 16 on AVX-512, else the eight lanes of [`Self::V`] ([`Narrow`]).
    type Wide: Width;
    fn wide(self) -> Self::Wide;
    /// Lanes `8 h .. 8 h + 8` of a wide vector (`h < N / 8`).
    fn half(self, w: <Self::Wide as Width>::V, h: usize) -> Self::V;
    /// The 8 x 8 transpose: lane `j` of result `i` is lane `i` of `rows[j]` (values moved,
    /// never computed). Turns eight pixels' coefficient runs into eight coefficients'
    /// pixel lanes (the pixel-packed path's batch layout).
    fn transpose8(self, rows: [Self::V; 8]) -> [Self::V; 8];
}

/// Vectors of one width on one instruction set, for the code that is the same at any
/// width: per-lane work with no cross-lane step (the SH recurrence, [`crate::kernel::sh`];
/// pixels in lanes). Lane `i` of a result depends only on lane `i` of the operands, so a
/// light's or a pixel's value has the same bits at 8 and at 16 lanes.
pub trait Width: Copy + Send + Sync {
    type V: Arith;
    /// Number of lanes (8 or 16).
    const N: usize;
    fn splat(self, v: f32) -> Self::V;
    /// Lanes `s[0..N]` (panics if `s` is shorter).
    fn load(self, s: &[f32]) -> Self::V;
    /// Writes the lanes to `out[..N]`.
    fn store(self, v: Self::V, out: &mut [f32]);
    #[inline(always)]
    fn zero(self) -> Self::V {
        self.splat(0.0)
    }
    /// Lanes `8 h .. 8 h + 8` from `s[at[h]..at[h] + 8]`, for the `N / 8` first entries of
    /// `at` (two groups of eight from anywhere in `s`, e.g. two chunks of lights).
    fn load_groups(self, s: &[f32], at: [usize; 2]) -> Self::V;
    /// Bit `i` set where lane `i` of `v` is `> o` (false for NaN), as [`F32x8::gt_mask`].
    fn gt_mask(self, v: Self::V, o: Self::V) -> u32;
    /// Writes the lanes whose bit is set in `mask`, in lane order, to `out[at..]`, and
    /// returns how many, as [`F32x8::compress_store`]; `out` must hold `at + N` values.
    fn compress_store(self, v: Self::V, mask: u32, out: &mut [f32], at: usize) -> usize;
}

/// The eight lanes of an instruction set as a [`Width`] (the wide vectors of AVX2 and
/// portable, whose widest is eight).
#[derive(Clone, Copy, Debug)]
pub struct Narrow<S>(pub S);

impl<S: Isa> Width for Narrow<S> {
    type V = S::V;
    const N: usize = LANES;
    #[inline(always)]
    fn splat(self, v: f32) -> S::V {
        self.0.splat(v)
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> S::V {
        self.0.load(s)
    }
    #[inline(always)]
    fn store(self, v: S::V, out: &mut [f32]) {
        v.store(out)
    }
    #[inline(always)]
    fn load_groups(self, s: &[f32], at: [usize; 2]) -> S::V {
        self.0.load(&s[at[0]..])
    }
    #[inline(always)]
    fn gt_mask(self, v: S::V, o: S::V) -> u32 {
        v.gt_mask(o)
    }
    #[inline(always)]
    fn compress_store(self, v: S::V, mask: u32, out: &mut [f32], at: usize) -> usize {
        v.compress_store(mask, out, at)
    }
}

/// The most lanes any [`Width`] has (room for scratch arrays laid out by width).
pub const MAX_LANES: usize = 16;

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
    /// The widest path this CPU runs: AVX-512 where detected, else AVX2 + FMA, else
    /// portable.
    #[default]
    Auto,
    /// `[f32; 8]` per-lane loops, on any CPU.
    Portable,
    /// AVX2 + FMA intrinsics (x86_64 CPUs that have both).
    Avx2,
    /// AVX-512 (F + VL) with AVX2 + FMA: 16 lanes where the work is per lane, mask
    /// registers for compress and tails (x86_64 CPUs that have all four).
    Avx512,
}

impl KernelPath {
    /// Every explicit path, in order.
    pub const EXPLICIT: [KernelPath; 3] =
        [KernelPath::Portable, KernelPath::Avx2, KernelPath::Avx512];

    /// The name used in scene files, on the command line and in golden manifests.
    pub fn name(self) -> &'static str {
        match self {
            KernelPath::Auto => "auto",
            KernelPath::Portable => "portable",
            KernelPath::Avx2 => "avx2",
            KernelPath::Avx512 => "avx512",
        }
    }

    /// The explicit paths this CPU runs, in [`KernelPath::EXPLICIT`] order.
    pub fn available() -> Vec<KernelPath> {
        KernelPath::EXPLICIT
            .into_iter()
            .filter(|p| Dispatch::choose(*p).is_some())
            .collect()
    }

    /// The explicit paths this CPU does not run, each with the instructions it needs: what
    /// a test that loops over [`KernelPath::available`] did not cover, so it can say so.
    pub fn unavailable() -> Vec<(KernelPath, &'static str)> {
        KernelPath::EXPLICIT
            .into_iter()
            .filter(|p| Dispatch::choose(*p).is_none())
            .map(|p| {
                let needs = match p {
                    KernelPath::Avx512 => "AVX-512F, AVX-512VL, AVX2 and FMA",
                    KernelPath::Avx2 => "AVX2 and FMA",
                    KernelPath::Auto | KernelPath::Portable => "nothing",
                };
                (p, needs)
            })
            .collect()
    }
}

/// The instruction set chosen for a frame.
#[derive(Clone, Copy, Debug)]
pub enum Dispatch {
    #[cfg(target_arch = "x86_64")]
    Avx2Fma(Avx2Fma),
    #[cfg(target_arch = "x86_64")]
    Avx512(Avx512),
    Portable(Portable),
}

impl Dispatch {
    /// The widest instruction set of this CPU (AVX-512, else AVX2 + FMA, else portable):
    /// `choose(KernelPath::Auto)`. Cheap, but call it once per frame, not per pixel.
    pub fn detect() -> Dispatch {
        Dispatch::choose(KernelPath::Auto).expect("auto always has a path")
    }

    /// The instruction set of `path`; `None` when this CPU cannot run it (AVX2 without
    /// AVX2 and FMA detected, AVX-512 without AVX-512F and VL besides, or on another
    /// architecture). Never `None` for [`KernelPath::Auto`] or [`KernelPath::Portable`].
    pub fn choose(path: KernelPath) -> Option<Dispatch> {
        #[cfg(target_arch = "x86_64")]
        let (avx2, avx512) = {
            let has_avx2 = || is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma");
            (
                move || has_avx2().then_some(Dispatch::Avx2Fma(Avx2Fma(()))),
                move || {
                    (has_avx2()
                        && is_x86_feature_detected!("avx512f")
                        && is_x86_feature_detected!("avx512vl"))
                    .then_some(Dispatch::Avx512(Avx512(())))
                },
            )
        };
        #[cfg(not(target_arch = "x86_64"))]
        let (avx2, avx512) = (|| None, || None);
        match path {
            KernelPath::Auto => Some(
                avx512()
                    .or_else(avx2)
                    .unwrap_or(Dispatch::Portable(Portable)),
            ),
            KernelPath::Portable => Some(Dispatch::Portable(Portable)),
            KernelPath::Avx2 => avx2(),
            KernelPath::Avx512 => avx512(),
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
            #[cfg(target_arch = "x86_64")]
            Dispatch::Avx512(_) => KernelPath::Avx512,
            Dispatch::Portable(_) => KernelPath::Portable,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            #[cfg(target_arch = "x86_64")]
            Dispatch::Avx2Fma(s) => s.name(),
            #[cfg(target_arch = "x86_64")]
            Dispatch::Avx512(s) => s.name(),
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
            #[cfg(target_arch = "x86_64")]
            // SAFETY: an `Avx512` token exists only where AVX-512F, VL, AVX2 and FMA were
            // detected.
            Dispatch::Avx512(s) => unsafe { run_avx512(s, k) },
            Dispatch::Portable(s) => k.run(s),
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma")]
unsafe fn run_avx2<K: Kernel>(s: Avx2Fma, k: K) -> K::Out {
    k.run(s)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma,avx512f,avx512vl")]
unsafe fn run_avx512<K: Kernel>(s: Avx512, k: K) -> K::Out {
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

mod portable;
pub use portable::{Portable, P8, PD4, PI8};

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
pub use avx2::{Avx2Fma, A8, AD4, AI8};

#[cfg(target_arch = "x86_64")]
mod avx512;
#[cfg(target_arch = "x86_64")]
pub use avx512::{Avx512, Avx512Wide, V16, V8};

#[cfg(test)]
mod tests;
