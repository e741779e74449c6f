//! Test support: an independent restatement of OpenGL texture filtering (OpenGL 4.6 spec
//! 8.14.2) to check the lookups against, sample coordinates that hit centres, edges, the
//! azimuth seam and the polar clamp, and random data sets.
//!
//! Design rule: nothing here calls the texel arithmetic of [`crate::conventions`] under test
//! (brute force over all texels instead of floor/fract).

use super::ShDataset;
use crate::sh::basis::num_terms;
use rand::{Rng, SeedableRng};

/// Scalar GL reference written as a tent filter over *all* texels with periodic distance
/// in s and a clamped coordinate in t (OpenGL 4.6 spec 8.14.2 restated), independent of
/// the floor/fract arithmetic under test.
pub(super) fn gl_linear_ref(tab: &[f64], nu: usize, nv: usize, s: f64, t: f64) -> f64 {
    let u = s * nu as f64 - 0.5;
    let v = (t * nv as f64 - 0.5).clamp(0.0, (nv - 1) as f64);
    let mut acc = 0.0;
    for j in 0..nv {
        let wj = (1.0 - (v - j as f64).abs()).max(0.0);
        for i in 0..nu {
            let mut d = (u - i as f64).rem_euclid(nu as f64);
            if d > nu as f64 / 2.0 {
                d -= nu as f64;
            }
            let wi = (1.0 - d.abs()).max(0.0);
            acc += wi * wj * tab[j * nu + i];
        }
    }
    acc
}

/// GL_NEAREST reference: the texel whose centre is nearest, ties resolved to the texel
/// above the edge, periodic in s, clamped in t.
pub(super) fn gl_nearest_ref(tab: &[f64], nu: usize, nv: usize, s: f64, t: f64) -> f64 {
    let pick = |x: f64, n: usize, periodic: bool| -> usize {
        let mut best = 0;
        let mut bd = f64::INFINITY;
        for i in 0..n {
            let mut d = x * n as f64 - (i as f64 + 0.5);
            if periodic {
                d = (d + n as f64 / 2.0).rem_euclid(n as f64) - n as f64 / 2.0;
            }
            // ties: prefer d = -0.5 (texel above the edge) over d = +0.5
            let key = if (-0.5..0.5).contains(&d) {
                d.abs() - 1e-9
            } else {
                d.abs()
            };
            if key < bd {
                bd = key;
                best = i;
            }
        }
        best
    };
    let i = pick(s, nu, true);
    let j = if t < 0.0 {
        0
    } else {
        pick(t.min(1.0 - 1e-12), nv, false)
    };
    tab[j * nu + i]
}

pub(super) fn sample_coords() -> Vec<(f32, f32)> {
    let (nu, nv) = (8usize, 4usize);
    let mut v = vec![];
    // centres and edges (exact in f32 for power-of-two grids)
    for i in 0..=2 * nu {
        for j in 0..=2 * nv {
            v.push((i as f32 / (2 * nu) as f32, j as f32 / (2 * nv) as f32));
        }
    }
    // seam and clamp regions
    for &s in &[0.0f32, 1e-4, 0.01, 0.99, 0.9999, 1.0, -0.01, 1.01] {
        for &t in &[0.0f32, 0.01, 0.06, 0.5, 0.94, 0.99, 1.0] {
            v.push((s, t));
        }
    }
    let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
    for _ in 0..500 {
        v.push((rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0)));
    }
    v
}

pub(super) fn random_dataset(nu: usize, nv: usize, bands: usize, seed: u64) -> ShDataset {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let n = nu * nv * 3 * num_terms(bands);
    let c: Vec<f32> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    ShDataset::new(nu, nv, bands, false, "random test data", c).unwrap()
}

pub(super) fn texel(i: usize, n: usize) -> f32 {
    crate::conventions::texel_center(i, n)
}
