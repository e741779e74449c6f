//! Building a [`TransferTable`] from a probe: the exact sum over every texel (parent
//! module doc), and the choice of the brightest texels summed exactly beside it.
//!
//! (Past 400 lines because it is one computation, the table's sum over the probe: choosing
//! the exact texels, the residual and its downsampling, the per-row geometry and the FFT
//! correlation all feed the one loop in `build_table_from_residual` and are not used
//! elsewhere.)
//!
//! # How the sum is organised
//! Node `(i, j)`'s normal is node `(0, j)`'s turned about +y by the node's azimuth
//! `2 pi i / nu`, and the shading frame turns with it (it is built from the up vector,
//! which the turn keeps). When `nu` divides the probe's width `W`, the turn moves every
//! texel by exactly `s_i = i W / nu` columns, so
//! `T_k(i, j) = sum_rows sum_cols L(row, col + s_i) Omega_row w_k(j, row, col)` with
//! `w_k(j, row, col) = Y_k(local) [local.z > 0] [local.z if cosine]` the weights of node
//! `(0, j)` (columns mod `W`). The weights are evaluated once per table row and probe row
//! (`W x terms` values, the SH by [`crate::sh::basis::ShLanes`], four columns at once,
//! `weights.rs`). Summed directly that is
//! `nodes x texels above the horizon x 3 x terms` multiply-adds; but for one table row and
//! one probe row the sum over columns is a circular correlation of the power row with the
//! weight row, evaluated at the shifts `s_i`, so the build sums its transform instead
//! (`correlate.rs`, the correlation theorem, rustfft in f64): per table row and probe row
//! `terms / 2` FFTs of size `W` and `3 terms (W/2 + 1)` complex multiply-adds, one inverse
//! per term and channel at the end. It agrees with the direct sum (kept, test only) to
//! within f64 rounding (tests.rs, `fft_build_matches_the_direct_sum`).
//!
//! # Residual
//! The sum runs over the residual: the probe without the texels summed exactly per pixel
//! (`exclude`, the brightest). A table of at most 8 bands on a grid of 2.8-degree nodes
//! needs it only smooth, so a residual wider than [`RESIDUAL_WIDTH`] is first downsampled by
//! an integer factor ([`residual_factor`]): each coarse texel carries the exact summed power
//! of its block of fine texels, at the coarse texel's centre, and the sum above runs over
//! the coarse texels (`W` is then the coarse width). The brightest texels stay exact, taken
//! out at full resolution before the downsampling. The cost no longer grows with the probe
//! past that width: a 4096 x 2048 probe (8 M texels) is summed as 512 x 256, its texels
//! only read once and added up (docs/environment-methods.md has the times and the accuracy
//! cost against the full-resolution sum).
//!
//! # Determinism
//! One rayon task per table row; each node's sum runs over probe rows in index order
//! inside that task, the transforms planned once per build, so the table is the same bits
//! for any thread count. The residual's rows and their transforms are each computed by one
//! task, in a fixed order. (rustfft picks its SIMD kernels by CPU: another machine may round
//! the f64 sums differently in the last bits, far below the table's f32.)

use super::correlate::{table_row_fft, PowerSpectra, RowGeometry};
use super::fault::BuildFault;
use super::table::TransferTable;
use super::TransferBasis;
use crate::conventions::{probe_direction, texel_center_f64};
use crate::env::{luminance, LightSet, Probe};
use crate::error::{Error, Result};
use crate::progress::Progress;
use glam::DVec3;
use rayon::prelude::*;

