//! [`TransferTable`]: `T_k(n)` (RGB, `k` over the basis's terms) on a latitude-longitude
//! grid of normals, and its bilinear lookup (grid and frame in the parent module's doc).

use super::TransferBasis;
use glam::Vec3;

/// A transfer table (parent module doc). Values are f32, node-major with the polar index
/// slowest, then colour, then term: `values[((j * nu + i) * 3 + c) * terms + k]`.
#[derive(Clone, Debug, PartialEq)]
pub struct TransferTable {
    pub(super) nu: usize,
    pub(super) nv: usize,
    pub(super) basis: TransferBasis,
    /// Probe rotation about +y, radians: a world normal `n` reads the node of
    /// `rotate_about_up(n, -rotation)`.
    pub(super) rotation: f32,
    pub(super) values: Vec<f32>,
}

/// The four nodes and weights bilinear interpolation blends at a normal: `(node index,
/// weight)`, weights summing to 1.
pub type Corners = [(usize, f32); 4];

impl TransferTable {
    /// `(nu, nv)`: azimuth nodes (wrapping) and polar nodes (both poles included).
    pub fn grid(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// The basis the table projects onto.
    pub fn basis(&self) -> TransferBasis {
        self.basis
    }

    /// Terms per colour ([`TransferBasis::terms`]).
    pub fn terms(&self) -> usize {
        self.basis.terms()
    }

    /// The `3 x terms` values of node `n` (`[R.., G.., B..]`).
    #[inline]
    pub fn node(&self, n: usize) -> &[f32] {
        let w = 3 * self.terms();
        &self.values[n * w..(n + 1) * w]
    }

    /// Bilinear corners at the world unit normal `n`: the normal is turned into the probe's
    /// frame (rotation undone), its probe angles `(polar from +y, azimuth 2 pi u)` found as
    /// [`crate::conventions::probe_uv`] does, and the grid is interpolated linearly in both
    /// angles (azimuth wraps; polar nodes include the poles, so no clamping is needed).
    #[inline]
    pub fn corners(&self, n: Vec3) -> Corners {
        let (s, c) = (-self.rotation).sin_cos();
        // rotate_about_up(n, -rotation), in f32.
        let x = n.x * c + n.z * s;
        let z = -n.x * s + n.z * c;
        let polar = n.y.clamp(-1.0, 1.0).acos();
        let mut u = (-x).atan2(z) * (0.5 * std::f32::consts::FRAC_1_PI);
        if u < 0.0 {
            u += 1.0;
        }
        let a = u * self.nu as f32;
        let b = polar * std::f32::consts::FRAC_1_PI * (self.nv - 1) as f32;
        let af = a.floor();
        let bf = b.floor();
        let (fa, fb) = (a - af, b - bf);
        let i0 = (af as usize) % self.nu;
        let i1 = (i0 + 1) % self.nu;
        let j0 = (bf as usize).min(self.nv - 1);
        let j1 = (j0 + 1).min(self.nv - 1);
        [
            (j0 * self.nu + i0, (1.0 - fa) * (1.0 - fb)),
            (j0 * self.nu + i1, fa * (1.0 - fb)),
            (j1 * self.nu + i0, (1.0 - fa) * fb),
            (j1 * self.nu + i1, fa * fb),
        ]
    }

    /// Outgoing radiance `sum_k c_k T_k(n)` per colour at the world unit normal `n`, for
    /// coefficients `c` laid out `[R.., G.., B..]` (`3 x terms` values; for Lambert the one
    /// coefficient per colour is `albedo / pi`). `T` is interpolated bilinearly (the dot
    /// products of the four corners, blended: the same value in exact arithmetic).
    #[inline]
    pub fn radiance(&self, n: Vec3, c: &[f32]) -> Vec3 {
        let nt = self.terms();
        debug_assert_eq!(c.len(), 3 * nt);
        let mut out = Vec3::ZERO;
        for (node, w) in self.corners(n) {
            if w == 0.0 {
                continue;
            }
            let t = self.node(node);
            let dot = |o: usize| -> f32 {
                c[o..o + nt]
                    .iter()
                    .zip(&t[o..o + nt])
                    .fold(0.0f32, |s, (a, b)| a.mul_add(*b, s))
            };
            out += w * Vec3::new(dot(0), dot(nt), dot(2 * nt));
        }
        out
    }
}
