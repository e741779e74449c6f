//! The bake's tabulated sums over one node's texels (`build`, module doc "The sum at one
//! sample"), arranged for the many samples of a node: each texel's direction is held by
//! its components along the node's frame `(r, t, b)` ([`FrameTexels`]), so a sample's
//! `l.n` and `l.v` are a few multiply-adds, and the pairs run in [`LANES`] independent
//! partial sums over structure-of-arrays, a chunk of [`LANES`] texels one vector of the f64
//! lanes of [`crate::lanes`] ([`frame_sum`]; never fused, so each lane has the bits of the
//! scalar expression: the scalar code is the tests' oracle, compared bit for bit on every
//! path). Quiet machine, `reflection_error -- 16 m=blinn-phong-200 kd=0.05 ks=0.9
//! set=reflection_order=6 set=reflection_grid=128 studio`, the bake before the lanes and
//! with them, alternately: 22.8, 13.3, 22.8, 13.3 s, the same printed row. The radial
//! table's lookup and the D-BRDF's per-pair factors on the lanes too
//! ([`super::lobe::RadialTable::at_lanes`], [`dbrdf_pair_lanes`]; same bits), on an Intel
//! host where the same bake took 21 s: 21.0, 16.7, 20.8, 15.9 s, alternately.
//!
//! # The pair in the node's frame
//! A sample of node `r` is `n = cos(polar_o) r + sin(polar_o) (cos psi t + sin psi b)` and
//! `v = 2 (n.r) n - r`, so with `c = cos(polar_o)`, `a = sin(polar_o) cos psi`,
//! `b = sin(polar_o) sin psi` and a texel's components `(l.r, l.t, l.b)`:
//! `z = l.n = c (l.r) + a (l.t) + b (l.b)`, `l.v = 2 c z - l.r`, `n.v = c`,
//! `|l + v|^2 = 2 + 2 l.v` and the half vector's `cos(polar_h) = (z + c) / |l + v|`. The
//! radial table's variable is `x = 1 - cos(polar_h)` ([`super::lobe`]), one square root and
//! one division per pair (two square roots and a division before, through `u = sqrt(x)`;
//! and the dot products `l.n`, `l.v` per pair in the probe frame).
//!
//! # Skipped chunks
//! The radial table is exactly zero from its cut `x_cut` on ([`super::lobe`], "Culling"),
//! that is where `cos(polar_h) <= 1 - x_cut`. Where the integrand has no Lambertian part (the
//! shipped bake), a chunk of [`LANES`] texels none of which is above the normal's horizon
//! with `(z + c)^2 >= (1 - x_cut)^2 (1 - 1e-9) |l + v|^2` (no square root, no division)
//! adds exact zeros and is skipped: the same bits. The node's list is culled for every
//! sample of the node at once (by `2 polar_h`, a circle about `r`); at a view `polar_o`
//! from the normal one sample's lobe is about an ellipse of that circle's radius in the
//! plane of incidence and `cos(polar_o)` of it across (the map from the half vector to
//! the texel scales a tangent across the plane by `2 v.h`), and the horizon cuts it, so
//! the grazing slices skip most chunks.
//!
//! # Order of the sums
//! Texel `k` of the list goes to partial sum `k mod LANES`; each partial sum runs over its
//! texels in list order and the four are added `(s0 + s1) + (s2 + s3)`. The list is padded
//! to a multiple of [`LANES`] with texels of zero power at `l = 0` (below every horizon).
//! Each node's sums run inside one task, so the bake's table is the same bits for any
//! thread count. A material's constant factors (its RGB scales, the Lambertian part) are
//! applied once to the sums of `g z P` and `z P`, not per pair.

// The lanes of a chunk are indexed by the lane number across several arrays, which reads as
// the per-lane arithmetic it is (and unrolls to it).
#![allow(clippy::needless_range_loop)]

use super::lobe::{LobeForm, RadialTable};
use crate::lanes::{Dispatch, F64x4, Isa, Kernel};
use glam::DVec3;

/// Independent partial sums per sample (module doc, "Order of the sums").
pub const LANES: usize = 4;

