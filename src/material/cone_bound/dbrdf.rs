//! The D-BRDF's share of the cone bounds: the largest `p(h)` of its half-vector table over
//! a cone of half vectors, and its `f cos` bound (derivation in the parent module doc,
//! "D-BRDF").
//!
//! The renderer evaluates `p` from a table derived from the file's (the octahedral lookup
//! of [`crate::brdf::dbrdf`], "The lookup the renderer evaluates"): each derived texel is
//! the file's `GL_LINEAR` lookup at the texel's centre times the derived table's scale
//! `k`, and the derived lookup at `h` blends the four texels around `h`, whose centres lie
//! within [`DbrdfBound::widening`] radians of `h` (one and a half texels of the `n x n`
//! map, times the inverse map's largest stretch, `sqrt(9/2)` rad per unit of `(u, v)`).
//! So the bound below is the file table's bound over the cone widened by that angle, times
//! `max(k, 1)`: an upper bound of the derived lookup, as tight as the file table's up to
//! that widening (2 degrees for the 256 x 256 table of a 64 x 32 file). For small cones
//! the derived table's own bound (`dbrdf_derived.rs`) is tighter; the smaller is taken.

use super::box_max::box_max;
use super::dbrdf_derived::DerivedTableBound;
use super::{schlick_max, Cone, ConeAngles};
use crate::brdf::DBrdf;
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, TAU};

/// What a D-BRDF's bound needs: its table, the per-row maxima and the largest value.
#[derive(Clone, Debug)]
pub struct DbrdfBound {
    nu: usize,
    nv: usize,
    p: Vec<f32>,
    row_max: Vec<f32>,
    /// `runs[k][j nu + i]`: the largest of row `j`'s texels `i .. i + 2^k` (azimuth
    /// wrapped), for `2^k <= nu`: any run of a row in two reads (a sparse table).
    runs: Vec<Vec<f32>>,
    max: f32,
    c: f32,
    rs: Vec3,
    /// Radians the cone of half vectors is widened by (module doc).
    widening: f32,
    /// `max(k, 1)` of the derived table's scale `k`, rounded up.
    scale: f32,
    /// The derived table's own bound (`dbrdf_derived.rs`), tighter for small cones.
    derived: DerivedTableBound,
}

/// Largest box (texels per side) whose exact bilinear maximum [`box_max`]
/// computes; a larger one takes the largest texel of its footprint.
const BOX_TEXELS: f32 = 3.0;

impl DbrdfBound {
    /// Precomputes the per-row maxima of `d`'s table.
    pub fn new(d: &DBrdf) -> DbrdfBound {
        let (nu, nv) = d.grid();
        let p = d.table().to_vec();
        let row_max: Vec<f32> = p
            .chunks(nu)
            .map(|r| r.iter().copied().fold(0.0f32, f32::max))
            .collect();
        let max = row_max.iter().copied().fold(0.0f32, f32::max);
        let mut runs = vec![p.clone()];
        while 2usize << (runs.len() - 1) <= nu {
            let half = 1usize << (runs.len() - 1);
            let prev = runs.last().expect("level 0");
            let next: Vec<f32> = (0..nu * nv)
                .map(|k| {
                    let (j, i) = (k / nu, k % nu);
                    prev[k].max(prev[j * nu + (i + half) % nu])
                })
                .collect();
            runs.push(next);
        }
        DbrdfBound {
            nu,
            nv,
            p,
            row_max,
            runs,
            max,
            c: d.c,
            rs: d.rs,
            widening: DbrdfBound::widening(d.octahedral_grid()),
            scale: (d.octahedral_scale().max(1.0) * (1.0 + 1e-6)) as f32,
            derived: DerivedTableBound::new(d),
        }
    }

    /// The largest angle between a half vector and the centres of the derived texels its
    /// lookup blends, for an `n x n` derived table (module doc): 1.5 texels of `2/n` in
    /// `(u, v)` along each axis, so `1.5 sqrt 2 (2/n)`, times `sqrt(9/2)` rad per unit:
    /// `9/n` rad.
    pub fn widening(n: usize) -> f32 {
        9.0 / n as f32
    }

