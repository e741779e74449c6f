//! Building a [`TransferTable`] from a probe: the exact sum over every texel (parent
//! module doc), and the choice of the brightest texels summed exactly beside it.
//!
//! # How the sum is organised
//! Node `(i, j)`'s normal is node `(0, j)`'s turned about +y by the node's azimuth
//! `2 pi i / nu`, and the shading frame turns with it (it is built from the up vector,
//! which the turn keeps). When `nu` divides the probe's width `W`, the turn moves every
//! texel by exactly `s_i = i W / nu` columns, so
//! `T_k(i, j) = sum_rows sum_cols L(row, col + s_i) Omega_row w_k(j, row, col)` with
//! `w_k(j, row, col) = Y_k(local) [local.z > 0] [local.z if cosine]` the weights of node
//! `(0, j)` (columns mod `W`). The weights are evaluated once per table row and probe row
//! (`W x terms` values, the SH by [`crate::sh::basis::eval_sh_f64`]), so the work is
//! `nodes x texels above the horizon x 3 x terms` multiply-adds, in f64.
//!
//! # Determinism
//! One rayon task per table row; each node's sum runs over probe rows, then columns, in
//! index order inside that task, so the table is the same bits for any thread count.

use super::table::TransferTable;
use super::TransferBasis;
use crate::conventions::{probe_direction, texel_center_f64};
use crate::env::{luminance, LightSet, Probe};
use crate::error::{Error, Result};
use crate::progress::Progress;
use crate::sh::basis::eval_sh_f64;
use glam::DVec3;
use rayon::prelude::*;

/// **Test only**: faults seeded into the build, for the tests that show the accuracy
/// check fails on them.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BuildFault {
    /// No fault: the shipped build.
    #[default]
    None,
    /// Nodes stored with the azimuth index slowest (`i * nv + j`) while the lookup reads
    /// `j * nu + i`: a transposed table axis.
    TransposedAxes,
    /// Texels below the node's horizon summed too: a missing hemisphere clip.
    NoHemisphereClip,
}

/// Indices (`row * width + col`) of the `k` texels of largest luminance x solid angle
/// ([`crate::env::luminance`], exact texel solid angles), brightest first; ties keep the
/// lower index. Fewer when the probe has fewer texels.
pub fn brightest_texels(probe: &Probe, k: usize) -> Vec<usize> {
    let w = probe.width();
    let mut order: Vec<(f64, usize)> = probe
        .texels()
        .iter()
        .enumerate()
        .map(|(idx, t)| (luminance(*t) * probe.solid_angle(idx / w), idx))
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    order.into_iter().take(k).map(|(_, idx)| idx).collect()
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
/// elsewhere, [`texel_lights`]). One progress step per table row (`nv` in all).
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
    // Texel power L Omega intensity per channel, excluded texels zero.
    let mut power: Vec<[f64; 3]> = probe
        .texels()
        .iter()
        .enumerate()
        .map(|(idx, t)| {
            let o = probe.solid_angle(idx / w) * intensity as f64;
            [t[0] as f64 * o, t[1] as f64 * o, t[2] as f64 * o]
        })
        .collect();
    for &idx in exclude {
        power[idx] = [0.0; 3];
    }
    // Unrotated texel centre directions (the table lives in the probe's frame).
    let dirs: Vec<DVec3> = (0..w * h)
        .map(|idx| probe_direction(texel_center_f64(idx % w, w), texel_center_f64(idx / w, h)))
        .collect();
    let stride = w / nu;
    progress.set_length(nv as u64);
    let rows: Vec<Vec<f64>> = (0..nv)
        .into_par_iter()
        .map(|j| {
            let row = table_row(j, nu, nv, w, h, stride, basis, &power, &dirs, fault);
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

/// The `nu` nodes of table row `j` (polar `pi j / (nv - 1)`), `nu x 3 x terms` f64 values
/// (module doc, "How the sum is organised").
#[allow(clippy::too_many_arguments)]
fn table_row(
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
