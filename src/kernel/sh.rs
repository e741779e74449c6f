//! The SH kernel: `sum_k E_k w_k sum_lm c_lm(view) Y_lm(l_k)` for one pixel (thesis Def. 10
//! and 12, Code 4), eight lights at a time.
//!
//! Per chunk of eight lights: their local directions (three dot products each), the horizon
//! mask and weights `E cos` (or `E` when the data set includes the cosine), then one fused
//! pass over (l, m) that runs the SH recurrence of [`crate::sh::basis`] on eight lanes and
//! immediately accumulates `c_lm * Y_lm` per colour, so the basis is never stored. The
//! recurrence constants are computed once per data set ([`ShRecurrence`]).

use super::lanes::{F32x8, LANES};
use super::DirLights;
use crate::conventions::ShadingFrame;
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
/// coefficients `c` (`[R.., G.., B..]`, each `bands^2` long).
#[inline(always)]
fn sh_dot(rec: &ShRecurrence, c: &[f32], x: F32x8, y: F32x8, z: F32x8) -> (F32x8, F32x8, F32x8) {
    let bands = rec.bands;
    let t = bands * bands;
    let (cr, cg, cb) = (&c[..t], &c[t..2 * t], &c[2 * t..3 * t]);
    let (mut ar, mut ag, mut ab) = (F32x8::default(), F32x8::default(), F32x8::default());
    let mut acc = |k: usize, yv: F32x8| {
        ar += yv * cr[k];
        ag += yv * cg[k];
        ab += yv * cb[k];
    };
    let sqrt2 = std::f64::consts::SQRT_2 as f32;
    let mut cm = F32x8::splat(1.0);
    let mut sm = F32x8::splat(0.0);
    for m in 0..bands {
        if m > 0 {
            let c = x * cm - y * sm;
            let s = x * sm + y * cm;
            cm = c;
            sm = s;
        }
        let qmm = F32x8::splat(rec.qmm[m]);
        let (fc, fs) = (cm * sqrt2, sm * sqrt2);
        let mut emit = |l: usize, q: F32x8| {
            let base = l * l + l;
            if m == 0 {
                acc(base, q);
            } else {
                acc(base + m, q * fc);
                acc(base - m, q * fs);
            }
        };
        emit(m, qmm);
        if m + 1 < bands {
            let mut q2 = qmm;
            let mut q1 = (z * rec.c1[m]) * qmm;
            emit(m + 1, q1);
            for l in (m + 2)..bands {
                let k = l * l + l + m;
                let q = (z * q1 - q2 * rec.b[k]) * rec.a[k];
                emit(l, q);
                q2 = q1;
                q1 = q;
            }
        }
    }
    (ar, ag, ab)
}

/// Per-pixel scratch space for [`shade_pixel`]: the lights above the pixel's horizon,
/// compacted (in light order) into local coordinates and weights.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    wr: Vec<f32>,
    wg: Vec<f32>,
    wb: Vec<f32>,
}

/// Reflected radiance of one pixel: view coefficients `c`, shading frame, the lights and
/// the chunk list to visit. `includes_cosine`: the data already holds `f cos`.
///
/// Two passes: the first computes every visited light's local direction and weight and
/// keeps, in light order, those above the horizon (weight > 0); the second runs the SH sum
/// over the kept lights eight at a time (the last group padded with zero weights). Lights
/// below the horizon thus cost three dot products, not a basis evaluation. The kept list,
/// and so the result, depends only on the pixel and the lights, never on which chunks a
/// tile's culling dropped (those lights are below the horizon and would not be kept).
#[multiversion::multiversion(targets("x86_64+avx2"))]
pub fn shade_pixel(
    rec: &ShRecurrence,
    c: &[f32],
    includes_cosine: bool,
    frame: &ShadingFrame,
    lights: &DirLights,
    chunks: &[u32],
    scratch: &mut Scratch,
) -> Vec3 {
    let (t, b, n) = (frame.t, frame.b, frame.n);
    let sc = scratch;
    for v in [
        &mut sc.x, &mut sc.y, &mut sc.z, &mut sc.wr, &mut sc.wg, &mut sc.wb,
    ] {
        v.clear();
    }
    for &ch in chunks {
        let o = ch as usize * LANES;
        let dx = F32x8::from_slice(&lights.dx[o..]);
        let dy = F32x8::from_slice(&lights.dy[o..]);
        let dz = F32x8::from_slice(&lights.dz[o..]);
        let z = dx * n.x + dy * n.y + dz * n.z;
        // Horizon: lanes at or below it weigh exactly zero and are not kept.
        let cosw = if includes_cosine {
            F32x8::splat(1.0)
        } else {
            z
        };
        let w = cosw.select_positive(z);
        if !w.any_nonzero() {
            continue;
        }
        let x = dx * t.x + dy * t.y + dz * t.z;
        let y = dx * b.x + dy * b.y + dz * b.z;
        let er = w * F32x8::from_slice(&lights.er[o..]);
        let eg = w * F32x8::from_slice(&lights.eg[o..]);
        let eb = w * F32x8::from_slice(&lights.eb[o..]);
        for i in 0..LANES {
            if er.0[i] != 0.0 || eg.0[i] != 0.0 || eb.0[i] != 0.0 {
                sc.x.push(x.0[i]);
                sc.y.push(y.0[i]);
                sc.z.push(z.0[i]);
                sc.wr.push(er.0[i]);
                sc.wg.push(eg.0[i]);
                sc.wb.push(eb.0[i]);
            }
        }
    }
    while sc.x.len() % LANES != 0 {
        for (v, fill) in [
            (&mut sc.x, 0.0),
            (&mut sc.y, 0.0),
            (&mut sc.z, 1.0),
            (&mut sc.wr, 0.0),
            (&mut sc.wg, 0.0),
            (&mut sc.wb, 0.0),
        ] {
            v.push(fill);
        }
    }
    let (mut tr, mut tg, mut tb) = (F32x8::default(), F32x8::default(), F32x8::default());
    for o in (0..sc.x.len()).step_by(LANES) {
        let (fr, fg, fb) = sh_dot(
            rec,
            c,
            F32x8::from_slice(&sc.x[o..]),
            F32x8::from_slice(&sc.y[o..]),
            F32x8::from_slice(&sc.z[o..]),
        );
        tr += fr * F32x8::from_slice(&sc.wr[o..]);
        tg += fg * F32x8::from_slice(&sc.wg[o..]);
        tb += fb * F32x8::from_slice(&sc.wb[o..]);
    }
    Vec3::new(tr.sum(), tg.sum(), tb.sum())
}
