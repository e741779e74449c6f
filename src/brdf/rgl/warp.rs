//! Piecewise-bilinear tables on the unit square with interpolated parameter axes: the
//! interpolants and the 2D warp of the RGL format (Dupuy & Jakob 2018, section 5; the
//! structure Mitsuba 3 calls `Marginal2D<Float, D, Continuous = true>` and pbrt-v4
//! `PiecewiseLinear2D<D>`).
//!
//! A table holds `nx x ny` values per *slice* on the grid `x = i/(nx - 1)`,
//! `y = j/(ny - 1)` of `[0, 1]^2`, x fastest; a slice is picked by up to two parameter
//! axes (outermost first, each a strictly increasing list of values) and, innermost, a
//! channel index that is not interpolated (three for an RGB table, one otherwise). Between
//! the grid nodes the table is bilinear; between parameter values it is linear, the
//! weight `(p - p0)/(p1 - p0)` clamped to `[0, 1]` (constant beyond the ends); an axis of
//! one value is constant.
//!
//! - [`Table::eval`]: the interpolated value (the `ndf`, `sigma` and `spectra` fields).
//! - A *warp* ([`Table::warp`], the `vndf` field) is normalised per slice to integrate to
//!   1 over the square, and [`Table::invert`] maps a point `(x, y)` to
//!   `(C(x | y), M(y))`: `M` the marginal CDF of the bilinear density in y, `C` its
//!   conditional CDF in x at that y, both exact integrals of the bilinear density (so the
//!   map is continuous and one-to-one where the density is positive). Between parameter
//!   values the normalised densities and their CDFs are interpolated with the same
//!   weights, which is the exact CDF map of the interpolated density.
//!   [`Table::sample`] is its inverse (what a writer needs to place samples).
//!
//! The CDFs are accumulated in f64 and stored in the table's precision.

use super::real::Real;

/// At most this many parameter axes (the RGL fields use two: `phi_i`, `theta_i`).
pub const MAX_AXES: usize = 2;

/// A table of `S` values (module doc).
#[derive(Clone, Debug)]
pub struct Table<S> {
    nx: usize,
    ny: usize,
    channels: usize,
    axes: Vec<Vec<S>>,
    /// Per axis, the step of one parameter index in parameter cells (0 for an axis of one value).
    strides: Vec<usize>,
    data: Vec<S>,
    /// Per slice, `ny` rows of `nx - 1` partial row integrals (warps only).
    cond: Vec<S>,
    /// Per slice, `ny - 1` partial integrals of the row integrals (warps only).
    marg: Vec<S>,
}

/// Where the parameter values fall: the first slice and, per axis, the stride and the
/// two weights.
struct Weights<S> {
    base: usize,
    step: [usize; MAX_AXES],
    w: [(S, S); MAX_AXES],
}

fn strides(axes: &[Vec<f64>]) -> (Vec<usize>, usize) {
    let mut st = vec![0; axes.len()];
    let mut cells = 1;
    for (k, a) in axes.iter().enumerate().rev() {
        st[k] = if a.len() > 1 { cells } else { 0 };
        cells *= a.len();
    }
    (st, cells)
}

impl<S: Real> Table<S> {
    /// An interpolant of `data` (layout `[axis0][axis1][channel][y][x]`), values as given.
    /// The caller has checked the sizes (`nx, ny >= 2`, axes strictly increasing,
    /// `data.len()` the product).
    pub fn interpolant(
        data: &[f64],
        nx: usize,
        ny: usize,
        axes: &[Vec<f64>],
        channels: usize,
    ) -> Self {
        let (strides, cells) = strides(axes);
        debug_assert_eq!(data.len(), cells * channels * nx * ny);
        Table {
            nx,
            ny,
            channels,
            axes: axes
                .iter()
                .map(|a| a.iter().map(|&v| S::lit(v)).collect())
                .collect(),
            strides,
            data: data.iter().map(|&v| S::lit(v)).collect(),
            cond: Vec::new(),
            marg: Vec::new(),
        }
    }

