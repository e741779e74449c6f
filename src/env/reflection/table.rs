//! [`ReflectionTable`]: the outgoing radiance of one isotropic material under one probe,
//! over (reflected direction, view polar angle, Fourier series in the normal's angle about
//! the reflected direction), and its lookup (parent module doc, "Parameterisation").

use crate::conventions::{sphere_oct_decode_f64, sphere_oct_encode, sphere_oct_vertex};
use glam::{DVec3, Vec3};

/// Smallest order of the series in psi (`[env] reflection_order`).
pub const MIN_ORDER: usize = 1;

/// Largest order of the series in psi: the highest the diagnosis of the series measured
/// (0.3-16% at the 99th percentile; parent module doc, "Order of the series in psi"); its
/// series are 3.4 times the default's bytes and its bake about 4 times the time.
pub const MAX_ORDER: usize = 8;

/// Coefficients per (node, slice, colour) of the largest order: the size of the fixed
/// arrays the bake and the lookup hold a basis in.
pub const MAX_COEFFS: usize = 2 * MAX_ORDER + 1;

/// Fourier coefficients per (node, slice, colour) of a series of order `order`:
/// `a0, a1, b1, ..., a_order, b_order` of
/// `a0 + sum_{k = 1..order} (a_k cos k psi + b_k sin k psi)`; 5 at the default order 2.
pub const fn coeffs(order: usize) -> usize {
    2 * order + 1
}

/// Samples of psi per (node, slice) the bake projects onto the [`coeffs`] coefficients of
/// order `order` (`2 pi m / N`, `m = 0..N`, `N = max(3 order, 8)`: 8 at the default order
/// 2, 18 at order 6). At least `2 order + 1`, so the projection is the discrete Fourier
/// transform's; a harmonic `j` of the radiance lands on coefficient `k` when
/// `j = +-k (mod N)`, so the first above the order that reaches a held one is `N - order`
/// (`2 order` from order 3 on, 6 at order 2). Each sample is a sum over the node's texels,
/// so `N` is the bake's cost: `4 order` before, and at order 6 on 128 cells under studio
/// 18 samples gave the same error as 24 within 0.07 points of p99 for Blinn-Phong 50, 200,
/// 500 and gold-dust-paint (parent module doc, "Order of the series in psi"), 14 moved the
/// grazing band's p99 of Blinn-Phong 50 from 7.1% to 8.8%.
pub const fn psi_samples(order: usize) -> usize {
    if 3 * order > 8 {
        3 * order
    } else {
        8
    }
}

/// Polar angle of the view of the last uniform slice, degrees (slices `0..slices` span
/// `[0, LAST_UNIFORM_SLICE_DEG]`).
pub const LAST_UNIFORM_SLICE_DEG: f64 = 85.0;

/// Polar angle of the view of the horizon slice after them, degrees: clamping at the last
/// uniform slice left 50-160% p99 errors above it in the accuracy study.
pub const HORIZON_SLICE_DEG: f64 = 89.9;

/// `|r.y|` above which a node's psi is measured from +z instead of +y (the two charts of
/// the reference tangent, parent module doc).
pub const CHART_SWITCH: f64 = 0.8;

/// The error the bake measured of its own table against exact f64 sums over the full
/// resolution residual probe at sample points (`build::measure_error`), on Rec. 709
/// luminance of the table's term: relative RMSE `sqrt(sum e^2 / sum Y^2)` and the 99th
/// percentile and largest `|e| / Y`, over samples weighted as a camera sees a sphere
/// (`cos^2 polar_o` uniform) and, separately, over views with polar angle in 70-89.9 degrees.
#[derive(Clone, Copy, Debug, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakeError {
    /// Samples of each of the two sets.
    pub samples: usize,
    pub rel_rmse: f64,
    pub p99: f64,
    pub max: f64,
    pub grazing_rel_rmse: f64,
    pub grazing_p99: f64,
    pub grazing_max: f64,
}