/// One node's texels in its frame `(r, t, b)`, structure of arrays, padded to a multiple of
/// [`LANES`] (module doc).
#[derive(Clone, Debug, Default)]
pub(super) struct FrameTexels {
    lr: Vec<f64>,
    lt: Vec<f64>,
    lb: Vec<f64>,
    power: [Vec<f64>; 3],
}

impl FrameTexels {
    /// Texels of directions `dir` (probe frame) and powers `power` in the orthonormal frame
    /// `(r, t, b)`.
    pub fn new(dir: &[DVec3], power: &[[f64; 3]], r: DVec3, t: DVec3, b: DVec3) -> Self {
        let n = dir.len().div_ceil(LANES) * LANES;
        let mut f = FrameTexels {
            lr: Vec::with_capacity(n),
            lt: Vec::with_capacity(n),
            lb: Vec::with_capacity(n),
            power: std::array::from_fn(|_| Vec::with_capacity(n)),
        };
        for (l, p) in dir.iter().zip(power) {
            f.lr.push(l.dot(r));
            f.lt.push(l.dot(t));
            f.lb.push(l.dot(b));
            for (fc, pc) in f.power.iter_mut().zip(p) {
                fc.push(*pc);
            }
        }
        for _ in dir.len()..n {
            f.lr.push(0.0);
            f.lt.push(0.0);
            f.lb.push(0.0);
            for fc in &mut f.power {
                fc.push(0.0);
            }
        }
        f
    }
}

/// Adds `LANES` partial sums in the module doc's order.
#[inline(always)]
#[cfg(test)]
fn total(s: [f64; LANES]) -> f64 {
    (s[0] + s[1]) + (s[2] + s[3])
}

/// Per lane of one chunk: the cosine weight `w` (`z`, or 1 where the material includes the
/// cosine; 0 below the normal's horizon) and the radial table's variable `x` (module doc).
#[inline(always)]
#[cfg(test)]
fn chunk_pairs(
    cosine: bool,
    (lr, lt, lb): (&[f64], &[f64], &[f64]),
    c: f64,
    a: f64,
    b: f64,
) -> ([f64; LANES], [f64; LANES], [f64; LANES]) {
    let (mut z, mut d) = ([0.0f64; LANES], [0.0f64; LANES]);
    for i in 0..LANES {
        z[i] = c * lr[i] + a * lt[i] + b * lb[i];
    }
    // |l + v|^2 = 2 + 2 l.v, l.v = 2 c z - l.r; no smaller than the least normal f64 (where
    // l = -v, z = -c < 0: the weight is 0 there).
    for i in 0..LANES {
        d[i] = (2.0 + 2.0 * (2.0 * c * z[i] - lr[i])).max(f64::MIN_POSITIVE);
    }
    let mut len = [0.0f64; LANES];
    for i in 0..LANES {
        len[i] = d[i].sqrt();
    }
    let mut x = [0.0f64; LANES];
    for i in 0..LANES {
        x[i] = (1.0 - (z[i] + c) / len[i]).max(0.0);
    }
    let mut w = [0.0f64; LANES];
    for i in 0..LANES {
        w[i] = match (z[i] > 0.0, cosine) {
            (false, _) => 0.0,
            (true, true) => 1.0,
            (true, false) => z[i],
        };
    }
    (w, x, len)
}

/// A D-BRDF pair's factors `(q, q F5)`: `q = p(h) w / (a + b - a b)` (the lobe's radial
/// table at `x`, `a = min(z, 1)`, `b = c`: the D-BRDF's denominator, thesis 2.3.6) and
/// `F5 = (1 - k.h)^5` with `k.h = |l + v| / 2`; zero where the weight `w` is (below the
/// horizon). Where `|l + v|` vanishes the lobe is left out (the Lambertian part stays).
/// Per lane, the same expression in `frame_sum_scalar` and [`frame_sum`].
#[inline(always)]
#[cfg(test)]
fn dbrdf_pair(table: &RadialTable, c: f64, z: f64, x: f64, len: f64, w: f64) -> (f64, f64) {
    let za = z.min(1.0);
    let denom = za + c - za * c;
    let kh = (0.5 * len).clamp(0.0, 1.0);
    let lobe = if len <= 1e-6 { 0.0 } else { table.at(x) };
    let q = if w == 0.0 { 0.0 } else { lobe / denom * w };
    (q, q * (1.0 - kh).powi(5))
}