/// Indices (`row * width + col`) of the `k` texels of largest luminance x solid angle
/// ([`crate::env::luminance`], exact texel solid angles), brightest first; ties keep the
/// lower index. Fewer when the probe has fewer texels.
///
/// The order is total (weight, then index), so the `k` brightest are one set whatever
/// finds them: each band of probe rows keeps its own `k` best in a bounded heap (in
/// parallel), and the bands' lists are merged and cut to `k`. O(texels log k), a few
/// tens of milliseconds for a 4096 x 2048 probe (a full sort took about a second).
pub fn brightest_texels(probe: &Probe, k: usize) -> Vec<usize> {
    use std::collections::BinaryHeap;
    /// Weight and index ordered brightest first: `a < b` when `a` is brighter (or as bright
    /// with a lower index), so a max-heap's top is the dimmest kept.
    #[derive(Clone, Copy)]
    struct Ranked(f64, usize);
    impl PartialEq for Ranked {
        fn eq(&self, o: &Self) -> bool {
            self.cmp(o) == std::cmp::Ordering::Equal
        }
    }
    impl Eq for Ranked {}
    impl Ord for Ranked {
        fn cmp(&self, o: &Self) -> std::cmp::Ordering {
            o.0.total_cmp(&self.0).then(self.1.cmp(&o.1))
        }
    }
    impl PartialOrd for Ranked {
        fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(o))
        }
    }
    let (w, h) = (probe.width(), probe.height());
    if k == 0 || w * h == 0 {
        return Vec::new();
    }
    let texels = probe.texels();
    let band = (h / (4 * rayon::current_num_threads().max(1))).max(1);
    let best = |rows: std::ops::Range<usize>| -> Vec<Ranked> {
        let mut heap: BinaryHeap<Ranked> = BinaryHeap::with_capacity(k + 1);
        for row in rows {
            let omega = probe.solid_angle(row);
            for (col, t) in texels[row * w..(row + 1) * w].iter().enumerate() {
                let r = Ranked(luminance(*t) * omega, row * w + col);
                if heap.len() < k {
                    heap.push(r);
                } else if r < *heap.peek().expect("k > 0 kept") {
                    heap.pop();
                    heap.push(r);
                }
            }
        }
        heap.into_vec()
    };
    let mut all: Vec<Ranked> = (0..h.div_ceil(band))
        .into_par_iter()
        .map(|b| best(b * band..((b + 1) * band).min(h)))
        .flatten()
        .collect();
    all.sort_unstable();
    all.truncate(k);
    all.into_iter().map(|r| r.1).collect()
}

/// The texels `indices` as directional lights: each texel's centre direction (probe
/// rotation applied, [`Probe::direction`]) with irradiance `L x Omega x intensity`
/// (W/m^2 for a probe in W/(m^2 sr)), as [`crate::env::SamplerConfig::Full`] makes them.
pub fn texel_lights(probe: &Probe, indices: &[usize], intensity: f32) -> LightSet {
    let w = probe.width();
    let mut ls = LightSet::with_capacity(indices.len());
    for &idx in indices {
        let (row, col) = (idx / w, idx % w);
        let t = probe.texel(row, col);
        let e = DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * probe.solid_angle(row);
        ls.push(probe.direction(row, col), e * intensity as f64);
    }
    ls
}

/// Builds the transfer table of `probe` (times `intensity`) for `basis` on the
/// `grid = (nu, nv)` of normals (parent module doc), leaving out the texels `exclude` (summed exactly
/// elsewhere, [`texel_lights`]), from the residual at most [`RESIDUAL_WIDTH`] texels wide
/// ([`build_table_from_residual`]). One progress step per table row (`nv` in all).
///
/// Errors (naming the scene field): `nu` not a divisor of the probe's width, `nu < 3`,
/// `nv < 2`, or more than 2^24 values.
pub fn build_table(
    probe: &Probe,
    basis: TransferBasis,
    grid: (usize, usize),
    exclude: &[usize],
    intensity: f32,
    progress: &Progress,
    fault: BuildFault,
) -> Result<TransferTable> {
    build_table_from_residual(
        probe,
        basis,
        grid,
        (exclude, RESIDUAL_WIDTH),
        intensity,
        progress,
        fault,
    )
}

/// Largest width, in texels, of the residual probe (the probe without its `exact_lights`
/// brightest texels) a transfer table is projected from, unless the table's grid asks for
/// more ([`residual_factor`]: at least four residual texels per azimuth node). A wider probe
/// is downsampled by an integer factor, each coarse texel carrying the exact summed power of
/// its block at its centre (the module doc's "Residual").
///
/// Why 512: the shipped probes are 512 x 256, so their tables (and the golden images drawn
/// with them) keep their bits; and a table of at most 8 bands needs the residual only
/// smooth: at 512 texels a coarse texel is 0.7 degrees, a quarter of the default grid's
/// node spacing (2.8 degrees), whose bilinear interpolation bounds the table's accuracy.
/// Measured against the full-resolution projection on city upsampled to 2048 x 1024
/// (`examples/transfer_residual_error.rs`, teal-paint and Lambert): relative RMSE 0.0003%,
/// p99 0.002%, against the method's own 0.1-1% and a few percent (docs/environment-methods.md).
pub const RESIDUAL_WIDTH: usize = 512;