/// A reflection-space radiance table (parent module doc). Values are f32: first the lobes'
/// series, `values[((node * slices_total + s) * 3 + c) * C + k]` (`C =`
/// [`coeffs`]`(order)`, coefficient `k` in the order of [`coeffs`]) with
/// `node = j (G + 1) + i` the vertex at octahedral `(u, v) = (-1 + 2i/G, -1 + 2j/G)`, then
/// the diffuse term over normals on the same vertices,
/// `values[lobe_values + node * 3 + c]` ([`value_count`]; parent module doc, "Diffuse term").
#[derive(Clone, Debug, PartialEq)]
pub struct ReflectionTable {
    pub(super) grid: usize,
    /// Uniform slices (the horizon slice is one more).
    pub(super) slices: usize,
    /// Order of the series in psi, [`MIN_ORDER`] to [`MAX_ORDER`].
    pub(super) order: usize,
    /// Probe rotation about +y, radians: a world direction `d` reads the table at
    /// `rotate_about_up(d, -rotation)`.
    pub(super) rotation: f32,
    /// `sin` and `cos` of `-rotation`.
    pub(super) unrotate: (f32, f32),
    /// Per node, true when its psi is measured from +z ([`CHART_SWITCH`]).
    pub(super) chart_z: Vec<bool>,
    pub(super) values: Vec<f32>,
    pub(super) error: BakeError,
}

/// Values of the lobes' series of a table of `grid` cells, `slices` uniform slices and
/// series of order `order`.
pub fn lobe_value_count(grid: usize, slices: usize, order: usize) -> usize {
    (grid + 1).pow(2) * (slices + 1) * 3 * coeffs(order)
}

/// Values of a table of `grid` cells, `slices` uniform slices and series of order `order`:
/// the lobes' series and the diffuse term's RGB per node ([`ReflectionTable`]). Four bytes
/// each: at the default 64 cells and 13 + 1 slices, 0.71 MB per coefficient (3.6 MB at
/// order 2, 9.3 MB at order 6), at 128 cells 2.8 MB (14.2 and 36.5 MB).
pub fn value_count(grid: usize, slices: usize, order: usize) -> usize {
    lobe_value_count(grid, slices, order) + (grid + 1).pow(2) * 3
}

/// The polar angle of the view of slice `s` of `slices` uniform ones and the horizon slice
/// (`s == slices`), radians.
pub fn slice_angle(s: usize, slices: usize) -> f64 {
    if s >= slices {
        HORIZON_SLICE_DEG.to_radians()
    } else {
        (LAST_UNIFORM_SLICE_DEG * s as f64 / (slices - 1) as f64).to_radians()
    }
}

/// The direction of vertex `(i, j)` of a grid of `g` cells per side (probe frame).
pub fn node_direction(i: usize, j: usize, g: usize) -> DVec3 {
    sphere_oct_decode_f64(sphere_oct_vertex(i, g), sphere_oct_vertex(j, g))
}

/// Whether a node at reflected direction `r` measures psi from +z (else +y).
pub fn chart_is_z(r: DVec3) -> bool {
    r.y.abs() > CHART_SWITCH
}

/// The reference tangent `t` and `b = r x t` about the unit direction `r` in the chart
/// given (`t` the chart's axis projected normal to `r`): psi is the angle of the normal's
/// component normal to `r` from `t` towards `b`.
pub fn chart_frame(r: DVec3, chart_z: bool) -> (DVec3, DVec3) {
    let axis = if chart_z { DVec3::Z } else { DVec3::Y };
    let t = (axis - axis.dot(r) * r).normalize();
    (t, r.cross(t))
}

/// f32 [`chart_frame`] for lookups.
#[inline]
fn chart_frame_f32(r: Vec3, chart_z: bool) -> (Vec3, Vec3) {
    let axis = if chart_z { Vec3::Z } else { Vec3::Y };
    let t = (axis - axis.dot(r) * r).normalize_or(Vec3::X);
    (t, r.cross(t))
}

