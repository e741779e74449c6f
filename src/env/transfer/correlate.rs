//! The FFT correlation of [`super::build`]'s "How the sum is organised": the spectra of the
//! probe rows' power ([`PowerSpectra`], once per build) and one table row's sum over the
//! probe rows ([`table_row_fft`]), per probe row the weights' transforms multiplied into
//! the power's and added up on the f64 lanes of [`crate::lanes`].
//!
//! # Bits
//! Every value is the one the scalar formulation gives: [`crate::lanes::F64x4`] runs
//! each operation as the IEEE one, never fused, so a lane computes what the scalar
//! expression of its frequency computes (the complex arithmetic as num-complex's `Add`,
//! `Sub`, `Mul` and `conj` form it, operation for operation), and each sum takes its probe
//! rows in index order. The table is the same bits on every kernel path, the portable one
//! (per-lane scalar code, the oracle) included (tests.rs, `lane_paths_give_the_same_table`),
//! and the same as before the lanes (the golden images drawn under `method = "transfer"`).

use super::fault::BuildFault;
use super::weights::RowWeights;
use super::TransferBasis;
use crate::lanes::{Dispatch, F64x4, Isa, Kernel, F64_LANES};
use glam::DVec3;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

/// Which table row a task builds, and the grid and probe sizes.
pub(super) struct RowGeometry {
    pub j: usize,
    pub nu: usize,
    pub nv: usize,
    pub w: usize,
    pub h: usize,
}

/// The discrete Fourier transforms (`X[f] = sum_n x[n] e^{-2 pi i f n / W}`, rustfft's
/// forward transform, f64) of every probe row's texel power, per channel, frequencies
/// `0..=W/2` (the rest are their conjugates: the power is real), real and imaginary parts
/// apart, each channel's run padded with zeros to whole lane groups (`stride` values), so
/// the build's multiply-adds run along frequencies on plain f64 arrays; rows of zero power
/// are marked so the build skips them.
pub(super) struct PowerSpectra {
    /// `re[(r * 3 + c) * stride + f]`, and `im` alike; zero for `f >= half`.
    re: Vec<f64>,
    im: Vec<f64>,
    nonzero: Vec<bool>,
    /// `W / 2 + 1` frequencies.
    half: usize,
    /// `half` rounded up to whole groups of [`F64_LANES`].
    stride: usize,
    fft: std::sync::Arc<dyn Fft<f64>>,
}

impl PowerSpectra {
    /// The spectra of the `w x h` power image `power` (row-major), one task per probe row.
    pub(super) fn new(power: &[[f64; 3]], w: usize, h: usize) -> PowerSpectra {
        let fft = FftPlanner::new().plan_fft_forward(w);
        let half = w / 2 + 1;
        let stride = half.div_ceil(F64_LANES) * F64_LANES;
        let (mut re, mut im) = (vec![0.0; h * 3 * stride], vec![0.0; h * 3 * stride]);
        let nonzero: Vec<bool> = re
            .par_chunks_mut(3 * stride)
            .zip(im.par_chunks_mut(3 * stride))
            .enumerate()
            .map_init(
                || vec![Complex64::new(0.0, 0.0); w],
                |buf, (r, (out_re, out_im))| {
                    let row = &power[r * w..(r + 1) * w];
                    if !row.iter().any(|p| *p != [0.0; 3]) {
                        return false;
                    }
                    for c in 0..3 {
                        for (b, p) in buf.iter_mut().zip(row) {
                            *b = Complex64::new(p[c], 0.0);
                        }
                        fft.process(buf);
                        for (f, v) in buf[..half].iter().enumerate() {
                            out_re[c * stride + f] = v.re;
                            out_im[c * stride + f] = v.im;
                        }
                    }
                    true
                },
            )
            .collect();
        PowerSpectra {
            re,
            im,
            nonzero,
            half,
            stride,
            fft,
        }
    }
}

/// The `nu` nodes of one table row, `nu x 3 x terms` f64 values, by the correlation
/// theorem ([`super::build`]'s "How the sum is organised"): node `i` is
/// `c_k(s_i) = sum_rows sum_cols p(row, col + s_i) w_k(row, col)`, and per probe row the
/// correlation's transform is `P[f] conj(W_k[f])`. So the spectra of the weights are summed
/// against the power's over the probe rows, and one inverse transform per term and
/// channel at the end gives every shift at once: per probe row `terms / 2` complex FFTs of
/// size `W` (two real weight rows packed in one) and `3 terms (W/2 + 1)` complex
/// multiply-adds (on the lanes of `dispatch`, the module doc's "Bits"), where the direct
/// sum takes `3 terms nu (columns above the horizon)`. Only the shifts `s_i = i W / nu` are
/// needed, so the inverse is an `nu`-point transform of the spectrum folded modulo `nu`.
pub(super) fn table_row_fft(
    g: &RowGeometry,
    basis: TransferBasis,
    spectra: &PowerSpectra,
    dirs: &[DVec3],
    fault: BuildFault,
    dispatch: Dispatch,
) -> Vec<f64> {
    let (w, nu) = (g.w, g.nu);
    let nt = basis.terms();
    let (half, stride) = (spectra.half, spectra.stride);
    let zero = Complex64::new(0.0, 0.0);
    let (acc_re, acc_im) = dispatch.run(RowSums {
        g,
        basis,
        spectra,
        dirs,
        fault,
    });
    // Fold each spectrum modulo nu (the shifts are multiples of W / nu) and invert.
    let inverse = FftPlanner::new().plan_fft_inverse(nu);
    let mut out = vec![0.0f64; nu * 3 * nt];
    let mut folded = vec![zero; nu];
    for k in 0..nt {
        for c in 0..3 {
            let o = (k * 3 + c) * stride;
            let a = |f: usize| Complex64::new(acc_re[o + f], acc_im[o + f]);
            folded.fill(zero);
            for f in 0..w {
                // Frequencies past W/2 are the conjugates of W - f (a real correlation).
                let v = if f < half { a(f) } else { a(w - f).conj() };
                folded[f % nu] += v;
            }
            inverse.process(&mut folded);
            for i in 0..nu {
                out[(i * 3 + c) * nt + k] = folded[i].re / w as f64;
            }
        }
    }
    out
}

