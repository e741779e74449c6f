//! Least squares on the upper hemisphere held to `f_r cos >= 0` ([`super::Method::NonNegative`]):
//! the ringing-suppressed SH fit that keeps least squares' accuracy.
//!
//! Design rule: the same objective as [`super::Method::Lsq`],
//! `|| A c - g ||^2_H + lambda |c|^2` (normal equations `(G + lambda I) c = b`), minimised
//! subject to the reconstruction being non-negative on a dense set of upper-hemisphere
//! directions ([`CONSTRAINT_GRID`], equal solid-angle cells), by an exterior penalty with a
//! growing active set: solve, add every constraint direction where the reconstruction is
//! below zero to the active set, add `mu w Y_s Y_s^T` for each newly active direction `s` to
//! the matrix (`w` its cell's solid angle, `mu` = [`PENALTY`]), solve again; stop when no
//! direction is newly negative or after [`MAX_ROUNDS`]. Directions are never removed, so the
//! rounds end. A penalty of `mu` pulls an active value to about `1/(1 + mu w |Y_s|^2)` of
//! what it would be unpenalised (`|Y_s|^2 = L^2 / (4 pi)`): at 8 bands about 1/1600, so a
//! -3 % dip becomes about -0.002 %; between the directions small dips remain (the error
//! grid of `acquire`'s table, denser, sees them). Deterministic: directions in grid order, f64 throughout.
//!
//! Where the unconstrained fit is nowhere negative on the set, the result is exactly the
//! unconstrained one (the same bits as `lsq`).

use super::measure::ErrorGrid;
use super::quadrature::{cholesky, cholesky_solve};
use crate::sh::eval_sh_f64;

/// Directions on which `f_r cos >= 0` is enforced: 32 x 64 cells of the upper hemisphere
/// (about 3 square degrees each).
pub const CONSTRAINT_GRID: ErrorGrid = ErrorGrid { n_mu: 32, n_az: 64 };

/// The penalty weight `mu` per unit solid angle (module doc).
pub const PENALTY: f64 = 1e5;

/// Most active-set rounds per fit.
pub const MAX_ROUNDS: usize = 16;

/// The constraint directions' basis values, shared by every view texel of an acquisition.
pub(super) struct Constraints {
    t: usize,
    /// `Y_k(d_s)`, row-major `dirs x t`.
    y: Vec<f64>,
    /// Solid angle of one cell (all equal).
    weight: f64,
}

impl Constraints {
    pub(super) fn new(t: usize) -> Self {
        let dirs = CONSTRAINT_GRID.directions();
        let mut y = vec![0.0; dirs.len() * t];
        for (s, d) in dirs.iter().enumerate() {
            eval_sh_f64(*d, &mut y[s * t..(s + 1) * t]);
        }
        Constraints {
            t,
            y,
            weight: std::f64::consts::TAU / dirs.len() as f64,
        }
    }

    fn value(&self, s: usize, c: &[f64]) -> f64 {
        self.y[s * self.t..(s + 1) * self.t]
            .iter()
            .zip(c)
            .map(|(a, b)| a * b)
            .sum()
    }

    /// Solves `(G + lambda I) c = b` (`regularised` is `G + lambda I`, row-major; `factor`
    /// its Cholesky factor) under the constraints (module doc). `None` when a penalised
    /// matrix is not positive definite (it always is for a positive definite start).
    pub(super) fn solve(&self, regularised: &[f64], factor: &[f64], b: &[f64]) -> Option<Vec<f64>> {
        let t = self.t;
        let mut c = b.to_vec();
        cholesky_solve(factor, t, &mut c);
        let n = self.y.len() / t;
        let mut active = vec![false; n];
        let mut m: Option<Vec<f64>> = None;
        for _ in 0..MAX_ROUNDS {
            let mut added = false;
            for (s, on) in active.iter_mut().enumerate() {
                if !*on && self.value(s, &c) < 0.0 {
                    *on = true;
                    added = true;
                    let mm = m.get_or_insert_with(|| regularised.to_vec());
                    let ys = &self.y[s * t..(s + 1) * t];
                    let k = PENALTY * self.weight;
                    for i in 0..t {
                        let ki = k * ys[i];
                        for j in 0..t {
                            mm[i * t + j] += ki * ys[j];
                        }
                    }
                }
            }
            if !added {
                break;
            }
            let l = cholesky(m.as_ref().expect("set when a direction was added"), t)?;
            c = b.to_vec();
            cholesky_solve(&l, t, &mut c);
        }
        Some(c)
    }
}