/// The Fourier basis `[1, cos psi, sin psi, ..., cos(order psi), sin(order psi)]` of the
/// normal `n` about `r` in a chart's frame `(t, b)` (entries past [`coeffs`]`(order)`
/// zero); `[1, 1, 0, 1, 0, ...]` when `n` is `r` (then only the first coefficient is
/// non-zero: the bake stores zeros for the others at polar angle 0). Orders 1 and 2 in
/// closed form (`cos 2psi = c^2 - s^2`, `sin 2psi = 2 c s`: the lookup's bits from before
/// the order was a parameter), higher ones by the angle-addition recurrence from the one
/// below.
#[inline]
fn psi_basis(
    n: Vec3,
    r: Vec3,
    cos_o: f32,
    (t, b): (Vec3, Vec3),
    order: usize,
) -> [f32; MAX_COEFFS] {
    let d = n - cos_o * r;
    let (x, y) = (d.dot(t), d.dot(b));
    let len = (x * x + y * y).sqrt();
    let (c, s) = if len > 1e-12 {
        (x / len, y / len)
    } else {
        (1.0, 0.0)
    };
    let mut out = [0.0f32; MAX_COEFFS];
    out[0] = 1.0;
    let (mut ck, mut sk) = (c, s);
    for k in 1..=order {
        match k {
            1 => {}
            2 => (ck, sk) = (c * c - s * s, 2.0 * c * s),
            _ => (ck, sk) = (ck * c - sk * s, sk * c + ck * s),
        }
        out[2 * k - 1] = ck;
        out[2 * k] = sk;
    }
    out
}

/// The four vertices of an octahedral grid of `g` cells per side around the unit direction
/// `d` (node `j (g + 1) + i`) and their bilinear weights: the lookup of every value held
/// over the grid's vertices (the lobes' series at `r`, the diffuse term at `n`).
#[inline]
pub(super) fn grid_corners(d: Vec3, g: usize) -> [(usize, f32); 4] {
    let n1 = g + 1;
    let (u, w) = sphere_oct_encode(d);
    let cell = |x: f32| {
        let f = ((x + 1.0) * 0.5 * g as f32).clamp(0.0, g as f32);
        let i0 = (f.floor() as usize).min(g - 1);
        (i0, f - i0 as f32)
    };
    let ((i0, a), (j0, b)) = (cell(u), cell(w));
    [
        (j0 * n1 + i0, (1.0 - a) * (1.0 - b)),
        (j0 * n1 + i0 + 1, a * (1.0 - b)),
        ((j0 + 1) * n1 + i0, (1.0 - a) * b),
        ((j0 + 1) * n1 + i0 + 1, a * b),
    ]
}

impl ReflectionTable {
    /// A table from its parts; the caller checks `values.len()`. Panics on an order outside
    /// [`MIN_ORDER`] to [`MAX_ORDER`] (the lookup has no other;
    /// [`super::build::BakeParams::check`] and the cache's read refuse one first).
    pub(super) fn from_parts(
        grid: usize,
        slices: usize,
        order: usize,
        rotation: f64,
        values: Vec<f32>,
        error: BakeError,
    ) -> ReflectionTable {
        let n = grid + 1;
        assert!(
            (MIN_ORDER..=MAX_ORDER).contains(&order),
            "psi order {order}"
        );
        debug_assert_eq!(values.len(), value_count(grid, slices, order));
        let chart_z = (0..n * n)
            .map(|k| chart_is_z(node_direction(k % n, k / n, grid)))
            .collect();
        ReflectionTable {
            grid,
            slices,
            order,
            rotation: rotation as f32,
            unrotate: (-(rotation as f32)).sin_cos(),
            chart_z,
            values,
            error,
        }
    }

    /// The same table read with the probe turned by `angle` radians more about +y.
    pub fn turned(&self, angle: f64) -> ReflectionTable {
        let rotation = self.rotation as f64 + angle;
        ReflectionTable {
            rotation: rotation as f32,
            unrotate: (-(rotation as f32)).sin_cos(),
            ..self.clone()
        }
    }

    /// Cells per side of the octahedral grid of reflected directions (`(G + 1)^2` nodes).
    pub fn grid(&self) -> usize {
        self.grid
    }

    /// Uniform view slices (the horizon slice is one more).
    pub fn slices(&self) -> usize {
        self.slices
    }

    /// Order of the series in psi (`[env] reflection_order`; [`coeffs`] of it per node,
    /// slice and colour).
    pub fn order(&self) -> usize {
        self.order
    }

    /// Every value (layout in the type's doc).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The probe rotation about +y the lookup undoes, radians.
    pub fn rotation(&self) -> f32 {
        self.rotation
    }

    /// The error the bake measured ([`BakeError`]).
    pub fn error(&self) -> BakeError {
        self.error
    }

    /// Bytes of the values.
    pub fn bytes(&self) -> usize {
        4 * self.values.len()
    }

