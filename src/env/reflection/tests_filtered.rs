//! Filtered importance sampling of anisotropic D-BRDFs ([`super::filtered`]) against
//! anchors computed apart from it: the sampler's pdf against the lobe and integrated by its
//! own samples (the table's normalisation), a constant probe (the answer is
//! the lobe's directional albedo by a fine quadrature over the hemisphere, plus the base's
//! `r_d`, times the radiance) with a seeded wrong pdf that must fail it, the pyramid's
//! power on every level, and the same bits for any thread count.

use super::filtered::{half_samples, FilteredSampler, PdfFault};
use super::pyramid::RadiancePyramid;
use super::Material;
use crate::brdf::{Brdf, LambertDbrdf};
use crate::conventions::{probe_texel_solid_angle, ShadingFrame};
use crate::env::{LoadOptions, Probe};
use glam::{DVec3, Vec3};
use std::sync::Arc;

/// An anisotropic Lambert + D-BRDF: Phong lobe exponents 30 (tangent) and 90 (bitangent),
/// as the library's `lindt-paper` source.
fn anisotropic() -> LambertDbrdf {
    LambertDbrdf::anisotropic_phong(30.0, 90.0, Vec3::new(0.9, 0.7, 0.3), Vec3::splat(0.1))
}

fn constant_probe(w: usize, l: [f32; 3]) -> Probe {
    Probe::from_texels(
        "constant",
        w,
        w / 2,
        vec![l; w * w / 2],
        &LoadOptions::default(),
    )
    .unwrap()
    .0
}

/// The lobe's directional albedo `integral f(l, v) cos(polar_i) dl` at the view of polar
/// angle `polar` and azimuth `azimuth` (local frame), by a midpoint rule over
/// (cos polar_i, azimuth) (800 x 1600 cells).
fn lobe_albedo(lobe: &dyn Brdf, polar: f64, azimuth: f64) -> DVec3 {
    let wo = DVec3::new(
        polar.sin() * azimuth.cos(),
        polar.sin() * azimuth.sin(),
        polar.cos(),
    );
    let (nc, na) = (800, 1600);
    let mut sum = DVec3::ZERO;
    for i in 0..nc {
        let c = (i as f64 + 0.5) / nc as f64;
        let s = (1.0 - c * c).sqrt();
        for j in 0..na {
            let a = std::f64::consts::TAU * (j as f64 + 0.5) / na as f64;
            let wi = DVec3::new(s * a.cos(), s * a.sin(), c);
            sum += lobe.eval_f64(wi, wo) * c;
        }
    }
    sum * (std::f64::consts::TAU / (nc * na) as f64)
}

#[test]
fn the_samplers_pdf_integrates_the_table_and_follows_the_lobe() {
    let m = anisotropic();
    let s = half_samples(&m.lobe, 4096);
    assert!(s.iter().all(|x| x.h.z >= 0.0 && x.pdf > 0.0));
    // E[p (h.n) / pdf] = 1: the table's normalisation (the D-BRDF's module doc), integrated
    // by the sampler's own samples and pdf.
    let n = s.len() as f64;
    let norm: f64 = s
        .iter()
        .map(|x| m.lobe.p(x.h) as f64 * x.h.z as f64 / x.pdf as f64)
        .sum::<f64>()
        / n;
    assert!((norm - 1.0).abs() < 0.01, "E[p cos / pdf] = {norm}");
    // Where the lobe is above a tenth of its peak, the pdf is p (h.n) to the difference
    // between the bilinear table and its piecewise-constant texels.
    let peak = m
        .lobe
        .octahedral_table()
        .iter()
        .copied()
        .fold(0.0f32, f32::max);
    for x in &s {
        let want = m.lobe.p(x.h) * x.h.z;
        if m.lobe.p(x.h) > 0.1 * peak {
            let r = x.pdf / want;
            assert!((0.8..1.25).contains(&r), "{}: pdf {} vs {want}", x.h, x.pdf);
        }
    }
}

