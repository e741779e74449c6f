//! The weights of one table row against one probe row, `w_k(j, row, col)` of
//! [`super::build`]'s "How the sum is organised", evaluated [`SH_LANES`] columns at a time
//! ([`ShLanes`]) and stored term-major, so the build reads each term's row of `W` values
//! contiguously for its transform.
//!
//! Every value is the one the per-column evaluation gave ([`crate::sh::eval_sh_f64`], then
//! the cosine): the lanes run the same operations per column, so the tables keep their
//! bits (`crate::sh::basis`'s test `lanes_give_the_scalar_bits`; the golden images drawn
//! under `method = "transfer"`).

use super::TransferBasis;
use crate::sh::basis::{Lanes, ShLanes, SH_LANES};
use glam::DVec3;

/// Room for every term's weights of one probe row, and the SH constants.
pub(super) struct RowWeights {
    basis: TransferBasis,
    sh: ShLanes,
    /// Columns of a probe row.
    width: usize,
    /// Values between one term's row and the next: the width rounded up to whole lane
    /// groups, plus one cache line, so the terms' rows do not fall on the same cache sets
    /// (a 512-wide row of f64 is 4 KiB, and the stores of one lane group to every term
    /// would all map to one set).
    stride: usize,
    /// `values[k * stride + col]`.
    values: Vec<f64>,
    lanes: Vec<Lanes>,
}

impl RowWeights {
    /// Room for probe rows of `width` columns.
    pub(super) fn new(basis: TransferBasis, width: usize) -> RowWeights {
        let bands = match basis {
            TransferBasis::Sh { bands, .. } => bands,
            TransferBasis::Irradiance => 0,
        };
        let nt = basis.terms();
        let stride = width.div_ceil(SH_LANES) * SH_LANES + 8;
        RowWeights {
            basis,
            sh: ShLanes::new(bands),
            width,
            stride,
            values: vec![0.0; nt * stride],
            lanes: vec![[0.0; SH_LANES]; bands * bands],
        }
    }

    /// Term `k`'s weights along the row, one per column.
    pub(super) fn term(&self, k: usize) -> &[f64] {
        &self.values[k * self.stride..k * self.stride + self.width]
    }

    /// The weights of node `(0, j)` of a table with `nv` polar rows for every column of
    /// probe row `r` (`dirs`: the unrotated texel centre directions, `width` per row):
    /// `Y_k(local) [local.z > 0] [local.z if cosine]` in the node's shading frame, zero
    /// below its horizon when `clip` (the build's seeded fault "no hemisphere clip" passes
    /// `false`). Returns whether any column is above the horizon. Inlined into the build's
    /// lane kernel, so it is compiled for that kernel's instruction set (the same
    /// operations, never fused: the same bits).
    #[inline(always)]
    pub(super) fn compute(
        &mut self,
        (j, nv): (usize, usize),
        r: usize,
        dirs: &[DVec3],
        clip: bool,
    ) -> bool {
        let (w, stride, nt) = (self.width, self.stride, self.basis.terms());
        let polar = std::f64::consts::PI * j as f64 / (nv - 1) as f64;
        let (sp, cp) = polar.sin_cos();
        // Node (0, j): normal at probe azimuth 0 and its shading frame (parent module doc):
        // n = (0, cos p, sin p), t = (0, sin p, -cos p), b = n x t = (-1, 0, 0).
        let n = DVec3::new(0.0, cp, sp);
        let t = DVec3::new(0.0, sp, -cp);
        let b = n.cross(t);
        let row = &dirs[r * w..(r + 1) * w];
        let mut any = false;
        for col0 in (0..w).step_by(SH_LANES) {
            let (mut x, mut y, mut z) = ([0.0; SH_LANES], [0.0; SH_LANES], [0.0; SH_LANES]);
            let mut kept = [false; SH_LANES];
            for (i, d) in row[col0..].iter().take(SH_LANES).enumerate() {
                (x[i], y[i], z[i]) = (d.dot(t), d.dot(b), d.dot(n));
                kept[i] = z[i] > 0.0 || !clip;
            }
            let mut put = |k: usize, v: Lanes| {
                let out: &mut Lanes = (&mut self.values[k * stride + col0..][..SH_LANES])
                    .try_into()
                    .expect("a whole lane group");
                *out = v;
            };
            if !kept.contains(&true) {
                for k in 0..nt {
                    put(k, [0.0; SH_LANES]);
                }
                continue;
            }
            any = true;
            match self.basis {
                TransferBasis::Irradiance => put(
                    0,
                    std::array::from_fn(|i| if kept[i] { z[i].max(0.0) } else { 0.0 }),
                ),
                TransferBasis::Sh { cosine, .. } => {
                    self.sh.eval(x, y, z, &mut self.lanes);
                    for (k, v) in self.lanes.iter().enumerate() {
                        put(
                            k,
                            std::array::from_fn(|i| match (kept[i], cosine) {
                                (false, _) => 0.0,
                                (true, true) => v[i] * z[i],
                                (true, false) => v[i],
                            }),
                        );
                    }
                }
            }
        }
        any
    }
}
