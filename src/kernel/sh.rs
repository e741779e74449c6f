//! The SH kernel: `sum_k E_k w_k sum_lm c_lm(view) Y_lm(l_k)` for one pixel (thesis 3.1.5,
//! Def. 10 and 12, Code 4), eight lights at a time, one light per lane.
//!
//! Per pixel, a [`Scratch`] first receives the lights above the horizon in local coordinates
//! with their weights `E_k w_k` (`w_k = cos(polar_k)`, or 1 when the data set includes the
//! cosine), compacted in light order ([`super::gather`], shared with every material). [`sh_sum`] then
//! runs, per group of eight, one fused pass over (m, l): the rescaled associated-Legendre
//! recurrence of [`crate::sh::basis`] on eight lanes, accumulating `c_lm Y_lm` per colour at
//! once, so the basis is never stored. The band count is a literal in each of the
//! monomorphised copies (1..=10 bands; more bands take a generic copy), so the (m, l) loops
//! have fixed trip counts and unroll. Units: `E` irradiance (W/m^2) at normal incidence,
//! coefficients in 1/sr, result radiance.

use super::cluster::DirLights;
use super::gather::{gather_dir, Scratch};
use crate::conventions::{hemi_bilinear_texels, hemi_nearest_texel, ShadingFrame};
use crate::lanes::{Arith, F32x8, Isa, Narrow, Width, LANES};
use crate::sh::dataset::{Lookup, ShDataset};
use glam::Vec3;

/// Recurrence constants for `bands` bands, computed exactly as
/// [`crate::sh::basis::eval_sh_f32`] computes them (f64 square roots of exact integer
/// ratios, narrowed to f32; `Q_mm` by the same running product in f32).
#[derive(Clone, Debug)]
pub struct ShRecurrence {
    pub bands: usize,
    /// `Q_mm` per m.
    qmm: Vec<f32>,
    /// `sqrt(2m + 3)` per m.
    c1: Vec<f32>,
    /// `a(l, m)`, `b(l, m)` at index `l*l + l + m` (m >= 0, l >= m + 2).
    a: Vec<f32>,
    b: Vec<f32>,
}

impl ShRecurrence {
    pub fn new(bands: usize) -> ShRecurrence {
        let n = bands * bands;
        let mut r = ShRecurrence {
            bands,
            qmm: vec![0.0; bands],
            c1: vec![0.0; bands],
            a: vec![0.0; n],
            b: vec![0.0; n],
        };
        let mut qmm = 0.5 / (std::f64::consts::PI as f32).sqrt();
        for m in 0..bands {
            let mf = m as f64;
            if m > 0 {
                qmm *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt() as f32;
            }
            r.qmm[m] = qmm;
            r.c1[m] = (2.0 * mf + 3.0).sqrt() as f32;
            for l in (m + 2)..bands {
                let lf = l as f64;
                let lm1 = lf - 1.0;
                r.a[l * l + l + m] = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt() as f32;
                r.b[l * l + l + m] =
                    ((lm1 * lm1 - mf * mf) / (4.0 * lm1 * lm1 - 1.0)).sqrt() as f32;
            }
        }
        r
    }
}

