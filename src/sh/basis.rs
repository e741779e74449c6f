//! Real orthonormal spherical harmonics evaluated from a Cartesian direction by recurrence.
//!
//! (Past 400 lines because it is the one recurrence and the tests that pin it: the scalar
//! evaluation, its lane form [`ShLanes`] that must keep its bits, and the independent
//! reference both are checked against.)
//!
//! Design rule: one recurrence, written once (a macro instantiates it for `f32` and `f64`),
//! with no trigonometry and no factorials: the thesis (Def. 11) writes
//! `Y_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) P_l^m(cos polar) e^{i m azimuth}`, whose
//! factorials overflow `f32` near l = 17 and whose trigonometry costs one `sin_cos` per m.
//!
//! # Convention (the only one in brdfkit; the file format records it, see `sh::file`)
//! * **Frame**: the SH are functions of a direction in the *local shading frame* of
//!   [`crate::conventions`]: the polar angle is measured from local +z (the normal) and the
//!   azimuth from local +x (world up projected onto the tangent plane), counter-clockwise
//!   towards local +y. So `(x, y, z) = (sin p cos a, sin p sin a, cos p)`.
//! * **Normalisation**: orthonormal over the *full* sphere:
//!   `integral_{S^2} Y_i Y_j dω = δ_ij` (dω in steradians).
//! * **Real form**: with `K_lm = sqrt((2l+1)/(4 pi) (l-|m|)!/(l+|m|)!)`,
//!   `Y_l0 = K_l0 P_l^0(z)`,
//!   `Y_lm = sqrt(2) K_lm P_l^m(z) cos(m a)` for m > 0,
//!   `Y_lm = sqrt(2) K_l|m| P_l^|m|(z) sin(|m| a)` for m < 0.
//! * **Condon-Shortley phase: NOT included.** `P_l^m` is taken without the `(-1)^m`
//!   factor, so `Y_11 = +sqrt(3/(4 pi)) x`, `Y_1,-1 = +sqrt(3/(4 pi)) y`,
//!   `Y_10 = +sqrt(3/(4 pi)) z` (all positive lobes along the positive axes).
//! * **Ordering**: flat index `k = l*l + l + m` (so `k = 0: (0,0)`, `1: (1,-1)`, `2: (1,0)`,
//!   `3: (1,1)`, `4: (2,-2)`, ...). `bands` = L means all l < L, i.e. `L*L` terms.
//!
//! # Recurrence
//! `sin^m(p) cos(m a) = Re((x + i y)^m) = C_m` and `sin^m(p) sin(m a) = Im((x + i y)^m) = S_m`
//! follow `C_m = x C_{m-1} - y S_{m-1}`, `S_m = x S_{m-1} + y C_{m-1}` (Chebyshev-like, no
//! trigonometry). The remaining polynomial in z, `Q_l^m(z) = K_lm P_l^m(z) / sin^m(p)`, is
//! normalised on the fly (standard fully-normalised recurrence, e.g. Sloan, "Stupid
//! Spherical Harmonics Tricks", 2008, and Holmes & Featherstone, J. Geodesy 76, 2002):
//! * `Q_00 = 1 / sqrt(4 pi)`,
//! * `Q_mm = sqrt((2m+1)/(2m)) Q_{m-1,m-1}`,
//! * `Q_{m+1,m} = sqrt(2m+3) z Q_mm`,
//! * `Q_lm = a_lm (z Q_{l-1,m} - b_lm Q_{l-2,m})`, with
//!   `a_lm = sqrt((4l^2-1)/(l^2-m^2))`, `b_lm = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1))`.
//!
//! All factors stay O(sqrt(l)), so any band count is safe from overflow.

use glam::{DVec3, Vec3};

/// Number of SH terms for `bands` bands (all l < bands): `bands * bands`.
#[inline]
pub const fn num_terms(bands: usize) -> usize {
    bands * bands
}