    /// `d` in the probe's frame (rotation undone).
    #[inline]
    fn unrotated(&self, d: Vec3) -> Vec3 {
        let (s, c) = self.unrotate;
        Vec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c)
    }

    /// The table's radiance (RGB, W/(m^2 sr) for a probe in W/(m^2 sr)) at the unit world
    /// normal `n` and unit world view `v` (towards the viewer, at most 90 degrees from `n`):
    /// bilinear over the four grid nodes around `r = reflect(v, n)`, linear between the two
    /// slices around the view's polar angle (clamped to the horizon slice), each node's
    /// Fourier series evaluated at psi measured in its own chart; plus the diffuse term,
    /// bilinear over the four grid nodes around `n`. Plain f32 in a fixed order:
    /// the same bits on every path and thread count.
    #[inline]
    pub fn radiance(&self, n: Vec3, v: Vec3) -> Vec3 {
        let (n, v) = (self.unrotated(n), self.unrotated(v));
        let cos_o = n.dot(v).clamp(0.0, 1.0);
        let r = (2.0 * cos_o * n - v).normalize_or(n);
        // Slice pair and weight.
        let polar = cos_o.acos();
        let last = LAST_UNIFORM_SLICE_DEG.to_radians() as f32;
        let (s0, ws) = if polar < last {
            let f = polar / last * (self.slices - 1) as f32;
            let s0 = (f.floor() as usize).min(self.slices - 2);
            (s0, f - s0 as f32)
        } else {
            let span = (HORIZON_SLICE_DEG - LAST_UNIFORM_SLICE_DEG).to_radians() as f32;
            (self.slices - 1, ((polar - last) / span).min(1.0))
        };
        // Grid cell and weights: of `r` for the lobes, of `n` for the diffuse term.
        let g = self.grid;
        let bases = [
            psi_basis(n, r, cos_o, chart_frame_f32(r, false), self.order),
            psi_basis(n, r, cos_o, chart_frame_f32(r, true), self.order),
        ];
        // One unrolled copy of the series' sum per order (the order is checked where a
        // table is made, `from_parts`).
        let mut out = match coeffs(self.order) {
            3 => self.lobes::<3>(r, (s0, ws), &bases),
            5 => self.lobes::<5>(r, (s0, ws), &bases),
            7 => self.lobes::<7>(r, (s0, ws), &bases),
            9 => self.lobes::<9>(r, (s0, ws), &bases),
            11 => self.lobes::<11>(r, (s0, ws), &bases),
            13 => self.lobes::<13>(r, (s0, ws), &bases),
            15 => self.lobes::<15>(r, (s0, ws), &bases),
            17 => self.lobes::<17>(r, (s0, ws), &bases),
            c => unreachable!("{c} coefficients: from_parts admits orders 1 to {MAX_ORDER}"),
        };
        let diffuse = lobe_value_count(g, self.slices, self.order);
        for (node, wc) in grid_corners(n, g) {
            let at = diffuse + node * 3;
            for (c, o) in out.iter_mut().enumerate() {
                *o += wc * self.values[at + c];
            }
        }
        Vec3::from_array(out)
    }

    /// The lobes' series of [`ReflectionTable::radiance`] at the reflected direction `r`
    /// (probe frame), between slices `s0` and `s0 + 1` (weight `ws` on the second), each
    /// node's series of `C` coefficients evaluated at the basis of its chart (`bases`: +y,
    /// +z). Products summed in coefficient order from the first.
    #[inline]
    fn lobes<const C: usize>(
        &self,
        r: Vec3,
        (s0, ws): (usize, f32),
        bases: &[[f32; MAX_COEFFS]; 2],
    ) -> [f32; 3] {
        let ns = self.slices + 1;
        let mut out = [0.0f32; 3];
        for (node, wc) in grid_corners(r, self.grid) {
            let basis = &bases[self.chart_z[node] as usize];
            for (s, wt) in [(s0, 1.0 - ws), (s0 + 1, ws)] {
                let wgt = wc * wt;
                let at = (node * ns + s) * 3 * C;
                for (c, o) in out.iter_mut().enumerate() {
                    let q = &self.values[at + c * C..][..C];
                    let mut f = q[0] * basis[0];
                    for (qk, bk) in q[1..].iter().zip(&basis[1..]) {
                        f += qk * bk;
                    }
                    *o += wgt * f;
                }
            }
        }
        out
    }
}
