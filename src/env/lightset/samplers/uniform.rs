//! The uniform sampler ([`uniform()`], thesis 3.2.2 "unweighted sampling") and its sphere
//! map with inverse and pdf ([`uniform_direction`], [`uniform_inverse`], [`uniform_pdf`]).
//!
//! Design rule: the directions are uniform random, the powers are not Monte Carlo
//! estimates: each light carries its Voronoi cell ([`super::voronoi`]'s rule), so no
//! energy is lost when no sample lands on a small bright light.

use super::nearest_light_cells;
use super::voronoi::lights_from_cells;
use crate::env::probe::ProbeTables;
use crate::env::{LightSet, Probe};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// Uniform random directions (thesis 3.2.2, "unweighted sampling"): `n` directions
/// uniform on the sphere (`y = 1 - 2 xi_1`, azimuth `2 pi xi_2`, `Pcg64` seeded with
/// `seed`), pdf `1 / (4 pi)` ([`uniform_pdf`]). Instead of the Monte Carlo estimate
/// `L(d) 4 pi / n` (whose total power is random, and zero when no sample hits a small
/// light), each light carries the exact summed power of its Voronoi cell (texels nearer
/// to it than to any other light), so the total is exact and no energy is lost.
/// Deterministic per seed. Returns `n` lights (zero-power ones included); empty for
/// `n == 0` or a black probe.
pub fn uniform(probe: &Probe, n: usize, seed: u64) -> LightSet {
    let t = ProbeTables::new(probe);
    if n == 0 || t.total_weight <= 0.0 {
        return LightSet::default();
    }
    let mut rng = Pcg64::seed_from_u64(seed);
    let dirs: Vec<DVec3> = (0..n)
        .map(|_| uniform_direction(rng.gen::<f64>(), rng.gen::<f64>()))
        .collect();
    let cells = nearest_light_cells(&t, &dirs);
    lights_from_cells(&t, &dirs, &cells)
}

/// Uniform sphere map of `[0,1)^2`: `y = 1 - 2 xi_1`, azimuth `2 pi xi_2` with direction
/// `(r cos a, y, r sin a)`. Inverse: [`uniform_inverse`].
pub fn uniform_direction(xi1: f64, xi2: f64) -> DVec3 {
    let y = 1.0 - 2.0 * xi1;
    let r = (1.0 - y * y).max(0.0).sqrt();
    let a = std::f64::consts::TAU * xi2;
    DVec3::new(r * a.cos(), y, r * a.sin())
}

/// Inverse of [`uniform_direction`]: the `(xi_1, xi_2)` of a unit direction.
pub fn uniform_inverse(d: DVec3) -> (f64, f64) {
    let xi1 = (1.0 - d.y.clamp(-1.0, 1.0)) / 2.0;
    let mut xi2 = d.z.atan2(d.x) / std::f64::consts::TAU;
    if xi2 < 0.0 {
        xi2 += 1.0;
    }
    (xi1, xi2)
}

/// Density of [`uniform_direction`] in 1/sr: `1 / (4 pi)` everywhere.
pub fn uniform_pdf(_d: DVec3) -> f64 {
    1.0 / (4.0 * std::f64::consts::PI)
}
