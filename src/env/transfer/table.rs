//! [`TransferTable`]: `T_k(n)` (RGB, `k` over the basis's terms) on a latitude-longitude
//! grid of normals, and its bilinear lookup (grid and frame in the parent module's doc).

use super::TransferBasis;
use crate::conventions::floor_f32;
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
    /// `sin` and `cos` of `-rotation`, computed once.
    pub(super) unrotate: (f32, f32),
    pub(super) values: Vec<f32>,
}

/// The four nodes and weights bilinear interpolation blends at a normal: `(node index,
/// weight)`, weights summing to 1.
pub type Corners = [(usize, f32); 4];

impl TransferTable {
    /// A table from its parts (values laid out as the type's doc says); `rotation` is the
    /// probe's rotation about +y in radians. The caller checks `values.len()`.
    pub(super) fn from_parts(
        grid: (usize, usize),
        basis: TransferBasis,
        rotation: f64,
        values: Vec<f32>,
    ) -> TransferTable {
        debug_assert_eq!(values.len(), grid.0 * grid.1 * 3 * basis.terms());
        TransferTable {
            nu: grid.0,
            nv: grid.1,
            basis,
            rotation: rotation as f32,
            unrotate: (-(rotation as f32)).sin_cos(),
            values,
        }
    }

    /// The same table read with the probe turned by `angle` radians more about +y (the
    /// values are in the probe's own frame; only the lookup's rotation changes).
    pub fn turned(&self, angle: f64) -> TransferTable {
        let rotation = self.rotation as f64 + angle;
        TransferTable {
            rotation: rotation as f32,
            unrotate: (-(rotation as f32)).sin_cos(),
            ..self.clone()
        }
    }

    /// Every value (layout in the type's doc).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The probe rotation about +y the lookup undoes, radians.
    pub fn rotation(&self) -> f32 {
        self.rotation
    }

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
    /// [`crate::conventions::probe_uv`] does (`std`'s `acos` and `atan2`), and the grid is
    /// interpolated linearly in both angles (azimuth wraps; polar nodes include the poles,
    /// so no clamping is needed). The scalar oracle's and the f64 path's lookup; the fast
    /// path's is the same on polynomial angles (`crate::shade`'s transfer term).
    #[inline]
    pub fn corners(&self, n: Vec3) -> Corners {
        let (x, z) = self.unrotated_xz(n);
        let polar = n.y.clamp(-1.0, 1.0).acos();
        let mut u = (-x).atan2(z) * (0.5 * std::f32::consts::FRAC_1_PI);
        if u < 0.0 {
            u += 1.0;
        }
        self.corners_at(polar, u)
    }

    /// `(x, z)` of `rotate_about_up(n, -rotation)`, in f32: the world unit normal `n`
    /// turned into the probe's frame.
    #[inline(always)]
    pub fn unrotated_xz(&self, n: Vec3) -> (f32, f32) {
        let (s, c) = self.unrotate;
        (n.x * c + n.z * s, -n.x * s + n.z * c)
    }

    /// Bilinear corners at probe polar angle `polar` (radians from +y) and azimuth
    /// fraction `u` in `[0, 1]` (the probe's angles of a normal turned by
    /// [`TransferTable::unrotated_xz`]; the fast path's lookup, `crate::shade`'s transfer
    /// term, finds them with the kernel's polynomial angles).
    #[inline(always)]
    pub fn corners_at(&self, polar: f32, u: f32) -> Corners {
        let a = u * self.nu as f32;
        let b = polar * std::f32::consts::FRAC_1_PI * (self.nv - 1) as f32;
        let af = floor_f32(a);
        let bf = floor_f32(b);
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
    /// coefficient per colour is `albedo / pi`). `T` is interpolated bilinearly at `n`
    /// ([`TransferTable::corners`]) into `scratch` (`3 x terms` values), then dotted with `c`
    /// ([`dot`]). Plain multiplies and adds in a fixed order (no FMA, no reassociation).
    #[inline]
    pub fn radiance_with(&self, n: Vec3, c: &[f32], scratch: &mut [f32]) -> Vec3 {
        let nt = self.terms();
        let w3 = 3 * nt;
        debug_assert_eq!(c.len(), w3);
        let t = &mut scratch[..w3];
        let [(n0, a0), (n1, a1), (n2, a2), (n3, a3)] = self.corners(n);
        let (t0, t1, t2, t3) = (self.node(n0), self.node(n1), self.node(n2), self.node(n3));
        for ((((d, x0), x1), x2), x3) in t.iter_mut().zip(t0).zip(t1).zip(t2).zip(t3) {
            *d = a0 * x0 + a1 * x1 + a2 * x2 + a3 * x3;
        }
        Vec3::new(
            dot(&c[..nt], &t[..nt]),
            dot(&c[nt..2 * nt], &t[nt..2 * nt]),
            dot(&c[2 * nt..], &t[2 * nt..]),
        )
    }

    /// [`TransferTable::radiance_with`] with its own scratch buffer (for callers outside a
    /// pixel loop).
    pub fn radiance(&self, n: Vec3, c: &[f32]) -> Vec3 {
        let mut scratch = vec![0.0f32; 3 * self.terms()];
        self.radiance_with(n, c, &mut scratch)
    }
}

/// `sum_k a_k b_k` in f32 with eight partial sums (term `k` into sum `k mod 8`), added
/// pairwise in a fixed order at the end: the same bits on every machine, and a loop the
/// compiler turns into SIMD.
#[inline]
pub fn dot(a: &[f32], b: &[f32]) -> f32 {
    debug_assert_eq!(a.len(), b.len());
    let mut acc = [0.0f32; 8];
    let mut ca = a.chunks_exact(8);
    let mut cb = b.chunks_exact(8);
    for (x, y) in (&mut ca).zip(&mut cb) {
        for l in 0..8 {
            acc[l] += x[l] * y[l];
        }
    }
    for (l, (x, y)) in ca.remainder().iter().zip(cb.remainder()).enumerate() {
        acc[l] += x * y;
    }
    ((acc[0] + acc[4]) + (acc[2] + acc[6])) + ((acc[1] + acc[5]) + (acc[3] + acc[7]))
}