    /// The largest `p(h)` over the half vectors in `h` (`None`: every half vector), module
    /// doc: the file table's over the widened cone, times `max(k, 1)`, or the derived
    /// table's own bound (`dbrdf_derived.rs`) where that is smaller (small cones).
    pub fn p_max(&self, h: Option<&Cone>) -> f32 {
        let Some(h) = h else {
            return self.max * self.scale;
        };
        let wide = Cone::new(h.axis, h.sin.atan2(h.cos) + self.widening);
        (self.file_p_max(&wide) * self.scale).min(self.derived.p_max(Some(h)))
    }

    /// The largest file-table `p(h)` over the half vectors in `h`.
    fn file_p_max(&self, h: &Cone) -> f32 {
        let ConeAngles {
            theta,
            phi,
            beta,
            azimuth_half_width,
        } = ConeAngles::of(h);
        let lo = (theta - beta).clamp(0.0, FRAC_PI_2);
        let hi = (theta + beta).clamp(0.0, FRAC_PI_2);
        // Rows whose bilinear footprint meets [lo, hi]: v = t nv - 1/2, rows floor(v) and
        // floor(v) + 1, clamped.
        let row = |a: f32| (a / FRAC_PI_2) * self.nv as f32 - 0.5;
        let j0 = (row(lo).floor() as i64).clamp(0, self.nv as i64 - 1) as usize;
        let j1 = (row(hi).floor() as i64 + 1).clamp(0, self.nv as i64 - 1) as usize;
        let Some(delta) = azimuth_half_width else {
            return self.row_max[j0..=j1].iter().copied().fold(0.0f32, f32::max);
        };
        let col = |a: f32| (a / TAU) * self.nu as f32 - 0.5;
        let (u0, u1) = (col(phi - delta), col(phi + delta));
        let (v0, v1) = (row(lo), row(hi));
        if u1 - u0 <= BOX_TEXELS && v1 - v0 <= BOX_TEXELS {
            return box_max(u0, u1, v0, v1, |u, v| self.bilinear(u, v)) * (1.0 + 1e-6);
        }
        let i0 = u0.floor() as i64;
        let i1 = u1.floor() as i64 + 1;
        let len = (i1 - i0 + 1) as usize;
        if len >= self.nu {
            return self.row_max[j0..=j1].iter().copied().fold(0.0f32, f32::max);
        }
        (j0..=j1)
            .map(|j| self.run_max(j, i0, len))
            .fold(0.0f32, f32::max)
    }

    /// The largest of row `j`'s texels `start .. start + len` (wrapped; `1 <= len <= nu`):
    /// two overlapping runs of `2^k` texels from the sparse table.
    #[inline]
    pub(super) fn run_max(&self, j: usize, start: i64, len: usize) -> f32 {
        let k = (usize::BITS - 1 - len.leading_zeros()) as usize;
        let a = start.rem_euclid(self.nu as i64) as usize;
        let b = (a + len - (1 << k)) % self.nu;
        let runs = &self.runs[k];
        runs[j * self.nu + a].max(runs[j * self.nu + b])
    }

    /// The bilinear `p` at continuous texel coordinates `(u, v)` (`u = s nu - 1/2`,
    /// `v = t nv - 1/2`: [`crate::conventions::hemi_bilinear_texels`]'s arithmetic, azimuth
    /// wrapped, rows clamped).
    #[inline]
    fn bilinear(&self, u: f32, v: f32) -> f32 {
        let (uf, vf) = (u.floor(), v.floor());
        let (a, b) = (u - uf, v - vf);
        let i0 = (uf as i64).rem_euclid(self.nu as i64) as usize;
        let i1 = (i0 + 1) % self.nu;
        let j0 = (vf as i64).clamp(0, self.nv as i64 - 1) as usize;
        let j1 = (vf as i64 + 1).clamp(0, self.nv as i64 - 1) as usize;
        let p = |i: usize, j: usize| self.p[j * self.nu + i];
        (1.0 - a) * (1.0 - b) * p(i0, j0)
            + a * (1.0 - b) * p(i1, j0)
            + (1.0 - a) * b * p(i0, j1)
            + a * b * p(i1, j1)
    }

    /// The bound of the D-BRDF's `f cos` (module doc) given `c_i`, `wo` and the half vectors.
    #[inline]
    pub(super) fn f_cos_max(&self, ci: f32, wo: Vec3, h: Option<&Cone>, kh_min: f32) -> Vec3 {
        let b = wo.z.min(1.0);
        let ratio = ci / (ci + b - ci * b);
        self.c * self.p_max(h) * ratio * schlick_max(self.rs, kh_min)
    }
}