/// [`dbrdf_pair`] on the f64 lanes of `s` for one chunk, operation for operation (the
/// `if`s as selects, `clamp` and `min` as the lanes' `max` and `min` on finite inputs,
/// `powi(5)` as the products `t (t^2)^2` LLVM expands it to): the same bits per lane.
#[inline(always)]
fn dbrdf_pair_lanes<S: Isa>(
    s: S,
    table: &RadialTable,
    c: f64,
    lanes: &ChunkLanes<S::D>,
) -> (S::D, S::D) {
    let (zero, one, c) = (s.splat_f64(0.0), s.splat_f64(1.0), s.splat_f64(c));
    let za = lanes.z.min(one);
    let denom = za + c - za * c;
    let kh = (s.splat_f64(0.5) * lanes.len).max(zero).min(one);
    let lobe = lanes
        .len
        .select_gt(s.splat_f64(1e-6), table.at_lanes(s, lanes.x), zero);
    let q = lanes.w.select_gt(zero, lobe / denom * lanes.w, zero);
    let t = one - kh;
    let t2 = t * t;
    (q, q * (t * (t2 * t2)))
}

/// Whether any lane of one chunk may have a non-zero lobe: above the normal's horizon and
/// `cos^2(polar_h) = (z + c)^2 / |l + v|^2` not below `hc2` ([`RadialTable`]'s
/// `zero_from_cos_squared`, less a relative margin of 1e-9 for rounding), tested without
/// a square root or a division. A chunk with none adds exact zeros to the lobe's sums and
/// is skipped (module doc, "Skipped chunks").
///
/// [`RadialTable`]: super::lobe::RadialTable
#[inline(always)]
#[cfg(test)]
fn any_in_lobe((lr, lt, lb): (&[f64], &[f64], &[f64]), c: f64, a: f64, b: f64, hc2: f64) -> bool {
    let mut any = false;
    for i in 0..LANES {
        let z = c * lr[i] + a * lt[i] + b * lb[i];
        let d = 2.0 + 2.0 * (2.0 * c * z - lr[i]);
        any |= z > 0.0 && (z + c) * (z + c) >= hc2 * d;
    }
    any
}