/// The integer factor a `w x h` probe is downsampled by before its projection onto a table
/// of `nu` azimuth nodes: the smallest `f` that divides `w` and `h`, leaves `w / f` a
/// multiple of `nu` (so the FFT build's shifts stay whole texels) of at least `4 nu`
/// texels, and `w / f` at most `max(max_width, 4 nu)`; when no factor brings it that low,
/// the largest admissible factor below that (1, the full probe, at worst). 1 for a probe no
/// wider than that.
pub fn residual_factor(w: usize, h: usize, nu: usize, max_width: usize) -> usize {
    let nu = nu.max(1);
    let ok = |f: usize| {
        w.is_multiple_of(f)
            && h.is_multiple_of(f)
            && (w / f).is_multiple_of(nu)
            && (f == 1 || w / f >= 4 * nu)
    };
    let limit = max_width.max(4 * nu);
    let need = w.div_ceil(limit).max(1);
    (need..=w / nu)
        .find(|&f| ok(f))
        .or_else(|| (1..need).rev().find(|&f| ok(f)))
        .unwrap_or(1)
}

/// [`build_table`] with the residual's largest width given: `residual = (exclude,
/// max_width)`, the texels left out and the width [`residual_factor`] downsamples the rest
/// to (`usize::MAX`: the full probe, as the accuracy study compares against).
pub fn build_table_from_residual(
    probe: &Probe,
    basis: TransferBasis,
    grid: (usize, usize),
    residual: (&[usize], usize),
    intensity: f32,
    progress: &Progress,
    fault: BuildFault,
) -> Result<TransferTable> {
    let (exclude, max_width) = residual;
    let (nu, nv) = grid;
    let (w, h) = (probe.width(), probe.height());
    if nu < 3 || w % nu != 0 {
        return Err(Error::field(
            "env.transfer_azimuth",
            format!("{nu} must be at least 3 and divide the probe's width {w}"),
        ));
    }
    if nv < 2 {
        return Err(Error::field(
            "env.transfer_polar",
            format!("{nv} must be at least 2 (both poles are rows)"),
        ));
    }
    let nt = basis.terms();
    if nu * nv * 3 * nt > 1 << 24 {
        return Err(Error::field(
            "env.transfer_polar",
            format!("{nu} x {nv} nodes x {nt} terms is over 2^24 values"),
        ));
    }
    let f = residual_factor(w, h, nu, max_width);
    let (power, cw, ch) = residual_power(probe, exclude, intensity, f);
    // Unrotated texel centre directions of the residual (the table lives in the probe's
    // frame).
    let dirs: Vec<DVec3> = (0..cw * ch)
        .map(|idx| {
            probe_direction(
                texel_center_f64(idx % cw, cw),
                texel_center_f64(idx / cw, ch),
            )
        })
        .collect();
    progress.set_length(nv as u64);
    let spectra = PowerSpectra::new(&power, cw, ch);
    let dispatch = lane_dispatch();
    let (w, h) = (cw, ch);
    let rows: Vec<Vec<f64>> = (0..nv)
        .into_par_iter()
        .map(|j| {
            let geometry = RowGeometry { j, nu, nv, w, h };
            #[cfg(test)]
            if DIRECT_SUM.with(|d| d.get()) {
                let row = table_row_direct(j, nu, nv, w, h, w / nu, basis, &power, &dirs, fault);
                progress.inc(1);
                return row;
            }
            let row = table_row_fft(&geometry, basis, &spectra, &dirs, fault, dispatch);
            progress.inc(1);
            row
        })
        .collect();
    let mut values = vec![0.0f32; nu * nv * 3 * nt];
    for (j, row) in rows.iter().enumerate() {
        for i in 0..nu {
            let node = match fault {
                BuildFault::TransposedAxes => i * nv + j,
                _ => j * nu + i,
            };
            let src = &row[i * 3 * nt..(i + 1) * 3 * nt];
            for (d, s) in values[node * 3 * nt..(node + 1) * 3 * nt]
                .iter_mut()
                .zip(src)
            {
                *d = *s as f32;
            }
        }
    }
    Ok(TransferTable::from_parts(
        (nu, nv),
        basis,
        probe.rotation(),
        values,
    ))
}

/// The residual's texel power `L Omega intensity` per channel (the texels `exclude` zero),
/// summed over blocks of `f x f` texels (row-major within a block) into a
/// `w / f x h / f` image: `(power, w / f, h / f)`. With `f = 1` every texel's own power,
/// the full probe. Parallel over residual rows, each summed by one task in a fixed order.
fn residual_power(
    probe: &Probe,
    exclude: &[usize],
    intensity: f32,
    f: usize,
) -> (Vec<[f64; 3]>, usize, usize) {
    let (w, h) = (probe.width(), probe.height());
    let (cw, ch) = (w / f, h / f);
    let mut excluded = vec![false; w * h];
    for &idx in exclude {
        excluded[idx] = true;
    }
    let texels = probe.texels();
    let mut power = vec![[0.0f64; 3]; cw * ch];
    power
        .par_chunks_mut(cw)
        .enumerate()
        .for_each(|(crow, out)| {
            for row in crow * f..(crow + 1) * f {
                let o = probe.solid_angle(row) * intensity as f64;
                for (ccol, acc) in out.iter_mut().enumerate() {
                    for col in ccol * f..(ccol + 1) * f {
                        let idx = row * w + col;
                        if excluded[idx] {
                            continue;
                        }
                        let t = texels[idx];
                        let p = [t[0] as f64 * o, t[1] as f64 * o, t[2] as f64 * o];
                        if f == 1 {
                            *acc = p;
                        } else {
                            for c in 0..3 {
                                acc[c] += p[c];
                            }
                        }
                    }
                }
            }
        });
    (power, cw, ch)
}

