//! Writing RGL files from a BRDF given as a function: how the test materials are made
//! (no real RGL file can be fetched in the project's environment), and the inverse of
//! the evaluation in [`super`], so a file written here reproduces its source exactly at
//! the table's nodes and by interpolation between them.
//!
//! Given a microfacet distribution `D(m)` (any positive function; the closer to the
//! source's lobe, the better the table resolves it) the writer tabulates, on the unit
//! square coordinates of [`super`] (`theta = u^2 pi / 2`, `phi = (2 v - 1) pi`):
//! - `ndf`: `D` at the grid nodes;
//! - `sigma`: the projected area `sigma(w) = int D(m) max(0, m.w) dm` by a midpoint rule
//!   in the same coordinates (`dm = 2 pi^2 u sin(theta) du dv`);
//! - `vndf`: per viewer node `w_t`, the density of the visible normals in `(u, v)`,
//!   `D(m) max(0, m.w_t) / sigma(w_t) * 2 pi^2 u sin(theta_m)` (azimuth relative to the
//!   viewer's for isotropic files);
//! - `spectra` / `rgb`: per viewer node, at each node `s` of the sample grid, the half
//!   vector `m = VNDF(s)` ([`super::warp::Table::sample`]), the light `2 (w_t.m) m - w_t`,
//!   and the value `f cos(theta_light) * 4 sigma(u_t) / D(u_m)` (the interpolated `ndf`
//!   and `sigma` tables, as the reader divides by them), 0 below the horizon;
//! - `luminance`: the mean over channels plus 5% of the slice's mean (positive wherever
//!   the table is, which sampling readers need); `jacobian` = 1.

use super::tensor::{self, Dtype};
use super::warp::Table;
use glam::DVec3;
use std::f64::consts::PI;

/// The grid of a file to write.
#[derive(Clone, Debug)]
pub struct Layout {
    /// Viewer polar nodes, radians, strictly increasing in `[0, pi/2]`.
    pub theta_i: Vec<f32>,
    /// Viewer azimuth nodes: `[0]` for an isotropic file, or strictly increasing over
    /// `[-pi, pi]` (both ends included) for an anisotropic one.
    pub phi_i: Vec<f32>,
    /// `ndf` and `sigma` grid: (azimuth rows, polar columns).
    pub ndf_res: (usize, usize),
    /// `vndf` grid per viewer node: (azimuth rows, polar columns).
    pub vndf_res: (usize, usize),
    /// Sample grid side of the spectra.
    pub sample_res: usize,
    /// Wavelengths (nm) of a spectral file; `None` writes an RGB file.
    pub wavelengths: Option<Vec<f32>>,
}

impl Layout {
    /// `n` polar nodes evenly spaced from 0 to `max_deg` degrees.
    pub fn thetas(n: usize, max_deg: f64) -> Vec<f32> {
        (0..n)
            .map(|k| (k as f64 / (n - 1) as f64 * max_deg.to_radians()) as f32)
            .collect()
    }

    /// `n` azimuth nodes over `[-pi, pi]`, ends included.
    pub fn phis(n: usize) -> Vec<f32> {
        (0..n)
            .map(|k| (-PI + 2.0 * PI * k as f64 / (n - 1) as f64) as f32)
            .collect()
    }
}

fn u2theta(u: f64) -> f64 {
    u * u * PI / 2.0
}

fn u2phi(v: f64) -> f64 {
    (2.0 * v - 1.0) * PI
}

fn dir(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

fn f32_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|&x| (x as f32).to_le_bytes()).collect()
}