/// The sum of one sample `(c, a, b)` (module doc, "The pair in the node's frame") over the
/// node's texels for a tabulated lobe: `sum P f z` (`sum P f` where the material includes
/// the cosine); `None` for [`LobeForm::Exact`], which sums the texels per pair through the
/// material instead (`build::radiance_sum`). Per lane in plain arrays: the oracle (test
/// only) of [`frame_sum`], which computes the same operations on f64 lanes.
#[cfg(test)]
pub(super) fn frame_sum_scalar(
    form: &LobeForm,
    cosine: bool,
    f: &FrameTexels,
    c: f64,
    a: f64,
    b: f64,
) -> Option<DVec3> {
    let chunks =
        f.lr.chunks_exact(LANES)
            .zip(f.lt.chunks_exact(LANES))
            .zip(f.lb.chunks_exact(LANES))
            .zip(f.power[0].chunks_exact(LANES))
            .zip(f.power[1].chunks_exact(LANES))
            .zip(f.power[2].chunks_exact(LANES))
            .map(|(((((lr, lt), lb), p0), p1), p2)| ((lr, lt, lb), [p0, p1, p2]));
    Some(match form {
        LobeForm::BlinnPhong {
            lambert,
            scale,
            table,
        } => {
            // sum z P (the Lambertian part) and sum g z P (the lobe's).
            let (mut e, mut gs) = ([[0.0f64; LANES]; 3], [[0.0f64; LANES]; 3]);
            let with_lambert = *lambert != DVec3::ZERO;
            let hc2 = table.zero_from_cos_squared();
            for (dirs, p) in chunks {
                if !with_lambert && !any_in_lobe(dirs, c, a, b, hc2) {
                    continue;
                }
                let (w, x, _) = chunk_pairs(cosine, dirs, c, a, b);
                let mut g = [0.0f64; LANES];
                for i in 0..LANES {
                    g[i] = table.at(x[i]) * w[i];
                }
                for ch in 0..3 {
                    for i in 0..LANES {
                        gs[ch][i] += g[i] * p[ch][i];
                    }
                }
                if with_lambert {
                    for ch in 0..3 {
                        for i in 0..LANES {
                            e[ch][i] += w[i] * p[ch][i];
                        }
                    }
                }
            }
            let (l, s) = (lambert.to_array(), scale.to_array());
            DVec3::from_array(std::array::from_fn(|ch| {
                l[ch] * total(e[ch]) + s[ch] * total(gs[ch])
            }))
        }
        LobeForm::Dbrdf {
            lambert,
            c: cd,
            rs,
            table,
        } => {
            // sum z P, sum q z P and sum q F5 z P, q = p(h) / (a + b - a b), F5 = (1 - k.h)^5.
            let mut e = [[0.0f64; LANES]; 3];
            let (mut qs, mut fs) = ([[0.0f64; LANES]; 3], [[0.0f64; LANES]; 3]);
            let with_lambert = *lambert != DVec3::ZERO;
            let hc2 = table.zero_from_cos_squared();
            for ((lr, lt, lb), p) in chunks {
                if !with_lambert && !any_in_lobe((lr, lt, lb), c, a, b, hc2) {
                    continue;
                }
                let (w, x, len) = chunk_pairs(cosine, (lr, lt, lb), c, a, b);
                let (mut q, mut q5) = ([0.0f64; LANES], [0.0f64; LANES]);
                for i in 0..LANES {
                    let z = c * lr[i] + a * lt[i] + b * lb[i];
                    (q[i], q5[i]) = dbrdf_pair(table, c, z, x[i], len[i], w[i]);
                }
                for ch in 0..3 {
                    for i in 0..LANES {
                        qs[ch][i] += q[i] * p[ch][i];
                        fs[ch][i] += q5[i] * p[ch][i];
                    }
                }
                if with_lambert {
                    for ch in 0..3 {
                        for i in 0..LANES {
                            e[ch][i] += w[i] * p[ch][i];
                        }
                    }
                }
            }
            let (l, r) = (lambert.to_array(), rs.to_array());
            DVec3::from_array(std::array::from_fn(|ch| {
                l[ch] * total(e[ch])
                    + cd * r[ch] * total(qs[ch])
                    + cd * (1.0 - r[ch]) * total(fs[ch])
            }))
        }
        LobeForm::Exact => return None,
    })
}

/// `frame_sum_scalar` on the f64 lanes of `dispatch` ([`crate::lanes::F64x4`]: each
/// operation the IEEE one, never fused): a chunk of [`LANES`] texels is one vector, so every
/// lane computes the scalar expression of its texel and the partial sums are the same
/// (texel `k` in lane `k mod LANES`, added `(s0 + s1) + (s2 + s3)`): the same bits as
/// `frame_sum_scalar` on every path, the radial table's lookups and the D-BRDF's per-pair
/// factors included ([`super::lobe::RadialTable::at_lanes`], [`dbrdf_pair_lanes`]).
pub(super) fn frame_sum(
    dispatch: Dispatch,
    form: &LobeForm,
    cosine: bool,
    f: &FrameTexels,
    c: f64,
    a: f64,
    b: f64,
) -> Option<DVec3> {
    dispatch.run(FrameSum {
        form,
        cosine,
        f,
        c,
        a,
        b,
    })
}

/// [`frame_sum`]'s work as a lane kernel.
struct FrameSum<'a> {
    form: &'a LobeForm,
    cosine: bool,
    f: &'a FrameTexels,
    c: f64,
    a: f64,
    b: f64,
}

/// One chunk's lanes: the cosine weight `w`, the table variable `x`, `|l + v|` and `z`
/// (`chunk_pairs`'s, operation for operation), and whether any lane may be inside the
/// lobe (`any_in_lobe`'s test on the same `z` and `|l + v|^2`).
struct ChunkLanes<D> {
    w: D,
    x: D,
    len: D,
    z: D,
    in_lobe: bool,
}