    /// A warp of the densities `data` (layout `[axis0][axis1][y][x]`, one channel), each
    /// slice normalised to integrate to 1 over the square. Returns the index of the first
    /// slice whose integral is not positive and finite, which the caller reports.
    pub fn warp(data: &[f64], nx: usize, ny: usize, axes: &[Vec<f64>]) -> Result<Self, usize> {
        let (strides, cells) = strides(axes);
        let n = nx * ny;
        debug_assert_eq!(data.len(), cells * n);
        let (sx, sy) = (0.5 / (nx - 1) as f64, 0.5 / (ny - 1) as f64);
        let mut out = Vec::with_capacity(data.len());
        let mut cond = Vec::with_capacity(cells * ny * (nx - 1));
        let mut marg = Vec::with_capacity(cells * (ny - 1));
        let mut rows = vec![0.0f64; ny];
        let mut c = vec![0.0f64; ny * (nx - 1)];
        let mut m = vec![0.0f64; ny - 1];
        for s in 0..cells {
            let d = &data[s * n..(s + 1) * n];
            for y in 0..ny {
                let mut acc = 0.0;
                for x in 0..nx - 1 {
                    acc += sx * (d[y * nx + x] + d[y * nx + x + 1]);
                    c[y * (nx - 1) + x] = acc;
                }
                rows[y] = acc;
            }
            let mut acc = 0.0;
            for y in 0..ny - 1 {
                acc += sy * (rows[y] + rows[y + 1]);
                m[y] = acc;
            }
            if !(acc > 0.0 && acc.is_finite()) {
                return Err(s);
            }
            let norm = 1.0 / acc;
            out.extend(d.iter().map(|&v| S::lit(v * norm)));
            cond.extend(c.iter().map(|&v| S::lit(v * norm)));
            marg.extend(m.iter().map(|&v| S::lit(v * norm)));
        }
        Ok(Table {
            nx,
            ny,
            channels: 1,
            axes: axes
                .iter()
                .map(|a| a.iter().map(|&v| S::lit(v)).collect())
                .collect(),
            strides,
            data: out,
            cond,
            marg,
        })
    }

    fn weights(&self, params: &[S]) -> Weights<S> {
        let mut w = Weights {
            base: 0,
            step: [0; MAX_AXES],
            w: [(S::ONE, S::ZERO); MAX_AXES],
        };
        for (k, axis) in self.axes.iter().enumerate() {
            if axis.len() == 1 {
                continue;
            }
            let p = params[k];
            // The interval [i, i + 1] holding p, clamped to the axis (NaN falls in the first).
            let i = axis[1..axis.len() - 1].iter().filter(|&&v| v < p).count();
            let (p0, p1) = (axis[i], axis[i + 1]);
            let t = ((p - p0) / (p1 - p0)).max(S::ZERO).min(S::ONE);
            w.w[k] = (S::ONE - t, t);
            w.step[k] = self.strides[k];
            w.base += self.strides[k] * i;
        }
        w
    }

    /// `arr[i0]` interpolated over the parameter axes `..dim` (slice size `size` in `arr`).
    fn lookup(&self, arr: &[S], i0: usize, size: usize, w: &Weights<S>, dim: usize) -> S {
        if dim == 0 {
            return arr[i0];
        }
        let (w0, w1) = w.w[dim - 1];
        let v0 = self.lookup(arr, i0, size, w, dim - 1);
        if w.step[dim - 1] == 0 {
            return v0;
        }
        let v1 = self.lookup(arr, i0 + w.step[dim - 1] * size, size, w, dim - 1);
        v0 * w0 + v1 * w1
    }

    /// Grid cell and position inside it of `(x, y)`, clamped to the square.
    fn cell(&self, x: S, y: S) -> (usize, usize, S, S) {
        let fx = x.max(S::ZERO).min(S::ONE) * S::lit((self.nx - 1) as f64);
        let fy = y.max(S::ZERO).min(S::ONE) * S::lit((self.ny - 1) as f64);
        let ix = fx.index().min(self.nx - 2);
        let iy = fy.index().min(self.ny - 2);
        (ix, iy, fx - S::lit(ix as f64), fy - S::lit(iy as f64))
    }

    /// The bilinear interpolant at `(x, y)` (clamped to the square), channel `channel`,
    /// at the parameter values `params` (one per axis).
    pub fn eval(&self, x: S, y: S, params: &[S], channel: usize) -> S {
        let w = self.weights(params);
        let (ix, iy, tx, ty) = self.cell(x, y);
        let n = self.nx * self.ny;
        let size = n * self.channels;
        let i = (w.base * self.channels + channel) * n + iy * self.nx + ix;
        let d = self.axes.len();
        let v00 = self.lookup(&self.data, i, size, &w, d);
        let v10 = self.lookup(&self.data, i + 1, size, &w, d);
        let v01 = self.lookup(&self.data, i + self.nx, size, &w, d);
        let v11 = self.lookup(&self.data, i + self.nx + 1, size, &w, d);
        let (sx, sy) = (S::ONE - tx, S::ONE - ty);
        (v00 * sx + v10 * tx) * sy + (v01 * sx + v11 * tx) * ty
    }

    /// The density of the warp (channel 0) on the left and right edges of cell `(ix, iy)`,
    /// each interpolated linearly to the height `ty` in the cell: what [`Table::invert`]
    /// and [`Table::sample`] integrate across the cell.
    fn cell_edges(&self, w: &Weights<S>, ix: usize, iy: usize, ty: S) -> (S, S) {
        let (nx, d) = (self.nx, self.axes.len());
        let n = nx * self.ny;
        let i = w.base * n + iy * nx + ix;
        let v00 = self.lookup(&self.data, i, n, w, d);
        let v10 = self.lookup(&self.data, i + 1, n, w, d);
        let v01 = self.lookup(&self.data, i + nx, n, w, d);
        let v11 = self.lookup(&self.data, i + nx + 1, n, w, d);
        (v00 + (v01 - v00) * ty, v10 + (v11 - v10) * ty)
    }

