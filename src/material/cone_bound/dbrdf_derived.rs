//! The D-BRDF bound's second half: the largest `p(h)` of the derived octahedral table
//! itself (its `GL_LINEAR` lookup, [`crate::brdf::dbrdf`]) over a cone of half vectors.
//! The octahedral map is `sqrt 6`-Lipschitz from angle to `(u, v)`, so a cone of half angle
//! `beta` lies in the box `(u, v) +- sqrt(6) beta` around its axis's coordinates. Tight for
//! small cones; for wide ones the file table's bound over the widened cone
//! (`dbrdf.rs`) is tighter, and [`super::dbrdf::DbrdfBound`] takes the smaller.

use super::{Cone, ConeAngles};
use crate::brdf::DBrdf;
use crate::conventions::{hemi_oct_encode, hemi_oct_texel_coord};

/// The derived octahedral table and a pyramid of its block maxima.
#[derive(Clone, Debug)]
pub struct DerivedTableBound {
    /// Side of the octahedral table (a power of two).
    n: usize,
    /// `levels[k][J (n >> k) + I]`: the largest texel of the aligned `2^k x 2^k` block
    /// `(I, J)`; level 0 is the table. Any texel range is covered by at most 2 x 2 blocks of
    /// the first level whose blocks are at least as long as the range.
    levels: Vec<Vec<f32>>,
    max: f32,
}

/// Largest box (texels per side) whose exact bilinear maximum [`super::box_max::box_max`]
/// computes; a larger one takes the largest texel of its footprint.
const BOX_TEXELS: f32 = 3.0;

/// Lipschitz constant of the octahedral map from the sphere (angle) to `(u, v)` (parent
/// module doc): `sqrt 6`.
const OCT_LIPSCHITZ: f32 = 2.449_49;

impl DerivedTableBound {
    /// Precomputes the block maxima of `d`'s derived table.
    pub fn new(d: &DBrdf) -> DerivedTableBound {
        let n = d.octahedral_grid();
        let mut levels = vec![d.octahedral_table().to_vec()];
        let mut side = n;
        while side > 1 {
            let prev = levels.last().expect("level 0");
            let half = side / 2;
            let next: Vec<f32> = (0..half * half)
                .map(|k| {
                    let (j, i) = (k / half, k % half);
                    let at = |a: usize, b: usize| prev[(2 * j + b) * side + 2 * i + a];
                    at(0, 0).max(at(1, 0)).max(at(0, 1)).max(at(1, 1))
                })
                .collect();
            levels.push(next);
            side = half;
        }
        let max = levels.last().expect("top")[0];
        DerivedTableBound { n, levels, max }
    }

    /// The largest `p(h)` over the half vectors in `h` (`None`: every half vector), parent
    /// module doc: the octahedral box `(u, v) +- sqrt(6) beta` around the axis's
    /// coordinates, its exact bilinear maximum when small, else its footprint's largest
    /// texel.
    pub fn p_max(&self, h: Option<&Cone>) -> f32 {
        let Some(h) = h else { return self.max };
        if h.axis.z <= 0.0 {
            return self.max;
        }
        let beta = ConeAngles::of(h).beta;
        let r = OCT_LIPSCHITZ * beta * (1.0 + 1e-5) + 1e-5;
        if r >= 2.0 {
            return self.max;
        }
        let (u, v) = hemi_oct_encode(h.axis);
        let c = |x: f32| hemi_oct_texel_coord(x, self.n);
        let (u0, u1, v0, v1) = (c(u - r), c(u + r), c(v - r), c(v + r));
        if u1 - u0 <= BOX_TEXELS && v1 - v0 <= BOX_TEXELS {
            return (super::box_max::box_max(u0, u1, v0, v1, |u, v| self.bilinear(u, v))
                * (1.0 + 1e-6))
                .min(self.max);
        }
        let last = self.n - 1;
        let lo = |x: f32| (x.floor() as usize).min(last);
        let hi = |x: f32| (x.ceil() as usize).min(last);
        self.range_max(lo(u0), hi(u1), lo(v0), hi(v1))
    }

    /// The largest texel of columns `i0..=i1`, rows `j0..=j1`: at most four blocks of the
    /// pyramid.
    pub(super) fn range_max(&self, i0: usize, i1: usize, j0: usize, j1: usize) -> f32 {
        let len = (i1 - i0 + 1).max(j1 - j0 + 1);
        let k = len.next_power_of_two().trailing_zeros() as usize;
        let k = k.min(self.levels.len() - 1);
        let side = self.n >> k;
        let level = &self.levels[k];
        let mut best = 0.0f32;
        for bj in (j0 >> k)..=(j1 >> k) {
            for bi in (i0 >> k)..=(i1 >> k) {
                best = best.max(level[bj * side + bi]);
            }
        }
        best
    }

    /// The bilinear `p` at clamped texel coordinates `(u, v)` in `[0, n - 1]^2`
    /// ([`crate::conventions::hemi_oct_bilinear_texels`]'s arithmetic).
    #[inline]
    fn bilinear(&self, u: f32, v: f32) -> f32 {
        let t = crate::conventions::hemi_oct_bilinear_texels(u, v, self.n);
        let p = |k: usize| self.levels[0][t[k].1 * self.n + t[k].0];
        (t[0].2 * p(0) + t[1].2 * p(1)) + (t[2].2 * p(2) + t[3].2 * p(3))
    }
}
