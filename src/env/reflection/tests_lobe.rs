//! The bake's tabulated integrand ([`super::lobe`]) against the material's own f64
//! evaluation: the radial tables' measured bounds against the closed-form interpolation
//! bound, and the bake's sums through the tables against exact sums within the bound the
//! module doc states (with seeded faults that must fail the same check: the table of a 2%
//! different Blinn-Phong exponent, of a 25% wider D-BRDF lobe, a D-BRDF without Fresnel).

use super::build::{lobe_sum, radiance_sum, sample_normal_view, Texels};
use super::lobe::{Lobe, CUT, RADIAL_INTERVALS};
use super::table::{chart_frame, chart_is_z};
use crate::brdf::{BlinnPhong, Brdf, LambertDbrdf};
use crate::material::Material;
use glam::{DVec3, Vec3};
use std::sync::Arc;

/// The D-BRDF lobes' `R_s`; the seeded faults are a table of a 25% wider lobe and a lobe
/// whose Fresnel term is left out (`R_s = 1`).
const RS: Vec3 = Vec3::new(0.9, 0.6, 0.3);

fn blinn_phong(exponent: f32) -> Material {
    Material::BlinnPhong(BlinnPhong {
        kd: Vec3::new(0.3, 0.2, 0.1),
        ks: Vec3::new(0.2, 0.25, 0.3),
        exponent,
    })
}

fn lambert_dbrdf(exponent: f32, rs: Vec3) -> Material {
    Material::LambertDbrdf(Arc::new(LambertDbrdf::anisotropic_phong(
        exponent,
        exponent,
        rs,
        Vec3::new(0.1, 0.1, 0.2),
    )))
}

/// 6000 directions on a Fibonacci sphere with a smooth coloured power and two bright
/// spots, none on an axis.
fn texels() -> Texels {
    let m = 6000;
    let mut t = Texels::default();
    for k in 0..m {
        let z = 1.0 - 2.0 * (k as f64 + 0.5) / m as f64;
        let s = (1.0 - z * z).sqrt();
        let a = k as f64 * 2.399_963_229_728_653;
        let d = DVec3::new(s * a.cos(), z, s * a.sin());
        let base = 1e-3 * (1.2 + (3.0 * d.x + 1.0).sin());
        let spot = |c: DVec3, e: f64| if d.dot(c.normalize()) > 0.995 { e } else { 0.0 };
        let p =
            base + spot(DVec3::new(0.3, 0.8, 0.2), 0.05) + spot(DVec3::new(-0.6, 0.1, 0.5), 0.02);
        t.push(d, [p, 0.8 * p, 0.6 * p]);
    }
    t
}

/// (normal, view) pairs: views from 3 to 89.9 degrees, normals spread over the sphere.
fn pairs() -> Vec<(DVec3, DVec3)> {
    (0..40)
        .map(|k| {
            let a = k as f64 * 2.399_96;
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / 40.0;
            let s = (1.0 - z * z).sqrt();
            let n = DVec3::new(s * a.cos(), z, s * a.sin());
            let polar = (3.0 + 2.2 * k as f64).min(89.9).to_radians();
            let t = n.any_orthonormal_vector();
            let b = n.cross(t);
            let phi = 1.3 * k as f64;
            let v = polar.cos() * n + polar.sin() * (phi.cos() * t + phi.sin() * b);
            (n, v.normalize())
        })
        .collect()
}

/// `sum P w(l.n)` over the texels above `n`'s horizon, per channel.
fn weighted_power(texels: &Texels, n: DVec3, w: impl Fn(f64) -> f64) -> DVec3 {
    texels
        .dir
        .iter()
        .zip(&texels.power)
        .filter(|(l, _)| l.dot(n) > 0.0)
        .map(|(l, p)| w(l.dot(n)) * DVec3::from_array(*p))
        .sum()
}

#[test]
fn blinn_phong_tables_measure_below_the_closed_form_interpolation_bound() {
    for s in [1.0f32, 50.0, 200.0, 500.0, 10_000.0] {
        let m = blinn_phong(s);
        let lobe = Lobe::new(&m, DVec3::ZERO);
        let table = lobe.table().expect("Blinn-Phong is tabulated");
        // Interpolation over [0, cut] in x (g(x) = (1 - x)^s, |g''| <= s (s - 1)), plus the
        // tail cut to zero below CUT of the peak.
        let delta = table.cut() / RADIAL_INTERVALS as f64;
        let s64 = s as f64;
        let closed = delta * delta * s64 * (s64 - 1.0) / 8.0 + CUT;
        assert!(
            table.bound() <= closed * 1.001 && (table.bound() > 0.0 || s == 1.0),
            "s = {s}: measured {:e} against delta^2 s (s - 1) / 8 + CUT = {closed:e}",
            table.bound()
        );
        assert_eq!(table.spread(), 0.0);
        // The variable: x = 1 - cos(polar_h), so (n.h)^s at polar_h = 0.1 rad.
        let want = 0.1f64.cos().powf(s64);
        assert!(
            (table.at(1.0 - 0.1f64.cos()) - want).abs() <= closed * 1.001,
            "s = {s}"
        );
    }
}

