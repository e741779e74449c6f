//! The product quadrature on the sphere, split at the horizon, with the SH basis tabulated at
//! its nodes, and the projection of a sphere function onto the SH basis with it (module doc
//! of [`super`], thesis 2.3.3).

use super::*;

/// Product quadrature on the sphere split at the horizon (module doc), with the SH basis
/// tabulated at its nodes. The first `upper` nodes are above the horizon; node `upper + p`
/// is the mirror image of node `p`.
pub struct SphereQuadrature {
    bands: usize,
    dirs: Vec<DVec3>,
    weights: Vec<f64>,
    upper: usize,
    y: Vec<f64>,
}

impl SphereQuadrature {
    /// `n_mu` Gauss-Legendre nodes in `z` per half sphere, `n_az` azimuths, basis of `bands`
    /// bands. Panics if any count is zero.
    pub fn new(bands: usize, n_mu: usize, n_az: usize) -> Self {
        assert!(bands > 0 && n_mu > 0 && n_az > 0, "empty quadrature");
        let (x, w) = gauss_legendre(n_mu);
        let mut dirs = Vec::with_capacity(2 * n_mu * n_az);
        let mut weights = Vec::with_capacity(2 * n_mu * n_az);
        let daz = std::f64::consts::TAU / n_az as f64;
        for sign in [1.0, -1.0] {
            for (xm, wm) in x.iter().zip(&w) {
                // Map [-1, 1] onto (0, 1): z = (x + 1)/2, dz = dx/2.
                let z = 0.5 * (xm + 1.0) * sign;
                let polar = z.clamp(-1.0, 1.0).acos();
                for a in 0..n_az {
                    let az = (a as f64 + 0.5) * daz;
                    dirs.push(local_direction_f64(polar, az));
                    weights.push(0.5 * wm * daz);
                }
            }
        }
        let t = num_terms(bands);
        let mut y = vec![0.0; dirs.len() * t];
        for (p, d) in dirs.iter().enumerate() {
            eval_sh_f64(*d, &mut y[p * t..(p + 1) * t]);
        }
        SphereQuadrature {
            bands,
            upper: n_mu * n_az,
            dirs,
            weights,
            y,
        }
    }

    /// `c_k = sum_p w_p g(d_p) Y_k(d_p)` over the whole sphere, RGB; `g` sees every node.
    pub fn project(&self, g: impl Fn(DVec3) -> DVec3) -> Vec<DVec3> {
        let t = num_terms(self.bands);
        let mut c = vec![DVec3::ZERO; t];
        for (p, d) in self.dirs.iter().enumerate() {
            let v = g(*d) * self.weights[p];
            if v == DVec3::ZERO {
                continue;
            }
            for (ck, yk) in c.iter_mut().zip(&self.y[p * t..(p + 1) * t]) {
                *ck += v * *yk;
            }
        }
        c
    }

    /// `b_k = sum_{p upper} w_p g(d_p) Y_k(d_p)` over the upper hemisphere only.
    pub(super) fn project_upper(&self, g: impl Fn(DVec3) -> DVec3) -> Vec<DVec3> {
        let t = num_terms(self.bands);
        let mut c = vec![DVec3::ZERO; t];
        for p in 0..self.upper {
            let v = g(self.dirs[p]) * self.weights[p];
            for (ck, yk) in c.iter_mut().zip(&self.y[p * t..(p + 1) * t]) {
                *ck += v * *yk;
            }
        }
        c
    }

    /// Hemisphere Gram matrix `G_kl = sum_{p upper} w_p Y_k Y_l` (row-major `T x T`).
    pub(super) fn upper_gram(&self) -> Vec<f64> {
        let t = num_terms(self.bands);
        let mut g = vec![0.0; t * t];
        for p in 0..self.upper {
            let y = &self.y[p * t..(p + 1) * t];
            let w = self.weights[p];
            for k in 0..t {
                let wk = w * y[k];
                for l in 0..t {
                    g[k * t + l] += wk * y[l];
                }
            }
        }
        g
    }
}

/// Projects a function of the direction over the **full sphere** onto `bands` bands with
/// the split product rule of the module doc (`n_mu` nodes per half, `2 n_mu` azimuths;
/// `n_mu` is raised to `bands` if smaller). Exact (to rounding) when `g` is band-limited to
/// `bands` bands. This is the projection of [`Method::Zero`] and [`Method::Even`] once the
/// extension below the horizon is applied.
pub fn project_sphere_function(
    g: &(dyn Fn(DVec3) -> DVec3 + Sync),
    bands: usize,
    n_mu: usize,
) -> Vec<DVec3> {
    let n_mu = n_mu.max(bands);
    SphereQuadrature::new(bands, n_mu, 2 * n_mu).project(g)
}

/// Cholesky factor (lower, row-major) of a symmetric positive definite `n x n` matrix.
/// `None` if a pivot is not positive.
pub(crate) fn cholesky(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if !(s > 0.0) {
                    return None;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    Some(l)
}

/// Solves `L L^T x = b` in place for a Cholesky factor from [`cholesky`].
pub(crate) fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}
