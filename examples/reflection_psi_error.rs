//! How much of a reflection table's error is its Fourier series in `psi` (the normal's
//! angle about the reflected direction; `src/env/reflection/mod.rs`, "Parameterisation"),
//! and how the exact set's size moves it, for people: a study without a bake.
//!
//! ```sh
//! cargo run --release --example reflection_psi_error -- [PROBE] [exponent=E] [kd=K] \
//!     [ks=K] [points=N] [k=K,K...] [bands=LO-HI,LO-HI...]
//! ```
//!
//! For a Blinn-Phong of exponent `E` (default 200) and grey albedos `kd`, `ks` (default the
//! sweep's glossy class, 0.05 and 0.9) under `assets/probes/PROBE.exr` (default studio), at
//! `N` points per band (default 64: reflected direction uniform on the sphere, view polar
//! angle uniform in the band, degrees; default bands 0-60, 60-70, 70-80, 80-89.9), the exact
//! f64 sum over every texel of the full-resolution probe is taken at 32 values of psi. The
//! residual's lobe part (`f - kd/pi` over the texels outside the `K` brightest, which a
//! table would hold in its series) is projected onto Fourier orders 2 (from 8 equally spaced
//! samples, as the bake does) and 3, 4, 6 and 8 (from all 32), and each order's
//! truncation error at the 32 samples is divided by the full radiance there (every texel,
//! the whole BRDF: what a pixel shows). Printed per band, exact-set size and order: the
//! relative RMSE and the 99th percentile of those (point, psi) errors. Only the series is
//! approximated here: the r-grid, the slices and the residual's downsampling are exact, so
//! the numbers isolate the `psi` order.

use brdfkit::conventions::{
    probe_direction, probe_texel_solid_angle, texel_center_f64, view_frame_f64,
};
use brdfkit::env::probe::{LoadOptions, Probe};
use brdfkit::env::reflection::build::sample_normal_view;
use brdfkit::env::transfer::brightest_texels;
use brdfkit::scene::{Scene, SceneFile};
use glam::DVec3;
use rayon::prelude::*;
use std::path::Path;

