//! Projected weights of table texels, `integral w(h) (h.n) dω_h` for the `GL_LINEAR` weight
//! `w` of each texel: what normalising `p(h)` for the function the renderer evaluates takes
//! (the parent module doc, "Normalisation").

use crate::conventions::{hemi_oct_bilinear_texels_f64, hemi_texel_angles_f64};
use std::sync::{Arc, Mutex};

/// `W_ij = integral w_ij(h) (h.n) dω_h` for every texel of an `n x n` octahedral table,
/// `w_ij` its `GL_LINEAR` weight as a function of the half vector (module doc): in
/// octahedral coordinates `(h.n) dω_h = z / |q|^4 du dv / 2` with `q = (x, y, z)` the
/// point of the octahedron (`dω = dA (q.N)/|q|^3` on a face of normal `N = (+-1, +-1, 1)/sqrt 3`,
/// `dA = sqrt 3 dx dy`, `dx dy = du dv / 2`). A midpoint rule on 8 x 8 cells per texel,
/// whose cell edges fall on the texel centres (where the tent weights have kinks), then
/// rescaled so that the weights sum to exactly `integral (h.n) dω = pi` (a constant table
/// keeps its value exactly; the rescale is 1 + 4e-7 at n = 64).
///
/// Computed once per side `n` for the rest of the process and shared ([`Arc`]): the sum
/// takes 64 n^2 octahedral decodes (0.1 s at n = 128), and fitting a D-BRDF builds several
/// tables of one side (the library's Lambert + D-BRDF fit built ten, 37 % of
/// `brdfkit render --material lindt-paper`'s start-up). Deterministic, so sharing changes
/// no bit.
pub fn octahedral_projected_weights(n: usize) -> Arc<Vec<f64>> {
    static BY_SIDE: Mutex<Vec<(usize, Arc<Vec<f64>>)>> = Mutex::new(Vec::new());
    let mut known = BY_SIDE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, w)) = known.iter().find(|(side, _)| *side == n) {
        return Arc::clone(w);
    }
    let w = Arc::new(compute_octahedral_projected_weights(n));
    known.push((n, Arc::clone(&w)));
    w
}

/// The sum behind [`octahedral_projected_weights`].
fn compute_octahedral_projected_weights(n: usize) -> Vec<f64> {
    const SUB: usize = 8;
    let m = n * SUB;
    let du = 2.0 / m as f64;
    let mut w = vec![0.0f64; n * n];
    for b in 0..m {
        let v = -1.0 + (b as f64 + 0.5) * du;
        for a in 0..m {
            let u = -1.0 + (a as f64 + 0.5) * du;
            let x = 0.5 * (u + v);
            let y = 0.5 * (u - v);
            let z = 1.0 - x.abs() - y.abs();
            let q2 = x * x + y * y + z * z;
            let jac = z / (q2 * q2) * 0.5 * du * du;
            for (i, j, t) in hemi_oct_bilinear_texels_f64(u, v, n) {
                w[j * n + i] += t * jac;
            }
        }
    }
    let total: f64 = w.iter().sum();
    let k = std::f64::consts::PI / total;
    for x in &mut w {
        *x *= k;
    }
    w
}

/// `W_j = integral_0^{pi/2} w_j(polar) cos(polar) sin(polar) d polar` for row `j` of an
/// `nv`-row hemispherical table, where `w_j` is the `GL_LINEAR` weight of row `j` as a
/// function of the polar angle ([`crate::conventions::hemi_bilinear_texels`]: a tent
/// between the neighbouring row centres, 1 from the first centre up to the pole and from
/// the last centre down to the horizon). The rows sum to 1/2 (`integral cos sin`).
/// Closed form per linear piece: with `g = sin(2x)/2`, `G0 = -cos(2x)/4` and
/// `G1 = -x cos(2x)/4 + sin(2x)/8` are antiderivatives of `g` and `x g`.
pub fn polar_row_projected_weight(j: usize, nv: usize) -> f64 {
    let centre = |k: usize| hemi_texel_angles_f64(0, k, 1, nv).0;
    let g0 = |x: f64| -(2.0 * x).cos() / 4.0;
    let g1 = |x: f64| -x * (2.0 * x).cos() / 4.0 + (2.0 * x).sin() / 8.0;
    // Rising from 0 at `a` to 1 at `b`, and falling from 1 at `a` to 0 at `b`.
    let rise = |a: f64, b: f64| ((g1(b) - g1(a)) - a * (g0(b) - g0(a))) / (b - a);
    let fall = |a: f64, b: f64| (b * (g0(b) - g0(a)) - (g1(b) - g1(a))) / (b - a);
    let flat = |a: f64, b: f64| g0(b) - g0(a);
    let half_pi = std::f64::consts::FRAC_PI_2;
    let c = centre(j);
    let below = if j == 0 {
        flat(0.0, c)
    } else {
        rise(centre(j - 1), c)
    };
    let above = if j + 1 == nv {
        flat(c, half_pi)
    } else {
        fall(c, centre(j + 1))
    };
    below + above
}
