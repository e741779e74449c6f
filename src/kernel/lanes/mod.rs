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

mod portable;
pub use portable::{Portable, P8};

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
pub use avx2::{Avx2Fma, A8};

#[cfg(test)]
mod tests;