/// Flat index of `(l, m)`: `l*l + l + m`. Requires `|m| <= l` (debug assertion).
#[inline]
pub const fn sh_index(l: usize, m: i32) -> usize {
    debug_assert!(m.unsigned_abs() as usize <= l);
    (l * l + l).wrapping_add_signed(m as isize)
}

/// `(l, m)` of a flat index `k` (inverse of [`sh_index`]).
#[inline]
pub fn sh_lm(k: usize) -> (usize, i32) {
    let mut l = (k as f64).sqrt() as usize;
    // Guard against rounding of the square root for large k.
    while l * l > k {
        l -= 1;
    }
    while (l + 1) * (l + 1) <= k {
        l += 1;
    }
    (l, k as i32 - (l * l + l) as i32)
}

/// `sqrt((2m+1)/(2m))`, the step `Q_{m-1,m-1} -> Q_mm` (module doc, "Recurrence"), in f64
/// (exact integers, one rounding per operation). `m >= 1`.
#[inline]
fn qmm_step(m: usize) -> f64 {
    let mf = m as f64;
    ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt()
}

/// `sqrt(2m+3)`, the step `Q_mm -> Q_{m+1,m}` (module doc), in f64.
#[inline]
fn first_step(m: usize) -> f64 {
    let mf = m as f64;
    (2.0 * mf + 3.0).sqrt()
}

/// `[a_lm, b_lm]` of the three-term step `Q_lm = a_lm (z Q_{l-1,m} - b_lm Q_{l-2,m})`
/// (module doc), in f64. `l >= m + 2`.
#[inline]
fn step_ab(l: usize, m: usize) -> [f64; 2] {
    let lf = l as f64;
    let mf = m as f64;
    let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
    let lm1 = lf - 1.0;
    let b = ((lm1 * lm1 - mf * mf) / (4.0 * lm1 * lm1 - 1.0)).sqrt();
    [a, b]
}

macro_rules! sh_eval_impl {
    ($name:ident, $t:ty, $v:ty) => {
        /// Evaluates every real SH term of the bands `l < out.len().sqrt()` at the direction
        /// `dir` (local shading frame, see the module doc), writing `Y_k(dir)` into `out[k]`
        /// with `k = l*l + l + m`.
        ///
        /// `out.len()` must be a perfect square `L*L` (L = number of bands, any L >= 0);
        /// otherwise the call panics. `dir` need not be unit: it is normalised inside. A zero
        /// or non-finite `dir` is replaced by +z (documented fallback, no NaN output).
        /// No allocation, no trigonometry.
        pub fn $name(dir: $v, out: &mut [$t]) {
            let n = out.len();
            let bands = (n as f64).sqrt() as usize;
            assert!(
                bands * bands == n,
                "SH output slice length {} is not a square number of terms",
                n
            );
            if bands == 0 {
                return;
            }
            let d = dir.try_normalize().unwrap_or(<$v>::Z);
            let (x, y, z) = (d.x, d.y, d.z);
            let one: $t = 1.0;
            let sqrt2: $t = std::f64::consts::SQRT_2 as $t;
            // m = 0 column.
            let q00: $t = 0.5 / (std::f64::consts::PI as $t).sqrt();
            // Q_{m,m} carried across m; C_m, S_m carried across m.
            let mut qmm = q00;
            let (mut cm, mut sm): ($t, $t) = (one, 0.0);
            for m in 0..bands {
                if m > 0 {
                    qmm *= qmm_step(m) as $t;
                    let c = x * cm - y * sm;
                    let s = x * sm + y * cm;
                    cm = c;
                    sm = s;
                }
                let (fc, fs) = if m == 0 {
                    (one, 0.0)
                } else {
                    (sqrt2 * cm, sqrt2 * sm)
                };
                // l = m
                let mut q_lm2: $t = 0.0; // Q_{l-2,m}
                let mut q_lm1: $t = qmm; // Q_{l-1,m} (becomes previous after the first step)
                let write = |out: &mut [$t], l: usize, q: $t| {
                    let base = l * l + l;
                    if m == 0 {
                        out[base] = q;
                    } else {
                        out[base + m] = q * fc;
                        out[base - m] = q * fs;
                    }
                };
                write(out, m, qmm);
                if m + 1 < bands {
                    let q = first_step(m) as $t * z * qmm;
                    write(out, m + 1, q);
                    q_lm2 = qmm;
                    q_lm1 = q;
                }
                for l in (m + 2)..bands {
                    // Constants in f64 (exact integers, one rounding) then narrowed.
                    let [a, b] = step_ab(l, m).map(|c| c as $t);
                    let q = a * (z * q_lm1 - b * q_lm2);
                    write(out, l, q);
                    q_lm2 = q_lm1;
                    q_lm1 = q;
                }
                let _ = q_lm2;
            }
        }
    };
}