    /// The warp's CDF map of `(x, y)` (module doc), in `[0, 1]^2`.
    pub fn invert(&self, x: S, y: S, params: &[S]) -> (S, S) {
        let w = self.weights(params);
        let d = self.axes.len();
        let (nx, ny) = (self.nx, self.ny);
        let (ix, iy, tx, ty) = self.cell(x, y);
        let (c0, c1) = self.cell_edges(&w, ix, iy, ty);
        let (px, py) = (
            S::ONE / S::lit((nx - 1) as f64),
            S::ONE / S::lit((ny - 1) as f64),
        );
        let half = S::lit(0.5);
        // x: the partial integral inside the cell, plus the cells before it.
        let mut u = tx * (c0 + (c1 - c0) * (half * tx)) * px;
        let nc = ny * (nx - 1);
        let row = w.base * nc + iy * (nx - 1);
        if ix > 0 {
            let a = self.lookup(&self.cond, row + ix - 1, nc, &w, d);
            let b = self.lookup(&self.cond, row + (nx - 1) + ix - 1, nc, &w, d);
            u = u + a + (b - a) * ty;
        }
        let r0 = self.lookup(&self.cond, row + nx - 2, nc, &w, d);
        let r1 = self.lookup(&self.cond, row + 2 * (nx - 1) - 1, nc, &w, d);
        let total = r0 + (r1 - r0) * ty;
        let u = if total > S::ZERO { u / total } else { S::ZERO };
        // y: the partial integral of the row integrals, plus the rows before.
        let mut v = ty * (r0 + (r1 - r0) * (half * ty)) * py;
        if iy > 0 {
            let nm = ny - 1;
            v = v + self.lookup(&self.marg, w.base * nm + iy - 1, nm, &w, d);
        }
        (u.max(S::ZERO).min(S::ONE), v.max(S::ZERO).min(S::ONE))
    }

    /// The inverse of [`Table::invert`]: the point whose CDF values are `(u, v)`.
    pub fn sample(&self, u: S, v: S, params: &[S]) -> (S, S) {
        let w = self.weights(params);
        let d = self.axes.len();
        let (nx, ny) = (self.nx, self.ny);
        let (u, v) = (u.max(S::ZERO).min(S::ONE), v.max(S::ZERO).min(S::ONE));
        let nm = ny - 1;
        let marg = |j: usize| self.lookup(&self.marg, w.base * nm + j, nm, &w, d);
        // The row: the last j whose cumulative integral is below v.
        let iy = (0..nm - 1).filter(|&j| marg(j) < v).count();
        let before = if iy > 0 { marg(iy - 1) } else { S::ZERO };
        let nc = ny * (nx - 1);
        let row = w.base * nc + iy * (nx - 1);
        let r0 = self.lookup(&self.cond, row + nx - 2, nc, &w, d);
        let r1 = self.lookup(&self.cond, row + 2 * (nx - 1) - 1, nc, &w, d);
        let py = S::lit((ny - 1) as f64);
        let ty = solve_segment((v - before) * py, r0, r1);
        // The column at that height.
        let cond = |k: usize| {
            let a = self.lookup(&self.cond, row + k, nc, &w, d);
            let b = self.lookup(&self.cond, row + (nx - 1) + k, nc, &w, d);
            a + (b - a) * ty
        };
        let target = u * (r0 + (r1 - r0) * ty);
        let ix = (0..nx - 2).filter(|&k| cond(k) < target).count();
        let left = if ix > 0 { cond(ix - 1) } else { S::ZERO };
        let (c0, c1) = self.cell_edges(&w, ix, iy, ty);
        let px = S::lit((nx - 1) as f64);
        let tx = solve_segment((target - left) * px, c0, c1);
        ((S::lit(ix as f64) + tx) / px, (S::lit(iy as f64) + ty) / py)
    }
}

/// The `t` in `[0, 1]` with `t (a + (b - a) t / 2) = q`: where the integral of the linear
/// function from `a` (at 0) to `b` (at 1) reaches `q`. The stable root
/// `2q / (a + sqrt(a^2 + 2 (b - a) q))`; 0 where the function vanishes.
fn solve_segment<S: Real>(q: S, a: S, b: S) -> S {
    let q = q.max(S::ZERO);
    let disc = (a * a + S::lit(2.0) * (b - a) * q).max(S::ZERO);
    let den = a + disc.sqrt();
    if den > S::ZERO {
        (S::lit(2.0) * q / den).min(S::ONE)
    } else {
        S::ZERO
    }
}