/// [`table_row_fft`]'s sum over the probe rows as a lane kernel: returns
/// `acc[(k * 3 + c) * stride + f] = sum over rows of P_c[f] conj(W_k[f])`, real and
/// imaginary parts apart, each sum taking its rows in index order.
struct RowSums<'a> {
    g: &'a RowGeometry,
    basis: TransferBasis,
    spectra: &'a PowerSpectra,
    dirs: &'a [DVec3],
    fault: BuildFault,
}

impl Kernel for RowSums<'_> {
    type Out = (Vec<f64>, Vec<f64>);

    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> (Vec<f64>, Vec<f64>) {
        let RowSums {
            g,
            basis,
            spectra,
            dirs,
            fault,
        } = self;
        let (w, h) = (g.w, g.h);
        let nt = basis.terms();
        let (half, stride) = (spectra.half, spectra.stride);
        let zero = Complex64::new(0.0, 0.0);
        let (mut acc_re, mut acc_im) = (vec![0.0; nt * 3 * stride], vec![0.0; nt * 3 * stride]);
        let mut weights = RowWeights::new(basis, w);
        let mut z = vec![zero; w];
        let mut scratch = vec![zero; spectra.fft.get_inplace_scratch_len()];
        // Z[f] and conj(Z[-f]) by parts for f < half, zero past it.
        let (mut a_re, mut a_im) = (vec![0.0; stride], vec![0.0; stride]);
        let (mut b_re, mut b_im) = (vec![0.0; stride], vec![0.0; stride]);
        let (one_half, minus_half) = (s.splat_f64(0.5), s.splat_f64(-0.5));
        let (zero_l, minus_one) = (s.splat_f64(0.0), s.splat_f64(-1.0));
        for r in 0..h {
            if !spectra.nonzero[r]
                || !weights.compute((g.j, g.nv), r, dirs, fault != BuildFault::NoHemisphereClip)
            {
                continue;
            }
            let p_re = &spectra.re[r * 3 * stride..(r + 1) * 3 * stride];
            let p_im = &spectra.im[r * 3 * stride..(r + 1) * 3 * stride];
            for k0 in (0..nt).step_by(2) {
                let k1 = k0 + 1;
                let pair = k1 < nt;
                // Two real rows in one complex transform: z = w_k0 + i w_k1.
                if pair {
                    let (a, b) = (weights.term(k0), weights.term(k1));
                    for ((zc, x), y) in z.iter_mut().zip(a).zip(b) {
                        *zc = Complex64::new(*x, *y);
                    }
                } else {
                    for (zc, x) in z.iter_mut().zip(weights.term(k0)) {
                        *zc = Complex64::new(*x, 0.0);
                    }
                }
                spectra.fft.process_with_scratch(&mut z, &mut scratch);
                for f in 0..half {
                    let (a, b) = (z[f], z[if f == 0 { 0 } else { w - f }].conj());
                    (a_re[f], a_im[f], b_re[f], b_im[f]) = (a.re, a.im, b.re, b.im);
                }
                for f in (0..stride).step_by(F64_LANES) {
                    let (ar, ai) = (s.load_f64(&a_re[f..]), s.load_f64(&a_im[f..]));
                    let (br, bi) = (s.load_f64(&b_re[f..]), s.load_f64(&b_im[f..]));
                    // W_k0 = (Z[f] + conj Z[-f]) / 2, W_k1 = (Z[f] - conj Z[-f]) / 2i, each
                    // conjugated, as num-complex forms `((a + b) * 0.5).conj()` and
                    // `((a - b) * Complex64::new(0.0, -0.5)).conj()` (`-x` as `x * -1`,
                    // the same bits).
                    let v0 = [(ar + br) * one_half, ((ai + bi) * one_half) * minus_one];
                    let (dr, di) = (ar - br, ai - bi);
                    let v1 = [
                        dr * zero_l - di * minus_half,
                        (dr * minus_half + di * zero_l) * minus_one,
                    ];
                    for c in 0..3 {
                        let q_re = s.load_f64(&p_re[c * stride + f..]);
                        let q_im = s.load_f64(&p_im[c * stride + f..]);
                        for (k, v) in [(k0, v0), (k1, v1)].into_iter().take(1 + pair as usize) {
                            // The complex product P conj(W) as num-complex's `Mul` forms it.
                            let o = (k * 3 + c) * stride + f;
                            let sum_re = s.load_f64(&acc_re[o..]) + (q_re * v[0] - q_im * v[1]);
                            let sum_im = s.load_f64(&acc_im[o..]) + (q_re * v[1] + q_im * v[0]);
                            sum_re.store(&mut acc_re[o..o + F64_LANES]);
                            sum_im.store(&mut acc_im[o..o + F64_LANES]);
                        }
                    }
                }
            }
        }
        (acc_re, acc_im)
    }
}