sh_eval_impl!(eval_sh_f32, f32, Vec3);
sh_eval_impl!(eval_sh_f64, f64, DVec3);

/// Number of directions [`ShLanes::eval`] evaluates at once.
pub const SH_LANES: usize = 4;

/// One value per lane, lane `i` the `i`-th of [`SH_LANES`] directions.
pub type Lanes = [f64; SH_LANES];

/// [`eval_sh_f64`] for [`SH_LANES`] directions at once, for loops that evaluate the basis
/// millions of times (a transfer table's build, [`crate::env::transfer`]): the recurrence's
/// constants computed once for a band count, and the recurrence (module doc) run on arrays
/// of lanes, which the compiler vectorises. Each lane's value is [`eval_sh_f64`]'s, bit for
/// bit: the same IEEE operations in the same order (the constants are the same f64
/// expressions, evaluated once instead of per call); a test holds it to that.
#[derive(Clone, Debug)]
pub struct ShLanes {
    bands: usize,
    /// `qmm_step(m)` (index 0 unused) and `first_step(m)`, per `m`.
    steps: Vec<[f64; 2]>,
    /// `step_ab(l, m)` at `l * bands + m`, for `l >= m + 2`.
    ab: Vec<[f64; 2]>,
}

impl ShLanes {
    /// The constants for `bands` bands (`bands * bands` terms).
    pub fn new(bands: usize) -> ShLanes {
        let mut ab = vec![[0.0; 2]; bands * bands];
        for m in 0..bands {
            for l in (m + 2)..bands {
                ab[l * bands + m] = step_ab(l, m);
            }
        }
        ShLanes {
            bands,
            steps: (0..bands)
                .map(|m| [if m > 0 { qmm_step(m) } else { 0.0 }, first_step(m)])
                .collect(),
            ab,
        }
    }

    /// The band count.
    pub fn bands(&self) -> usize {
        self.bands
    }