/// Psi samples of the exact sums per point (order 2 projects from 8 of them, the others
/// from all).
const PSI: usize = 32;
const ORDERS: [usize; 5] = [2, 3, 4, 6, 8];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |key: &str| args.iter().find_map(|a| a.strip_prefix(key));
    let probe_name = args
        .iter()
        .find(|a| !a.contains('='))
        .map_or("studio", |s| s.as_str());
    let exponent: f64 = get("exponent=").map_or(200.0, |s| s.parse().unwrap());
    let kd: f64 = get("kd=").map_or(0.05, |s| s.parse().unwrap());
    let ks: f64 = get("ks=").map_or(0.9, |s| s.parse().unwrap());
    let points: usize = get("points=").map_or(64, |s| s.parse().unwrap());
    let ks_list: Vec<usize> = get("k=").map_or(vec![64, 256, 1024], |l| {
        l.split(',').map(|x| x.parse().unwrap()).collect()
    });
    let bands: Vec<(f64, f64)> = get("bands=").map_or(
        vec![(0.0, 60.0), (60.0, 70.0), (70.0, 80.0), (80.0, 89.9)],
        |l| {
            l.split(',')
                .map(|b| {
                    let (lo, hi) = b.split_once('-').unwrap();
                    (lo.parse().unwrap(), hi.parse().unwrap())
                })
                .collect()
        },
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 8\n[material]\nkind = \"blinn-phong\"\n\
         exponent = {exponent}\nkd = [{kd}, {kd}, {kd}]\nks = [{ks}, {ks}, {ks}]\n"
    );
    let scene = Scene::resolve(&SceneFile::parse(&text).unwrap(), root).unwrap();
    let material = scene.material;
    let lambert = material.lambertian_term().as_dvec3();
    let (probe, _) = Probe::load(
        &root.join(format!("assets/probes/{probe_name}.exr")),
        &LoadOptions::default(),
    )
    .unwrap();
    let (w, h) = (probe.width(), probe.height());
    let dir: Vec<DVec3> = (0..w * h)
        .map(|i| probe_direction(texel_center_f64(i % w, w), texel_center_f64(i / w, h)))
        .collect();
    let power: Vec<DVec3> = probe
        .texels()
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let o = probe_texel_solid_angle(i / w, w, h);
            DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * o
        })
        .collect();
    // Each texel's rank among the brightest (usize::MAX beyond the largest K).
    let mut rank = vec![usize::MAX; w * h];
    for k in &ks_list {
        for &i in &brightest_texels(&probe, *k) {
            rank[i] = rank[i].min(*k);
        }
    }
    println!(
        "Blinn-Phong exponent {exponent}, kd {kd}, ks {ks}, probe {probe_name}, {points} points x {PSI} psi per band"
    );
    println!("| view polar (deg) | exact K | order | rel RMSE | p99 |");
    println!("|---|---|---|---|---|");
    let mut rng = 0x5eed_u64;
    for &(lo, hi) in &bands {
        let pts: Vec<(DVec3, f64)> = (0..points)
            .map(|_| {
                let (u1, u2, u3) = (next(&mut rng), next(&mut rng), next(&mut rng));
                let z = 1.0 - 2.0 * u1;
                let s = (1.0 - z * z).max(0.0).sqrt();
                let phi = std::f64::consts::TAU * u2;
                let r = DVec3::new(s * phi.cos(), z, s * phi.sin());
                (r, (lo + (hi - lo) * u3).to_radians())
            })
            .collect();
        // Per point and psi: the full radiance's luminance, and per K the lobe part's.
        let sums: Vec<Vec<(f64, Vec<f64>)>> = pts
            .par_iter()
            .map(|&(r, polar)| {
                let axis = if r.y.abs() > 0.8 { DVec3::Z } else { DVec3::Y };
                let t = (axis - axis.dot(r) * r).normalize();
                let b = r.cross(t);
                (0..PSI)
                    .map(|m| {
                        let psi = std::f64::consts::TAU * m as f64 / PSI as f64;
                        let (n, v) = sample_normal_view(r, polar, psi, (t, b));
                        let (x, y, wo) = view_frame_f64(n, v);
                        let mut full = DVec3::ZERO;
                        let mut lobe = vec![DVec3::ZERO; ks_list.len()];
                        for (i, (l, p)) in dir.iter().zip(&power).enumerate() {
                            let z = l.dot(n);
                            if z <= 0.0 {
                                continue;
                            }
                            let f = material.eval_f64(DVec3::new(l.dot(x), l.dot(y), z), wo);
                            full += f * z * *p;
                            let part = (f - lambert) * z * *p;
                            for (q, k) in lobe.iter_mut().zip(&ks_list) {
                                if rank[i] > *k {
                                    *q += part;
                                }
                            }
                        }
                        (lum(full), lobe.into_iter().map(lum).collect())
                    })
                    .collect()
            })
            .collect();
        for (ki, k) in ks_list.iter().enumerate() {
            for &ord in &ORDERS {
                // As the bake: order 2 from 8 samples; the others from all 32.
                let step = if ord == 2 { PSI / 8 } else { 1 };
                let (mut se, mut sy) = (0.0, 0.0);
                let mut rel = Vec::new();
                for point in &sums {
                    let y: Vec<f64> = point.iter().map(|s| s.1[ki]).collect();
                    let coeffs = project(&y, step, ord);
                    for (m, s) in point.iter().enumerate() {
                        let psi = std::f64::consts::TAU * m as f64 / PSI as f64;
                        let e = series(&coeffs, psi) - y[m];
                        se += e * e;
                        sy += s.0 * s.0;
                        rel.push(e.abs() / s.0.abs().max(1e-30));
                    }
                }
                rel.sort_by(f64::total_cmp);
                let p99 = rel[((0.99 * rel.len() as f64) as usize).min(rel.len() - 1)];
                println!(
                    "| {lo}-{hi} | {k} | {ord} | {:.3}% | {:.2}% |",
                    100.0 * (se / sy).sqrt(),
                    100.0 * p99
                );
            }
        }
    }
}

/// Fourier coefficients `[a0, a1, b1, ..., a_ord, b_ord]` of `y` (samples at `2 pi m / len`)
/// from every `step`-th sample, as the bake projects.
fn project(y: &[f64], step: usize, ord: usize) -> Vec<f64> {
    let used: Vec<(f64, f64)> = (0..y.len())
        .step_by(step)
        .map(|m| (std::f64::consts::TAU * m as f64 / y.len() as f64, y[m]))
        .collect();
    let n = used.len() as f64;
    let mut c = vec![0.0; 2 * ord + 1];
    for &(psi, v) in &used {
        c[0] += v / n;
        for j in 1..=ord {
            let (s, co) = (j as f64 * psi).sin_cos();
            c[2 * j - 1] += 2.0 / n * co * v;
            c[2 * j] += 2.0 / n * s * v;
        }
    }
    c
}

/// The series of `c` ([`project`]) at `psi`.
fn series(c: &[f64], psi: f64) -> f64 {
    let mut v = c[0];
    for j in 1..=(c.len() - 1) / 2 {
        let (s, co) = (j as f64 * psi).sin_cos();
        v += c[2 * j - 1] * co + c[2 * j] * s;
    }
    v
}

/// Rec. 709 luminance.
fn lum(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// SplitMix64 in [0, 1).
fn next(s: &mut u64) -> f64 {
    *s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *s;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}