/// Per-lane sums `sum_k c_k Y_k(x, y, z)` for the three colours of one view texel's
/// coefficients `c` (`[R.., G.., B..]`, each `bands^2` long), at the width of `s` (8 or 16
/// lanes: no step crosses lanes, so a lane's value is the same at either). `bands` is a
/// literal at every call site of the hot path ([`sh_sum`]), so the loops below have fixed
/// trip counts.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn sh_dot<S: Width>(
    s: S,
    bands: usize,
    rec: &ShRecurrence,
    c: &[f32],
    packed: bool,
    x: S::V,
    y: S::V,
    z: S::V,
) -> (S::V, S::V, S::V) {
    let t = bands * bands;
    // Per-pixel coefficients `[R.., G.., B..]` (one pixel, splat to every lane), or
    // `packed`: N pixels' coefficients transposed, `c[(colour t + k) N + lane]`.
    let w = if packed { S::N } else { 1 };
    let (cr, cg, cb) = (&c[..t * w], &c[t * w..2 * t * w], &c[2 * t * w..3 * t * w]);
    let (qmm_t, c1_t) = (&rec.qmm[..bands], &rec.c1[..bands]);
    let (a_t, b_t) = (&rec.a[..t], &rec.b[..t]);
    let (mut ar, mut ag, mut ab) = (s.zero(), s.zero(), s.zero());
    // Macros, not closures: a closure is a function of its own, which the compiler may
    // leave out of line and so outside the dispatcher's `target_feature` function.
    macro_rules! acc {
        ($k:expr, $yv:expr) => {{
            let (k, yv) = ($k, $yv);
            if packed {
                ar = yv.fma(s.load(&cr[k * S::N..]), ar);
                ag = yv.fma(s.load(&cg[k * S::N..]), ag);
                ab = yv.fma(s.load(&cb[k * S::N..]), ab);
            } else {
                ar = yv.fma(s.splat(cr[k]), ar);
                ag = yv.fma(s.splat(cg[k]), ag);
                ab = yv.fma(s.splat(cb[k]), ab);
            }
        }};
    }
    let sqrt2 = s.splat(std::f64::consts::SQRT_2 as f32);
    let mut cm = s.splat(1.0);
    let mut sm = s.zero();
    for m in 0..bands {
        if m > 0 {
            // (cos, sin)(m azimuth) from (cos, sin)((m-1) azimuth), scaled by sin(polar)^m.
            let c = y.neg_fma(sm, x * cm);
            let sn = x.fma(sm, y * cm);
            cm = c;
            sm = sn;
        }
        let qmm = s.splat(qmm_t[m]);
        // The azimuth factors (used for m > 0 only).
        let (fc, fs) = if m > 0 {
            (cm * sqrt2, sm * sqrt2)
        } else {
            (cm, sm)
        };
        macro_rules! emit {
            ($l:expr, $q:expr) => {{
                let (l, q) = ($l, $q);
                let base = l * l + l;
                if m == 0 {
                    acc!(base, q);
                } else {
                    acc!(base + m, q * fc);
                    acc!(base - m, q * fs);
                }
            }};
        }
        emit!(m, qmm);
        if m + 1 < bands {
            let mut q2 = qmm;
            let mut q1 = (z * s.splat(c1_t[m])) * qmm;
            emit!(m + 1, q1);
            for l in (m + 2)..bands {
                let k = l * l + l + m;
                let q = q2.neg_fma(s.splat(b_t[k]), z * q1) * s.splat(a_t[k]);
                emit!(l, q);
                q2 = q1;
                q1 = q;
            }
        }
    }
    (ar, ag, ab)
}

/// `sum_k w_k sum_lm c_lm Y_lm(l_k)` (RGB) over the lights in `sc`, for view coefficients
/// `c` (`[R.., G.., B..]`, `rec.bands^2` each). Pads `sc` ([`Scratch::pad`]). Summation
/// order: per lane over the groups of eight in light order, then the lanes in the fixed
/// order of [`F32x8::sum`]; it depends only on the light list, not on the width the basis
/// sums were computed at (16 lights at once on AVX-512, split into their two groups of
/// eight before they are weighted and added).
#[inline(always)]
pub fn sh_sum<S: Isa>(s: S, rec: &ShRecurrence, c: &[f32], sc: &mut Scratch) -> Vec3 {
    if sc.n == 0 {
        return Vec3::ZERO;
    }
    let end = sc.pad();
    macro_rules! bands {
        ($($b:literal)*) => {
            match rec.bands {
                $($b => sh_groups(s, $b, rec, c, sc, end),)*
                b => sh_groups(s, b, rec, c, sc, end),
            }
        };
    }
    bands!(1 2 3 4 5 6 7 8 9 10)
}

#[inline(always)]
fn sh_groups<S: Isa>(
    s: S,
    bands: usize,
    rec: &ShRecurrence,
    c: &[f32],
    sc: &Scratch,
    end: usize,
) -> Vec3 {
    let (mut tr, mut tg, mut tb) = (s.zero(), s.zero(), s.zero());
    let mut o = 0;
    // Whole wide groups (16 lights on AVX-512; none elsewhere, whose widest is eight):
    // the basis sums of 16 lights at once, then weighted and added as two groups of eight,
    // in light order, exactly as the loop below would.
    let wide = s.wide();
    let n = <S::Wide as Width>::N;
    if n > LANES {
        while o + n <= end {
            let (fr, fg, fb) = sh_dot(
                wide,
                bands,
                rec,
                c,
                false,
                wide.load(&sc.x[o..]),
                wide.load(&sc.y[o..]),
                wide.load(&sc.z[o..]),
            );
            for h in 0..n / LANES {
                let p = o + h * LANES;
                tr = s.half(fr, h).mul_add(s.load(&sc.wr[p..]), tr);
                tg = s.half(fg, h).mul_add(s.load(&sc.wg[p..]), tg);
                tb = s.half(fb, h).mul_add(s.load(&sc.wb[p..]), tb);
            }
            o += n;
        }
    }
    // The groups of eight left (all of them on eight-lane paths).
    let narrow = Narrow(s);
    while o < end {
        let (fr, fg, fb) = sh_dot(
            narrow,
            bands,
            rec,
            c,
            false,
            s.load(&sc.x[o..]),
            s.load(&sc.y[o..]),
            s.load(&sc.z[o..]),
        );
        tr = fr.mul_add(s.load(&sc.wr[o..]), tr);
        tg = fg.mul_add(s.load(&sc.wg[o..]), tg);
        tb = fb.mul_add(s.load(&sc.wb[o..]), tb);
        o += LANES;
    }
    Vec3::new(tr.sum(), tg.sum(), tb.sum())
}