    /// Writes `Y_k(d_i)` to `out[k][i]` for the directions `d_i = (x[i], y[i], z[i])`
    /// (local shading frame, normalised inside, a zero or non-finite direction replaced by
    /// +z, as [`eval_sh_f64`]). `out.len()` must be `bands * bands`. Always inlined, so a
    /// caller inside a lane kernel ([`crate::lanes::Kernel`]) compiles it for that kernel's
    /// instruction set (the same operations, never fused: the same bits).
    #[inline(always)]
    pub fn eval(&self, x: Lanes, y: Lanes, z: Lanes, out: &mut [Lanes]) {
        let bands = self.bands;
        assert_eq!(
            out.len(),
            bands * bands,
            "SH output lanes for {bands} bands"
        );
        if bands == 0 {
            return;
        }
        #[inline(always)]
        fn lanes(f: impl Fn(usize) -> f64) -> Lanes {
            std::array::from_fn(f)
        }
        // DVec3::try_normalize: 1 / sqrt((x x + y y) + z z), kept when finite and positive.
        let mut d = [[0.0; SH_LANES]; 3];
        for i in 0..SH_LANES {
            let rcp = 1.0 / ((x[i] * x[i] + y[i] * y[i]) + z[i] * z[i]).sqrt();
            let unit = rcp.is_finite() && rcp > 0.0;
            d[0][i] = if unit { x[i] * rcp } else { 0.0 };
            d[1][i] = if unit { y[i] * rcp } else { 0.0 };
            d[2][i] = if unit { z[i] * rcp } else { 1.0 };
        }
        let [x, y, z] = d;
        let sqrt2 = std::f64::consts::SQRT_2;
        let mut qmm: Lanes = [0.5 / std::f64::consts::PI.sqrt(); SH_LANES];
        let (mut cm, mut sm): (Lanes, Lanes) = ([1.0; SH_LANES], [0.0; SH_LANES]);
        for m in 0..bands {
            let [step, first] = self.steps[m];
            if m > 0 {
                qmm = lanes(|i| qmm[i] * step);
                let c = lanes(|i| x[i] * cm[i] - y[i] * sm[i]);
                let s = lanes(|i| x[i] * sm[i] + y[i] * cm[i]);
                cm = c;
                sm = s;
            }
            let fc = lanes(|i| sqrt2 * cm[i]);
            let fs = lanes(|i| sqrt2 * sm[i]);
            let write = |out: &mut [Lanes], l: usize, q: Lanes| {
                let base = l * l + l;
                if m == 0 {
                    out[base] = q;
                } else {
                    out[base + m] = lanes(|i| q[i] * fc[i]);
                    out[base - m] = lanes(|i| q[i] * fs[i]);
                }
            };
            write(out, m, qmm);
            if m + 1 < bands {
                let mut q_lm2 = qmm;
                let mut q_lm1 = lanes(|i| first * z[i] * qmm[i]);
                write(out, m + 1, q_lm1);
                for l in (m + 2)..bands {
                    let [a, b] = self.ab[l * bands + m];
                    let q = lanes(|i| a * (z[i] * q_lm1[i] - b * q_lm2[i]));
                    write(out, l, q);
                    q_lm2 = q_lm1;
                    q_lm1 = q;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Independent reference: explicit Legendre polynomial coefficients (Rodrigues /
    /// explicit sum), differentiated m times exactly, normalisation from a product of
    /// integers, azimuth by `atan2` + `cos`/`sin`. Shares no code with the recurrence.
    fn reference_sh(l: usize, m: i32, d: DVec3) -> f64 {
        let d = d.normalize();
        let am = m.unsigned_abs() as usize;
        // P_l(x) = 2^-l sum_k (-1)^k C(l,k) C(2l-2k, l) x^(l-2k)
        let binom = |n: usize, k: usize| -> f64 {
            let mut r = 1.0f64;
            for i in 0..k {
                r = r * (n - i) as f64 / (i + 1) as f64;
            }
            r
        };
        let mut coef = vec![0.0f64; l + 1]; // coef[p] of x^p
        for k in 0..=l / 2 {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            coef[l - 2 * k] = sign * binom(l, k) * binom(2 * l - 2 * k, l) / 2f64.powi(l as i32);
        }
        // m-th derivative
        let mut dpoly = 0.0;
        for (p, c) in coef.iter().enumerate() {
            if p >= am {
                let mut fall = 1.0;
                for q in 0..am {
                    fall *= (p - q) as f64;
                }
                dpoly += c * fall * d.z.powi((p - am) as i32);
            }
        }
        let s = (d.x * d.x + d.y * d.y).sqrt();
        let plm = s.powi(am as i32) * dpoly; // no Condon-Shortley phase
                                             // (l-m)!/(l+m)! = 1 / prod_{k=l-m+1}^{l+m} k
        let mut prod = 1.0;
        for k in (l - am + 1)..=(l + am) {
            prod *= k as f64;
        }
        let k = ((2 * l + 1) as f64 / (4.0 * PI) / prod).sqrt();
        let az = d.y.atan2(d.x);
        if m == 0 {
            k * plm
        } else if m > 0 {
            2f64.sqrt() * k * plm * (am as f64 * az).cos()
        } else {
            2f64.sqrt() * k * plm * (am as f64 * az).sin()
        }
    }

    fn test_dirs() -> Vec<DVec3> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        let mut v = vec![
            DVec3::Z,
            -DVec3::Z,
            DVec3::X,
            DVec3::Y,
            -DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1e-9, 0.0, 1.0),
            DVec3::new(0.0, -1e-9, -1.0),
        ];
        for i in 0..64 {
            // equator ring
            let a = i as f64 / 64.0 * 2.0 * PI;
            v.push(DVec3::new(a.cos(), a.sin(), 0.0));
        }
        for _ in 0..3000 {
            let z: f64 = rng.gen_range(-1.0..=1.0);
            let a: f64 = rng.gen_range(0.0..2.0 * PI);
            let s = (1.0 - z * z).max(0.0).sqrt();
            v.push(DVec3::new(s * a.cos(), s * a.sin(), z));
        }
        v
    }

    /// Max over directions and terms of |Y - ref| / max(|ref|, floor).
    fn max_rel_err_f64(bands: usize) -> f64 {
        let mut out = vec![0.0f64; bands * bands];
        let mut worst = 0.0f64;
        for d in test_dirs() {
            eval_sh_f64(d, &mut out);
            for (k, &y) in out.iter().enumerate() {
                let (l, m) = sh_lm(k);
                let r = reference_sh(l, m, d);
                let e = (y - r).abs() / r.abs().max(1e-3);
                worst = worst.max(e);
            }
        }
        worst
    }

    #[test]
    fn f64_matches_independent_reference_all_l_below_10() {
        let worst = max_rel_err_f64(10);
        eprintln!("SH f64 vs independent reference: max relative error {worst:e}");
        assert!(worst < 1e-6, "max relative error {worst:e}");
    }

    #[test]
    fn f32_matches_independent_reference_all_l_below_10() {
        let bands = 10;
        let mut out = vec![0.0f32; bands * bands];
        let mut worst = 0.0f64;
        for d in test_dirs() {
            let df = d.as_vec3();
            eval_sh_f32(df, &mut out);
            // Reference at the f32-rounded direction, so only f32 arithmetic is measured.
            let dr = df.as_dvec3();
            for (k, &y) in out.iter().enumerate() {
                let (l, m) = sh_lm(k);
                let r = reference_sh(l, m, dr);
                // Absolute floor 0.1 (band peaks are ~0.3-1.2 for l < 10): near a zero of
                // Y the f32 recurrence error is absolute (cancellation in `z Q1 - b Q2`),
                // a few tens of ulps of the band peak (measured ~3e-6 absolute), so f32 is
                // held to 5e-6 absolute / 5e-5 relative. f64 meets 1e-6 relative (test above).
                let e = (y as f64 - r).abs() / r.abs().max(0.1);
                worst = worst.max(e);
            }
        }
        eprintln!("SH f32 vs f64 reference: max relative error {worst:e}");
        assert!(worst < 5e-5, "max relative error {worst:e}");
    }

    #[test]
    fn closed_forms_low_bands_fix_sign_convention() {
        let c0 = 0.5 / PI.sqrt();
        let c1 = (3.0 / (4.0 * PI)).sqrt();
        let c2 = 0.5 * (15.0 / PI).sqrt();
        let c20 = 0.25 * (5.0 / PI).sqrt();
        let c3m3 = 0.25 * (35.0 / (2.0 * PI)).sqrt();
        let mut out = vec![0.0f64; 16];
        for d in test_dirs().into_iter().take(500) {
            let d = d.normalize();
            let (x, y, z) = (d.x, d.y, d.z);
            eval_sh_f64(d, &mut out);
            let expect = [
                (0, c0),
                (1, c1 * y),
                (2, c1 * z),
                (3, c1 * x),
                (4, c2 * x * y),
                (5, c2 * y * z),
                (6, c20 * (3.0 * z * z - 1.0)),
                (7, c2 * x * z),
                (8, 0.5 * c2 * (x * x - y * y)),
                (9, c3m3 * y * (3.0 * x * x - y * y)),
                (15, c3m3 * x * (x * x - 3.0 * y * y)),
            ];
            for (k, v) in expect {
                assert!((out[k] - v).abs() < 1e-12, "k={k} {} vs {v}", out[k]);
            }
        }
    }

    /// Gauss-Legendre in z times uniform azimuth is exact for products of band-limited
    /// terms (degree <= 18 in z needs 10 nodes; azimuth frequency <= 18 needs > 18 points).
    #[test]
    fn orthonormal_by_exact_quadrature() {
        let bands = 10;
        let n = bands * bands;
        let (zs, ws) = crate::sh::quadrature::gauss_legendre(bands + 1);
        let naz = 2 * bands + 1;
        let mut gram = vec![0.0f64; n * n];
        let mut y = vec![0.0f64; n];
        for (z, w) in zs.iter().zip(&ws) {
            for ia in 0..naz {
                let a = (ia as f64 + 0.5) / naz as f64 * 2.0 * PI;
                let s = (1.0 - z * z).sqrt();
                eval_sh_f64(DVec3::new(s * a.cos(), s * a.sin(), *z), &mut y);
                let wt = w * 2.0 * PI / naz as f64;
                for i in 0..n {
                    for j in 0..n {
                        gram[i * n + j] += wt * y[i] * y[j];
                    }
                }
            }
        }
        for i in 0..n {
            for j in 0..n {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (gram[i * n + j] - e).abs() < 1e-12,
                    "<{i},{j}> = {}",
                    gram[i * n + j]
                );
            }
        }
    }

    #[test]
    fn lanes_give_the_scalar_bits() {
        let mut dirs = test_dirs();
        dirs.extend([
            DVec3::ZERO,
            DVec3::new(f64::NAN, 0.0, 1.0),
            DVec3::new(3.0, -2.0, 0.5),
            DVec3::new(1e-200, 0.0, 0.0),
        ]);
        for bands in [0, 1, 2, 3, 8, 12] {
            let lanes = ShLanes::new(bands);
            let nt = bands * bands;
            let (mut out, mut one) = (vec![[0.0; SH_LANES]; nt], vec![0.0; nt]);
            for group in dirs.chunks(SH_LANES) {
                let at = |f: fn(DVec3) -> f64| -> Lanes {
                    std::array::from_fn(|i| group.get(i).map_or(0.0, |d| f(*d)))
                };
                lanes.eval(at(|d| d.x), at(|d| d.y), at(|d| d.z), &mut out);
                for (i, d) in group.iter().enumerate() {
                    eval_sh_f64(*d, &mut one);
                    for k in 0..nt {
                        assert_eq!(out[k][i].to_bits(), one[k].to_bits(), "{d} term {k}");
                    }
                }
            }
        }
    }

    #[test]
    fn index_roundtrip_and_high_band_finite() {
        for k in 0..400 {
            let (l, m) = sh_lm(k);
            assert_eq!(sh_index(l, m), k);
        }
        let mut out = vec![0.0f32; 40 * 40];
        eval_sh_f32(Vec3::new(0.3, -0.5, 0.2), &mut out);
        assert!(out.iter().all(|v| v.is_finite()));
    }

    #[test]
    #[should_panic]
    fn non_square_slice_panics() {
        let mut out = vec![0.0f32; 5];
        eval_sh_f32(Vec3::Z, &mut out);
    }
}