/// The bytes of an RGL file of `f` (module doc). `ndf` is `D(m)` for a unit local `m`;
/// `f(light, view)` gives `f_r` (1/sr, without the cosine) per channel: 3 (linear RGB)
/// for an RGB layout, one per wavelength for a spectral one.
pub fn tabulate(
    layout: &Layout,
    ndf: &(dyn Fn(DVec3) -> f64 + Sync),
    f: &(dyn Fn(DVec3, DVec3) -> Vec<f64> + Sync),
    description: &str,
) -> Vec<u8> {
    let isotropic = layout.phi_i.len() <= 2;
    let channels = layout.wavelengths.as_ref().map_or(3, |w| w.len());
    let (nr, nc) = layout.ndf_res;
    // ndf at the grid nodes
    let node = |i: usize, n: usize| i as f64 / (n - 1) as f64;
    let mut ndf_t = Vec::with_capacity(nr * nc);
    for j in 0..nr {
        for i in 0..nc {
            ndf_t.push(ndf(dir(u2theta(node(i, nc)), u2phi(node(j, nr)))));
        }
    }
    // sigma by a midpoint rule over the hemisphere of normals
    let (qu, qv) = (256usize, 512usize);
    let mut quad = Vec::with_capacity(qu * qv);
    for a in 0..qu {
        let u = (a as f64 + 0.5) / qu as f64;
        let theta = u2theta(u);
        for b in 0..qv {
            let v = (b as f64 + 0.5) / qv as f64;
            let m = dir(theta, u2phi(v));
            let w = ndf(m) * 2.0 * PI * PI * u * theta.sin() / (qu * qv) as f64;
            quad.push((m, w));
        }
    }
    let sigma_of =
        |w: DVec3| -> f64 { quad.iter().map(|(m, q)| q * m.dot(w).max(0.0)).sum::<f64>() };
    let mut sigma_t = Vec::with_capacity(nr * nc);
    for j in 0..nr {
        for i in 0..nc {
            sigma_t.push(sigma_of(dir(u2theta(node(i, nc)), u2phi(node(j, nr)))));
        }
    }
    let ndf_tab: Table<f64> = Table::interpolant(&ndf_t, nc, nr, &[], 1);
    let sigma_tab: Table<f64> = Table::interpolant(&sigma_t, nc, nr, &[], 1);
    // vndf per viewer node
    let (vr, vc) = layout.vndf_res;
    let thetas: Vec<f64> = layout.theta_i.iter().map(|&v| v as f64).collect();
    let phis: Vec<f64> = layout.phi_i.iter().map(|&v| v as f64).collect();
    let views: Vec<(f64, f64)> = phis
        .iter()
        .flat_map(|&p| thetas.iter().map(move |&t| (p, t)))
        .collect();
    let mut vndf_t = Vec::with_capacity(views.len() * vr * vc);
    for &(p, t) in &views {
        let wt = dir(t, p);
        let sigma = sigma_of(wt);
        for j in 0..vr {
            for i in 0..vc {
                let u = node(i, vc);
                let theta = u2theta(u);
                let phi = u2phi(node(j, vr)) + if isotropic { p } else { 0.0 };
                let m = dir(theta, phi);
                let d = ndf(m) * m.dot(wt).max(0.0) / sigma;
                vndf_t.push(d * 2.0 * PI * PI * u * theta.sin());
            }
        }
    }
    let axes = [phis.clone(), thetas.clone()];
    let vndf_tab: Table<f64> =
        Table::warp(&vndf_t, vc, vr, &axes).expect("the writer's vndf slices are positive");
    // spectra per viewer node
    let n = layout.sample_res;
    let mut spec = vec![0.0f64; views.len() * channels * n * n];
    let mut lum = vec![0.0f64; views.len() * n * n];
    for (cell, &(p, t)) in views.iter().enumerate() {
        let wt = dir(t, p);
        let params = [p, t];
        let ut = ((t * 2.0 / PI).sqrt(), (p + PI) / (2.0 * PI));
        let sigma = sigma_tab.eval(ut.0, ut.1, &[], 0);
        for j in 0..n {
            for i in 0..n {
                let (ux, uy) = vndf_tab.sample(node(i, n), node(j, n), &params);
                let theta_m = u2theta(ux);
                let phi_m = u2phi(uy) + if isotropic { p } else { 0.0 };
                let m = dir(theta_m, phi_m);
                let wl = 2.0 * wt.dot(m) * m - wt;
                let d = ndf_tab.eval(ux, uy, &[], 0);
                let k = j * n + i;
                if wl.z <= 0.0 || d <= 0.0 {
                    continue;
                }
                let values = f(wl, wt);
                let scale = wl.z * 4.0 * sigma / d;
                let mut sum = 0.0;
                for (c, v) in values.iter().enumerate().take(channels) {
                    let s = v * scale;
                    spec[(cell * channels + c) * n * n + k] = s;
                    sum += s;
                }
                lum[cell * n * n + k] = sum / channels as f64;
            }
        }
        let slice = &mut lum[cell * n * n..(cell + 1) * n * n];
        let mean = slice.iter().sum::<f64>() / (n * n) as f64;
        for v in slice.iter_mut() {
            *v += 0.05 * mean + 1e-12;
        }
    }
    let (np, nt) = (phis.len() as u64, thetas.len() as u64);
    let mut fields: Vec<(&str, Dtype, Vec<u64>, Vec<u8>)> = vec![
        (
            "description",
            Dtype::U8,
            vec![description.len() as u64],
            description.as_bytes().to_vec(),
        ),
        ("jacobian", Dtype::U8, vec![1], vec![1]),
        ("theta_i", Dtype::F32, vec![nt], f32_bytes(&thetas)),
        ("phi_i", Dtype::F32, vec![np], f32_bytes(&phis)),
        (
            "ndf",
            Dtype::F32,
            vec![nr as u64, nc as u64],
            f32_bytes(&ndf_t),
        ),
        (
            "sigma",
            Dtype::F32,
            vec![nr as u64, nc as u64],
            f32_bytes(&sigma_t),
        ),
        (
            "vndf",
            Dtype::F32,
            vec![np, nt, vr as u64, vc as u64],
            f32_bytes(&vndf_t),
        ),
        (
            "luminance",
            Dtype::F32,
            vec![np, nt, n as u64, n as u64],
            f32_bytes(&lum),
        ),
    ];
    let shape = vec![np, nt, channels as u64, n as u64, n as u64];
    match &layout.wavelengths {
        Some(w) => {
            let w: Vec<f64> = w.iter().map(|&v| v as f64).collect();
            fields.push((
                "wavelengths",
                Dtype::F32,
                vec![w.len() as u64],
                f32_bytes(&w),
            ));
            fields.push(("spectra", Dtype::F32, shape, f32_bytes(&spec)));
        }
        None => fields.push(("rgb", Dtype::F32, shape, f32_bytes(&spec))),
    }
    tensor::write(&fields)
}