impl FrameSum<'_> {
    #[inline(always)]
    fn chunk<S: Isa>(&self, s: S, k: usize, hc2: f64) -> ChunkLanes<S::D> {
        let f = self.f;
        let (lr, lt, lb) = (
            s.load_f64(&f.lr[k..]),
            s.load_f64(&f.lt[k..]),
            s.load_f64(&f.lb[k..]),
        );
        let (c, a, b) = (
            s.splat_f64(self.c),
            s.splat_f64(self.a),
            s.splat_f64(self.b),
        );
        let (zero, one, two) = (s.splat_f64(0.0), s.splat_f64(1.0), s.splat_f64(2.0));
        let z = c * lr + a * lt + b * lb;
        // `2 + 2 (2 c z - l.r)`, as `chunk_pairs` and `any_in_lobe` write it.
        let d = two + two * (two * c * z - lr);
        let zc = z + c;
        // `z > 0 && (z + c)^2 >= hc2 d` per lane; inputs are finite, so `>=` is `!(<)`.
        let above = z.gt_mask(zero);
        let outside = (s.splat_f64(hc2) * d).gt_mask(zc * zc);
        let in_lobe = (above & !outside & 0b1111) != 0;
        let d = d.max(s.splat_f64(f64::MIN_POSITIVE));
        let len = d.sqrt();
        let x = (one - zc / len).max(zero);
        let w = z.select_gt(zero, if self.cosine { one } else { z }, zero);
        ChunkLanes {
            w,
            x,
            len,
            z,
            in_lobe,
        }
    }
}

impl Kernel for FrameSum<'_> {
    type Out = Option<DVec3>;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> Option<DVec3> {
        let f = self.f;
        let n = f.lr.len();
        let zero = s.splat_f64(0.0);
        let power = |ch: usize, k: usize| s.load_f64(&f.power[ch][k..]);
        Some(match self.form {
            LobeForm::BlinnPhong {
                lambert,
                scale,
                table,
            } => {
                let (mut e, mut gs) = ([zero; 3], [zero; 3]);
                let with_lambert = *lambert != DVec3::ZERO;
                let hc2 = table.zero_from_cos_squared();
                for k in (0..n).step_by(LANES) {
                    let ch_lanes = self.chunk(s, k, hc2);
                    if !with_lambert && !ch_lanes.in_lobe {
                        continue;
                    }
                    let g = table.at_lanes(s, ch_lanes.x) * ch_lanes.w;
                    for (ch, acc) in gs.iter_mut().enumerate() {
                        *acc = *acc + g * power(ch, k);
                    }
                    if with_lambert {
                        for (ch, acc) in e.iter_mut().enumerate() {
                            *acc = *acc + ch_lanes.w * power(ch, k);
                        }
                    }
                }
                let (l, sc) = (lambert.to_array(), scale.to_array());
                DVec3::from_array(std::array::from_fn(|ch| {
                    l[ch] * e[ch].sum() + sc[ch] * gs[ch].sum()
                }))
            }
            LobeForm::Dbrdf {
                lambert,
                c: cd,
                rs,
                table,
            } => {
                let mut e = [zero; 3];
                let (mut qs, mut fs) = ([zero; 3], [zero; 3]);
                let with_lambert = *lambert != DVec3::ZERO;
                let hc2 = table.zero_from_cos_squared();
                for k in (0..n).step_by(LANES) {
                    let ch_lanes = self.chunk(s, k, hc2);
                    if !with_lambert && !ch_lanes.in_lobe {
                        continue;
                    }
                    let (q, q5) = dbrdf_pair_lanes(s, table, self.c, &ch_lanes);
                    for ch in 0..3 {
                        let p = power(ch, k);
                        qs[ch] = qs[ch] + q * p;
                        fs[ch] = fs[ch] + q5 * p;
                    }
                    if with_lambert {
                        for (ch, acc) in e.iter_mut().enumerate() {
                            *acc = *acc + ch_lanes.w * power(ch, k);
                        }
                    }
                }
                let (l, r) = (lambert.to_array(), rs.to_array());
                DVec3::from_array(std::array::from_fn(|ch| {
                    l[ch] * e[ch].sum()
                        + cd * r[ch] * qs[ch].sum()
                        + cd * (1.0 - r[ch]) * fs[ch].sum()
                }))
            }
            LobeForm::Exact => return None,
        })
    }
}