/// The sampler's term under a constant probe against `(albedo + r_d) L` at views over the
/// hemisphere; returns the largest relative error.
fn constant_probe_error(fault: PdfFault, samples: usize) -> f64 {
    let l = [1.0f32, 0.5, 0.25];
    let m = anisotropic();
    let material = Material::LambertDbrdf(Arc::new(m.clone()));
    let probe = constant_probe(128, l);
    let f = FilteredSampler::new(&probe, &material, &[], 1.0, samples, 16, fault).unwrap();
    let frame = ShadingFrame::from_normal(Vec3::new(0.3, 0.8, -0.52).normalize());
    let mut worst = 0.0f64;
    for (polar, azimuth) in [(20.0f64, 0.0f64), (40.0, 1.0), (55.0, 2.2), (65.0, 4.0)] {
        let (p, a) = (polar.to_radians(), azimuth);
        let wo = Vec3::new(
            (p.sin() * a.cos()) as f32,
            (p.sin() * a.sin()) as f32,
            p.cos() as f32,
        );
        let want =
            (lobe_albedo(&m.lobe, p, a) + m.rd.as_dvec3()) * DVec3::from_array(l.map(|x| x as f64));
        let got = f.radiance(&frame, wo).as_dvec3();
        let rel = ((got - want).abs() / want).max_element();
        eprintln!("polar {polar} azimuth {azimuth}: {got} vs {want} ({rel:.4})");
        worst = worst.max(rel);
    }
    worst
}

#[test]
fn constant_probe_gives_the_albedo_and_a_wrong_pdf_fails() {
    let e = constant_probe_error(PdfFault::None, 64);
    assert!(e < 0.03, "N = 64: {e}");
    // The reflection's Jacobian dropped: the check must see it.
    let bad = constant_probe_error(PdfFault::JacobianDropped, 64);
    assert!(bad > 0.2, "a wrong pdf passed: {bad}");
}

#[test]
fn the_pyramid_keeps_the_power_on_every_level() {
    let (w, h) = (64, 32);
    let power: Vec<[f64; 3]> = (0..w * h)
        .map(|i| {
            let o = probe_texel_solid_angle(i / w, w, h);
            [o * (1.0 + (i % 7) as f64), o * 0.5, o * (i / w) as f64]
        })
        .collect();
    let total: f64 = power.iter().map(|p| p[0]).sum();
    let p = RadiancePyramid::from_power(&power, w, h);
    assert_eq!(p.levels(), 6, "64 x 32 down to 2 x 1");
    // Constant radiance stays the constant on every level, at every lookup.
    let ones: Vec<[f64; 3]> = (0..w * h)
        .map(|i| [probe_texel_solid_angle(i / w, w, h); 3])
        .collect();
    let c = RadiancePyramid::from_power(&ones, w, h);
    for k in 0..c.levels() {
        for (u, v) in [(0.01f32, 0.0f32), (0.5, 0.5), (0.99, 1.0), (0.3, 0.97)] {
            let x = c.lookup(u, v, k as f32 + 0.25);
            assert!((x - Vec3::ONE).abs().max_element() < 1e-5, "{k}: {x}");
        }
    }
    // The red channel's power through the pyramid's radiance: the same on each level
    // (summed at the texel centres' lookups, each times its texel's solid angle).
    for k in 0..p.levels() {
        let (lw, lh) = (w >> k, h >> k);
        let mut s = 0.0f64;
        for row in 0..lh {
            for col in 0..lw {
                let (u, v) = (
                    (col as f32 + 0.5) / lw as f32,
                    (row as f32 + 0.5) / lh as f32,
                );
                s += p.lookup(u, v, k as f32).x as f64 * probe_texel_solid_angle(row, lw, lh);
            }
        }
        assert!((s / total - 1.0).abs() < 1e-5, "level {k}: {s} vs {total}");
    }
}

#[test]
fn the_same_bits_for_any_thread_count() {
    let m = Material::LambertDbrdf(Arc::new(anisotropic()));
    let probe = {
        let (w, h) = (64, 32);
        let texels = (0..w * h)
            .map(|i| {
                [
                    1.0 + (i % 13) as f32,
                    0.5 + (i % 5) as f32,
                    (i / w) as f32 * 0.1,
                ]
            })
            .collect();
        Probe::from_texels("varied", w, h, texels, &LoadOptions::default())
            .unwrap()
            .0
    };
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                FilteredSampler::new(&probe, &m, &[3, 70], 1.0, 32, 8, PdfFault::None).unwrap()
            })
    };
    let (a, b) = (run(1), run(3));
    assert_eq!(a.samples(), b.samples());
    let frame = ShadingFrame::from_normal(Vec3::new(0.2, 0.9, 0.1).normalize());
    let wo = Vec3::new(0.5, 0.1, 0.86).normalize();
    assert_eq!(
        a.radiance(&frame, wo).to_array().map(f32::to_bits),
        b.radiance(&frame, wo).to_array().map(f32::to_bits)
    );
}