#[test]
fn lobe_sums_agree_with_exact_sums_within_the_stated_bound_and_a_seeded_fault_fails() {
    let texels = texels();
    for (m, wrong, peak) in [
        (blinn_phong(50.0), blinn_phong(51.0), None),
        (blinn_phong(500.0), blinn_phong(510.0), None),
        (lambert_dbrdf(40.0, RS), lambert_dbrdf(50.0, RS), Some(())),
        (
            lambert_dbrdf(300.0, RS),
            lambert_dbrdf(300.0, Vec3::ONE),
            Some(()),
        ),
    ] {
        let minus = m.lambertian_term().as_dvec3();
        let lobe = Lobe::new(&m, minus);
        let faulty = Lobe::new(&wrong, minus);
        let table = lobe.table().expect("tabulated");
        // Largest lobe factor per pair (module doc): k_s (s + 8) / (8 pi) for Blinn-Phong,
        // c max(p) max(1, R_s) for a D-BRDF (cos(polar_i) / denominator <= 1).
        let f_max = match (&m, peak) {
            (Material::BlinnPhong(b), None) => {
                b.ks.max_element() as f64 * (b.exponent as f64 + 8.0) / (8.0 * std::f64::consts::PI)
            }
            (Material::LambertDbrdf(d), Some(())) => {
                d.lobe.max_cosine_weighted().unwrap().max_element() as f64
            }
            _ => unreachable!("the list above pairs them"),
        };
        let rel = table.bound() + table.spread();
        let mut fault_exceeds = false;
        let (mut worst, mut worst_fault) = (0.0f64, 0.0f64);
        for (n, v) in pairs() {
            let exact = radiance_sum(&m, false, minus, n, v, &texels);
            let got = lobe_sum(&lobe, false, n, v, &texels);
            // Blinn-Phong's error carries cos(polar_i); a D-BRDF's is bounded without it.
            let weight = if peak.is_none() {
                weighted_power(&texels, n, |z| z)
            } else {
                weighted_power(&texels, n, |_| 1.0)
            };
            let allowed = rel * f_max * weight.max_element() + 1e-15;
            let diff = (got - exact).abs().max_element();
            assert!(
                diff <= allowed,
                "{}: |{got} - {exact}| = {diff:e} > {allowed:e} (n {n}, v {v})",
                m.name()
            );
            let bad = (lobe_sum(&faulty, false, n, v, &texels) - exact)
                .abs()
                .max_element();
            fault_exceeds |= bad > allowed;
            worst = worst.max(diff / allowed);
            worst_fault = worst_fault.max(bad / allowed);
        }
        println!(
            "{} bound {:e} spread {:e}: worst {worst:.3} of the allowed, fault {worst_fault:.3}",
            m.name(),
            table.bound(),
            table.spread()
        );
        assert!(fault_exceeds, "{}: the seeded fault passed", m.name());
    }
}

#[test]
fn other_materials_keep_the_exact_sum() {
    let m = Material::Phong(crate::brdf::Phong {
        kd: Vec3::splat(0.2),
        ks: Vec3::splat(0.5),
        exponent: 80.0,
    });
    let lobe = Lobe::new(&m, DVec3::ZERO);
    assert!(lobe.table().is_none());
    let texels = texels();
    for (n, v) in pairs() {
        assert_eq!(
            lobe_sum(&lobe, false, n, v, &texels),
            radiance_sum(&m, false, DVec3::ZERO, n, v, &texels)
        );
    }
}

/// Texels of `texels` with `l.r > c`, in order.
fn kept(texels: &Texels, r: DVec3, c: f64) -> Texels {
    let mut out = Texels::default();
    for (l, p) in texels.dir.iter().zip(&texels.power) {
        if l.dot(r) > c {
            out.push(*l, *p);
        }
    }
    out
}

