//! Lane models: analytic BRDFs and the D-BRDF evaluated for eight lights at once (one light
//! per lane), over the lights [`super::gather::gather_dir`] left in a [`Scratch`] (local
//! directions, weights `E cos(polar)`). Each is the same formula as the model's scalar
//! `Brdf::eval` (thesis 2.2 and 2.3.6), tested against the scalar oracle at
//! [`super::KERNEL_TOLERANCE`]. Models without a lane form go through `Brdf::eval` per light
//! ([`LaneModel::Scalar`]).
//!
//! Design rule: the lane form is chosen by matching on the closed set of
//! [`Material`] variants ([`LaneModel::of`]); the BRDF models themselves know nothing of
//! the kernel.

use super::gather::Scratch;
use crate::brdf::{Brdf, DBrdf};
use crate::lanes::{F32x8, Isa, LANES};
use crate::material::Material;
use glam::Vec3;
use std::f32::consts::PI;

/// How the kernel evaluates a frame's material for the lights of one pixel. Built once per
/// frame ([`LaneModel::of`]).
#[derive(Clone, Copy)]
pub enum LaneModel<'a> {
    /// `f = albedo / pi` (thesis 2.2.1).
    Lambert { albedo: Vec3 },
    /// `f = kd/pi + ks (a+8)/(8 pi) (n.h)^a` ([`crate::brdf::BlinnPhong`]).
    BlinnPhong { kd: Vec3, ks: Vec3, exponent: f32 },
    /// The D-BRDF ([`crate::brdf::dbrdf`]).
    DBrdf(&'a DBrdf),
    /// Any other model: `Brdf::eval` per light.
    Scalar(&'a dyn Brdf),
}

impl<'a> LaneModel<'a> {
    /// The lane form of `material`: Lambert, Blinn-Phong and the D-BRDF have one; every
    /// other variant evaluates `Brdf::eval` per light ([`LaneModel::Scalar`]; an SH data
    /// set is shaded by the SH kernel instead, [`super::sh`]).
    pub fn of(material: &'a Material) -> LaneModel<'a> {
        match material {
            Material::Lambert(m) => LaneModel::Lambert { albedo: m.albedo },
            Material::BlinnPhong(m) => LaneModel::BlinnPhong {
                kd: m.kd,
                ks: m.ks,
                exponent: m.exponent,
            },
            Material::DBrdf(m) => LaneModel::DBrdf(m),
            Material::Phong(_)
            | Material::AshikhminShirley(_)
            | Material::LambertDbrdf(_)
            | Material::Merl(_)
            | Material::Rgl(_)
            | Material::Sh(_) => LaneModel::Scalar(material.as_brdf()),
        }
    }

    /// Lanes [`LaneModel::sum`] occupies for `n` gathered lights: whole groups of
    /// [`LANES`] (the last one padded), or one per light where it evaluates in scalar (the
    /// one-light cases, the scalar model). For the work counters only.
    pub fn lane_slots(&self, n: usize) -> usize {
        match *self {
            LaneModel::Scalar(_) => n,
            LaneModel::Lambert { .. } | LaneModel::BlinnPhong { .. } if n == 1 => 1,
            LaneModel::Lambert { .. } | LaneModel::BlinnPhong { .. } | LaneModel::DBrdf(_) => {
                super::gather::padded(n)
            }
        }
    }

    /// `sum_k f(l_k, wo) w_k` (RGB) over the lights of `sc` (weights `w_k = E_k cos`, or
    /// `E_k` if the scalar model includes the cosine), `wo` the unit local view direction.
    /// Pads `sc`.
    #[inline(always)]
    pub fn sum<S: Isa>(&self, s: S, wo: Vec3, sc: &mut Scratch) -> Vec3 {
        if sc.n == 0 {
            return Vec3::ZERO;
        }
        match *self {
            LaneModel::Scalar(brdf) => {
                let mut sum = Vec3::ZERO;
                for i in 0..sc.n {
                    let wi = Vec3::new(sc.x[i], sc.y[i], sc.z[i]);
                    sum += brdf.eval(wi, wo) * Vec3::new(sc.wr[i], sc.wg[i], sc.wb[i]);
                }
                sum
            }
            // One light (a key light, a point light): a group would be seven lanes of
            // padding and six lane sums; the scalar formula is cheaper. Chosen by the
            // pixel's own light count, so still independent of tiles and threads.
            LaneModel::Lambert { albedo } if sc.n == 1 => {
                Vec3::new(sc.wr[0], sc.wg[0], sc.wb[0]) * (albedo / PI)
            }
            LaneModel::BlinnPhong { kd, ks, exponent } if sc.n == 1 => {
                let h = Vec3::new(sc.x[0], sc.y[0], sc.z[0]) + wo;
                let nh = (h.z / h.length()).max(0.0);
                let spec = (exponent + 8.0) / (8.0 * PI) * nh.powf(exponent);
                (kd / PI + ks * spec) * Vec3::new(sc.wr[0], sc.wg[0], sc.wb[0])
            }
            LaneModel::Lambert { albedo } => {
                let end = sc.pad();
                let (mut r, mut g, mut b) = (s.zero(), s.zero(), s.zero());
                for o in (0..end).step_by(LANES) {
                    r += s.load(&sc.wr[o..]);
                    g += s.load(&sc.wg[o..]);
                    b += s.load(&sc.wb[o..]);
                }
                Vec3::new(r.sum(), g.sum(), b.sum()) * (albedo / PI)
            }
            LaneModel::BlinnPhong { kd, ks, exponent } => {
                let end = sc.pad();
                let norm = (exponent + 8.0) / (8.0 * PI);
                let (wox, woy, woz) = (s.splat(wo.x), s.splat(wo.y), s.splat(wo.z));
                let (mut dr, mut dg, mut db) = (s.zero(), s.zero(), s.zero());
                let (mut sr, mut sg, mut sb) = (s.zero(), s.zero(), s.zero());
                for o in (0..end).step_by(LANES) {
                    let hx = s.load(&sc.x[o..]) + wox;
                    let hy = s.load(&sc.y[o..]) + woy;
                    let hz = s.load(&sc.z[o..]) + woz;
                    let len = hz.mul_add(hz, hy.mul_add(hy, hx * hx)).sqrt();
                    let nh = hz.div(len).positive_part();
                    // powf per lane: the exact scalar function, no approximation.
                    let mut p = [0.0f32; LANES];
                    nh.store(&mut p);
                    // Padding lanes (weight 0) are not evaluated.
                    let live = (sc.n - o).min(LANES);
                    for v in &mut p[..live] {
                        *v = v.powf(exponent);
                    }
                    p[live..].fill(0.0);
                    let p = s.load(&p);
                    let (wr, wg, wb) = (
                        s.load(&sc.wr[o..]),
                        s.load(&sc.wg[o..]),
                        s.load(&sc.wb[o..]),
                    );
                    dr += wr;
                    dg += wg;
                    db += wb;
                    sr = p.mul_add(wr, sr);
                    sg = p.mul_add(wg, sg);
                    sb = p.mul_add(wb, sb);
                }
                let d = Vec3::new(dr.sum(), dg.sum(), db.sum());
                let sp = Vec3::new(sr.sum(), sg.sum(), sb.sum());
                d * (kd / PI) + sp * (ks * norm)
            }
            LaneModel::DBrdf(m) => dbrdf_sum(s, m, wo, sc),
        }
    }
}

/// The D-BRDF `c p(h) F(k.h) / (a + b - a b)` over the lights of `sc`, eight at a time.
#[inline(always)]
fn dbrdf_sum<S: Isa>(s: S, m: &DBrdf, wo: Vec3, sc: &mut Scratch) -> Vec3 {
    if wo.z <= 0.0 {
        return Vec3::ZERO;
    }
    let end = sc.pad();
    let (wox, woy, woz) = (s.splat(wo.x), s.splat(wo.y), s.splat(wo.z));
    let b = s.splat(wo.z.min(1.0));
    let one = s.splat(1.0);
    let (mut ar, mut ag, mut ab) = (s.zero(), s.zero(), s.zero());
    let (mut fr, mut fg, mut fb) = (s.zero(), s.zero(), s.zero());
    for o in (0..end).step_by(LANES) {
        let z = s.load(&sc.z[o..]);
        let sx = s.load(&sc.x[o..]) + wox;
        let sy = s.load(&sc.y[o..]) + woy;
        let sz = z + woz;
        let len = sz.mul_add(sz, sy.mul_add(sy, sx * sx)).sqrt();
        let p = half_vector_p(s, m, sx, sy, sz);
        let a = z.min(one);
        let denom = a + b - a * b;
        let kh = (s.splat(0.5) * len).min(one).max(s.zero());
        let t = one - kh;
        let t2 = t * t;
        let t5 = t2 * t2 * t;
        // c p / D, shared by the colours; Fresnel R_s + (1 - R_s) t^5 per colour.
        let g = (s.splat(m.c) * p).div(denom);
        let (wr, wg, wb) = (
            s.load(&sc.wr[o..]),
            s.load(&sc.wg[o..]),
            s.load(&sc.wb[o..]),
        );
        let (gr, gg, gb) = (g * wr, g * wg, g * wb);
        ar += gr;
        ag += gg;
        ab += gb;
        fr = gr.mul_add(t5, fr);
        fg = gg.mul_add(t5, fg);
        fb = gb.mul_add(t5, fb);
    }
    let rs = m.rs;
    let a = Vec3::new(ar.sum(), ag.sum(), ab.sum());
    let f = Vec3::new(fr.sum(), fg.sum(), fb.sum());
    rs * a + (Vec3::ONE - rs) * f
}

/// `p(h)` per lane ([`DBrdf::p`]) from the unnormalised half vector `(x, y, z) = wi + wo`
/// (`z > 0`): its octahedral coordinates `(x + y, x - y) / (|x| + |y| + z)` by one
/// division, texel coordinates clamped to the edge centres, and the derived table's
/// `GL_LINEAR` blend with four gathers: the texel arithmetic of
/// [`crate::conventions::hemi_oct_texel_coord`] and
/// [`crate::conventions::hemi_oct_bilinear_texels`], operation for operation, so the lanes
/// give the oracle's bits. No trigonometry.
#[inline(always)]
fn half_vector_p<S: Isa>(s: S, m: &DBrdf, x: S::V, y: S::V, z: S::V) -> S::V {
    let n = m.octahedral_grid();
    let table = m.octahedral_table();
    let nf = n as f32;
    let zero = s.zero();
    let one = s.splat(1.0);
    let r = one.div(x.abs() + y.abs() + z.max(zero));
    let (u, v) = ((x + y) * r, (x - y) * r);
    let (scale, offset) = (s.splat(0.5 * nf), s.splat(0.5 * (nf - 1.0)));
    let last = s.splat(nf - 1.0);
    let cu = (u * scale + offset).max(zero).min(last);
    let cv = (v * scale + offset).max(zero).min(last);
    let last0 = s.splat(nf - 2.0);
    let (fu, fv) = (cu.floor().min(last0), cv.floor().min(last0));
    let (a, b) = (cu - fu, cv - fv);
    let nv = s.splat(nf);
    let base = fv.mul_add(nv, fu);
    let p00 = base.gather(table);
    let p10 = (base + one).gather(table);
    let p01 = (base + nv).gather(table);
    let p11 = (base + nv + one).gather(table);
    let (ia, ib) = (one - a, one - b);
    ((ia * ib) * p00 + (a * ib) * p10) + ((ia * b) * p01 + (a * b) * p11)
}