/// One pixel through the SH kernel: [`gather_dir`] then [`sh_sum`], on the instruction set
/// of `s`. For benches and tests; the renderer calls the two steps from its tile loop.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn shade_pixel<S: Isa>(
    s: S,
    rec: &ShRecurrence,
    c: &[f32],
    includes_cosine: bool,
    frame: &ShadingFrame,
    lights: &DirLights,
    chunks: &[u32],
    scratch: &mut Scratch,
) -> Vec3 {
    scratch.clear();
    gather_dir(s, frame, includes_cosine, lights, chunks, scratch);
    sh_sum(s, rec, c, scratch)
}

/// [`ShDataset::lookup_coeffs`] on lanes: the view coefficients at texture coordinates
/// `(u, v)` into `out` (`3 bands^2` long), the bilinear blend of four texel blocks eight
/// coefficients at a time (with FMA where the instruction set has it: within rounding of
/// the scalar blend).
#[inline(always)]
pub fn lookup_coeffs<S: Isa>(s: S, ds: &ShDataset, u: f32, v: f32, out: &mut [f32]) {
    let (nu, nv) = ds.grid();
    match ds.coeff_lookup {
        Lookup::Nearest => {
            let (i, j) = hemi_nearest_texel(u, v, nu, nv);
            out.copy_from_slice(ds.texel_rgb(i, j));
        }
        Lookup::Bilinear => {
            let [(i0, j0, w0), (i1, j1, w1), (i2, j2, w2), (i3, j3, w3)] =
                hemi_bilinear_texels(u, v, nu, nv);
            let (b0, b1, b2, b3) = (
                ds.texel_rgb(i0, j0),
                ds.texel_rgb(i1, j1),
                ds.texel_rgb(i2, j2),
                ds.texel_rgb(i3, j3),
            );
            let n = out.len();
            let full = n / LANES * LANES;
            let (sw0, sw1, sw2, sw3) = (s.splat(w0), s.splat(w1), s.splat(w2), s.splat(w3));
            for o in (0..full).step_by(LANES) {
                let acc = s.load(&b0[o..]) * sw0;
                let acc = s.load(&b1[o..]).mul_add(sw1, acc);
                let acc = s.load(&b2[o..]).mul_add(sw2, acc);
                s.load(&b3[o..]).mul_add(sw3, acc).store(&mut out[o..]);
            }
            for k in full..n {
                out[k] = b0[k] * w0 + b1[k] * w1 + b2[k] * w2 + b3[k] * w3;
            }
        }
    }
}

/// `N` pixels at once ([`Width::N`] of `s`: 16 on AVX-512, else 8), one per lane, each lit
/// by the same few lights (point lights only: a point-light scene would otherwise fill one
/// lane of eight). `ct` holds the pixels' coefficients transposed
/// (`ct[(colour bands^2 + k) N + lane]`); light `i` of lane `p` is at index `N i + p` of
/// `sc`'s arrays (local direction, weight; weight 0 where the light is below that pixel's
/// horizon or the lane is empty). Returns per-lane RGB sums, over the lights in order: a
/// pixel's result depends neither on its neighbours in the batch nor on the width.
#[inline(always)]
pub fn sh_sum_packed<S: Width>(
    s: S,
    rec: &ShRecurrence,
    ct: &[f32],
    lights: usize,
    sc: &Scratch,
) -> (S::V, S::V, S::V) {
    macro_rules! bands {
        ($($b:literal)*) => {
            match rec.bands {
                $($b => packed_groups(s, $b, rec, ct, lights, sc),)*
                b => packed_groups(s, b, rec, ct, lights, sc),
            }
        };
    }
    bands!(1 2 3 4 5 6 7 8 9 10)
}

#[inline(always)]
fn packed_groups<S: Width>(
    s: S,
    bands: usize,
    rec: &ShRecurrence,
    ct: &[f32],
    lights: usize,
    sc: &Scratch,
) -> (S::V, S::V, S::V) {
    let (mut tr, mut tg, mut tb) = (s.zero(), s.zero(), s.zero());
    for i in 0..lights {
        let o = i * S::N;
        let (fr, fg, fb) = sh_dot(
            s,
            bands,
            rec,
            ct,
            true,
            s.load(&sc.x[o..]),
            s.load(&sc.y[o..]),
            s.load(&sc.z[o..]),
        );
        tr = fr.fma(s.load(&sc.wr[o..]), tr);
        tg = fg.fma(s.load(&sc.wg[o..]), tg);
        tb = fb.fma(s.load(&sc.wb[o..]), tb);
    }
    (tr, tg, tb)
}

#[cfg(test)]
#[path = "sh_op_count.rs"]
mod op_count;