/// **Test only**, the direct sum the FFT build ([`table_row_fft`]) is checked against: the
/// `nu` nodes of table row `j` (polar `pi j / (nv - 1)`), `nu x 3 x terms` f64 values
/// (module doc, "How the sum is organised"), each shift's correlation summed term by term.
#[cfg(test)]
#[allow(clippy::too_many_arguments)]
pub(super) fn table_row_direct(
    j: usize,
    nu: usize,
    nv: usize,
    w: usize,
    h: usize,
    stride: usize,
    basis: TransferBasis,
    power: &[[f64; 3]],
    dirs: &[DVec3],
    fault: BuildFault,
) -> Vec<f64> {
    use crate::sh::basis::eval_sh_f64;
    let nt = basis.terms();
    let polar = std::f64::consts::PI * j as f64 / (nv - 1) as f64;
    let (sp, cp) = polar.sin_cos();
    // Node (0, j): normal at probe azimuth 0 and its shading frame (parent module doc):
    // n = (0, cos p, sin p), t = (0, sin p, -cos p), b = n x t = (-1, 0, 0).
    let n = DVec3::new(0.0, cp, sp);
    let t = DVec3::new(0.0, sp, -cp);
    let b = n.cross(t);
    let mut acc = vec![0.0f64; nu * 3 * nt];
    let mut weights = vec![0.0f64; w * nt];
    let mut above: Vec<usize> = Vec::with_capacity(w);
    for r in 0..h {
        above.clear();
        for col in 0..w {
            let d = dirs[r * w + col];
            let local = DVec3::new(d.dot(t), d.dot(b), d.dot(n));
            if !(local.z > 0.0) && fault != BuildFault::NoHemisphereClip {
                continue;
            }
            let wk = &mut weights[col * nt..(col + 1) * nt];
            match basis {
                TransferBasis::Irradiance => wk[0] = local.z.max(0.0),
                TransferBasis::Sh { cosine, .. } => {
                    eval_sh_f64(local, wk);
                    if cosine {
                        for v in wk.iter_mut() {
                            *v *= local.z;
                        }
                    }
                }
            }
            above.push(col);
        }
        let prow = &power[r * w..(r + 1) * w];
        for i in 0..nu {
            let s = i * stride;
            let a = &mut acc[i * 3 * nt..(i + 1) * 3 * nt];
            let (ar, rest) = a.split_at_mut(nt);
            let (ag, ab) = rest.split_at_mut(nt);
            for &col in &above {
                let p = prow[(col + s) % w];
                if p == [0.0; 3] {
                    continue;
                }
                let wk = &weights[col * nt..(col + 1) * nt];
                for k in 0..nt {
                    ar[k] += p[0] * wk[k];
                    ag[k] += p[1] * wk[k];
                    ab[k] += p[2] * wk[k];
                }
            }
        }
    }
    acc
}

#[cfg(test)]
thread_local! {
    /// **Test only**: build with [`table_row_direct`] instead of the FFT (set on the thread
    /// that calls [`build_table`] inside a one-thread pool, see tests.rs).
    pub(super) static DIRECT_SUM: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

#[cfg(test)]
thread_local! {
    /// **Test only**: the kernel path the build's lanes take instead of the detected one
    /// (set on the thread that calls [`build_table`] inside a one-thread pool, see
    /// tests.rs).
    pub(super) static LANE_PATH: std::cell::Cell<Option<crate::lanes::KernelPath>> =
        const { std::cell::Cell::new(None) };
}

/// The lanes the build's multiply-adds run on: the widest this CPU runs (every path gives
/// the same bits, [`super::correlate`]'s "Bits"); in tests, [`LANE_PATH`]'s when set.
fn lane_dispatch() -> crate::lanes::Dispatch {
    #[cfg(test)]
    if let Some(path) = LANE_PATH.with(|p| p.get()) {
        return crate::lanes::Dispatch::choose(path).expect("a path this CPU runs");
    }
    crate::lanes::Dispatch::detect()
}