#[test]
fn culled_texels_change_no_sum_and_a_tighter_cull_would() {
    let texels = texels();
    let mut tighter_differs = false;
    for m in [
        blinn_phong(200.0),
        blinn_phong(500.0),
        lambert_dbrdf(300.0, RS),
    ] {
        let lobe = Lobe::new(&m, m.lambertian_term().as_dvec3());
        let c = lobe.cull_cos().expect("a sharp lobe has a zero tail");
        assert!(c > 0.0 && c < 0.9, "{}: cos {c}", m.name());
        // The seeded fault: the cut angle taken as the half vector's (no factor 2).
        let tight = 1.0 - lobe.table().unwrap().cut();
        for k in 0..12 {
            let a = k as f64 * 2.399_96;
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / 12.0;
            let s = (1.0 - z * z).sqrt();
            let r = DVec3::new(s * a.cos(), z, s * a.sin());
            let (near, far) = (kept(&texels, r, c), kept(&texels, r, tight));
            for polar in [0.0f64, 30.0, 70.0, 85.0, 89.9] {
                for psi in [0.0f64, 2.0, 4.0] {
                    let (n, v) = sample_normal_view(
                        r,
                        polar.to_radians(),
                        psi,
                        chart_frame(r, chart_is_z(r)),
                    );
                    // The culled texels add exact zeros; the kept ones move between the
                    // sums' lanes (sums.rs), so the totals agree to rounding.
                    let all = lobe_sum(&lobe, false, n, v, &texels);
                    let off = |t: &Texels| {
                        let d = (lobe_sum(&lobe, false, n, v, t) - all).abs().max_element();
                        d / all.abs().max_element().max(1e-300)
                    };
                    assert!(off(&near) <= 1e-12, "{}: {:e}", m.name(), off(&near));
                    tighter_differs |= off(&far) > 1e-6;
                }
            }
        }
    }
    assert!(tighter_differs, "the tighter cull changed no sum");
    // No cull where the integrand keeps a Lambertian term or the lobe's cut is at 90
    // degrees of the half vector (exponent 1: 4.9e-4 of the peak at the last node).
    let m = blinn_phong(200.0);
    assert!(Lobe::new(&m, DVec3::ZERO).cull_cos().is_none());
    let wide = blinn_phong(1.0);
    assert!(Lobe::new(&wide, wide.lambertian_term().as_dvec3())
        .cull_cos()
        .is_none());
}

#[test]
fn frame_sums_on_every_lane_path_have_the_scalar_sums_bits() {
    use super::sums::{frame_sum, frame_sum_scalar, FrameTexels};
    use crate::lanes::{Dispatch, KernelPath};
    use std::io::Write;
    for (path, needs) in KernelPath::unavailable() {
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED kernel path {}: frame_sums_on_every_lane_path_have_the_scalar_sums_bits: \
             this CPU lacks {needs}",
            path.name()
        );
    }
    let texels = texels();
    let mut compared = 0;
    for m in [blinn_phong(200.0), lambert_dbrdf(300.0, RS)] {
        // The Lambertian part held apart (the shipped bake: chunks past the lobe skipped)
        // and kept in the sums.
        for minus in [m.lambertian_term().as_dvec3(), DVec3::ZERO] {
            let lobe = Lobe::new(&m, minus);
            for k in 0..6 {
                let a = k as f64 * 2.399_96;
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / 6.0;
                let s = (1.0 - z * z).sqrt();
                let r = DVec3::new(s * a.cos(), z, s * a.sin());
                let (t, b) = chart_frame(r, chart_is_z(r));
                // 6000 texels: a multiple of the lanes; drop one so the padding is used.
                let n = texels.dir.len() - 1;
                let f = FrameTexels::new(&texels.dir[..n], &texels.power[..n], r, t, b);
                for polar in [0.0f64, 30.0, 70.0, 89.9] {
                    for psi in [0.0f64, 2.0, 4.0] {
                        let (so, co) = polar.to_radians().sin_cos();
                        let (sp, cp) = psi.sin_cos();
                        for cosine in [false, true] {
                            let want =
                                frame_sum_scalar(&lobe.form, cosine, &f, co, so * cp, so * sp)
                                    .expect("a tabulated lobe");
                            for path in KernelPath::available() {
                                let got = frame_sum(
                                    Dispatch::choose(path).unwrap(),
                                    &lobe.form,
                                    cosine,
                                    &f,
                                    co,
                                    so * cp,
                                    so * sp,
                                )
                                .unwrap();
                                assert_eq!(
                                    got.to_array().map(f64::to_bits),
                                    want.to_array().map(f64::to_bits),
                                    "{} on {}: polar {polar}, psi {psi}",
                                    m.name(),
                                    path.name()
                                );
                                compared += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(
        compared >= 2 * 2 * 6 * 4 * 3 * 2,
        "{compared} sums compared"
    );
}
