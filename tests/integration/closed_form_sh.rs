//! SH end to end against a closed form: a Lambert BRDF acquired as an SH data set
//! (`brdfkit::acquire`, the machinery of `brdfkit acquire`) at 2 to 8 bands, rendered
//! through the SH kernel (f32 fast path, f32 scalar oracle, f64 path) on a sphere under one
//! directional light, against the analytic image *plus the known truncation residual*.
//!
//! # The expected image
//! The acquisition stores `g(wi) = f_r cos(polar_i) = (albedo/pi) max(0, wi.z)` per view
//! texel (`includes_cosine`), independent of the view. `max(0, z)` is zonal, so its SH
//! projection keeps only the `m = 0` terms, and by the addition theorem
//! (`sum_m Y_lm(a) Y_lm(b) = (2l+1)/(4 pi) P_l(a.b)`) the projection onto `l < L` is the
//! Legendre series `max(0, z) ~ sum_{l<L} a_l P_l(z)` with
//! `a_l = (2l+1)/2 integral_{-1}^{1} max(0, x) P_l(x) dx = (2l+1)/2 integral_0^1 x P_l(x) dx`.
//! So a pixel with normal `n` under a light `l` of irradiance `E` is
//! `albedo/pi E sum_{l<L} a_l P_l(n.l)` for `n.l > 0` (the renderer drops lights below the
//! horizon) and 0 otherwise. `integral_0^1 x P_l` has the closed form
//! `1/2, 1/3` (l = 0, 1), `0` (odd l >= 3) and
//! `(-1)^(l/2+1) (l-2)! / (2^l (l/2-1)! (l/2+1)!)` (even l >= 2); the test checks it against
//! a composite Simpson rule in f64.
//!
//! `Method::Even` mirrors the data below the horizon: it expands `|z|`, whose coefficients
//! are `2 a_l` for even `l` and 0 for odd `l`. `Method::Lsq` fits the upper hemisphere only,
//! where the data is `z` itself; its expected image is the regularised solution, solved in
//! the test from the same closed-form integrals.
//!
//! # Tolerance
//! The acquisition's discretisation: `Method::Zero`/`Even` project with a Gauss-Legendre rule
//! in `cos(polar_i)` split at the horizon (48 nodes per half) times 96 azimuths, which is
//! exact for `x P_l(x)` (degree <= 9) and for the `m = 0` azimuthal terms, so the stored f32
//! coefficients are the exact `a_l` rounded once (relative 6e-8). The coefficients are the
//! same in every view texel, so the view lookup (nearest or bilinear) does not enter. What
//! is left is f32 shading arithmetic (the SH recurrence for up to 64 terms): bound
//! [`TOLERANCE`] = 1e-5 of the image peak, per pixel.

use crate::closed_form_common;

use brdfkit::acquire::{acquire, AcquireOptions, Method};
use brdfkit::brdf::Lambert;
use brdfkit::light::Light;
use brdfkit::render::{render, RenderOptions};
use closed_form_common::*;
use glam::DVec3;
use std::f64::consts::PI;

const TOLERANCE: f64 = 1e-5;
const ALBEDO: [f64; 3] = [0.9, 0.6, 0.3];

/// `P_l(x)` by Bonnet's recurrence, f64.
fn legendre(l: usize, x: f64) -> f64 {
    let (mut p0, mut p1) = (1.0, x);
    if l == 0 {
        return p0;
    }
    for k in 1..l {
        let k = k as f64;
        let p2 = ((2.0 * k + 1.0) * x * p1 - k * p0) / (k + 1.0);
        p0 = p1;
        p1 = p2;
    }
    p1
}

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// `integral_0^1 x P_l(x) dx` in closed form (module doc).
fn half_moment(l: usize) -> f64 {
    match l {
        0 => 0.5,
        1 => 1.0 / 3.0,
        l if l % 2 == 1 => 0.0,
        l => {
            let h = l / 2;
            let sign = if (h + 1) % 2 == 0 { 1.0 } else { -1.0 };
            sign * factorial(l - 2) / (2f64.powi(l as i32) * factorial(h - 1) * factorial(h + 1))
        }
    }
}

/// Legendre coefficients `a_l` of `max(0, z)` (module doc).
fn clamped_cosine_coeffs(bands: usize) -> Vec<f64> {
    (0..bands)
        .map(|l| (2 * l + 1) as f64 / 2.0 * half_moment(l))
        .collect()
}

#[test]
fn clamped_cosine_coefficients_closed_form_matches_quadrature() {
    // Composite Simpson on [0, 1], 4000 intervals: error h^4/180 max|f''''| < 1e-10 for
    // l < 12 (|P_l''''| <= l^8/384 on [-1, 1]).
    let n = 4000;
    for l in 0..12 {
        let f = |x: f64| x * legendre(l, x);
        let h = 1.0 / n as f64;
        let mut s = f(0.0) + f(1.0);
        for i in 1..n {
            s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        let q = s * h / 3.0;
        assert!(
            (q - half_moment(l)).abs() < 1e-10,
            "l = {l}: {q} vs {}",
            half_moment(l)
        );
    }
    // The series converges to max(0, z): 40 bands are within 1e-2 everywhere.
    let a = clamped_cosine_coeffs(40);
    for k in 0..=20 {
        let z = -1.0 + k as f64 / 10.0;
        let s: f64 = a.iter().enumerate().map(|(l, c)| c * legendre(l, z)).sum();
        assert!((s - z.max(0.0)).abs() < 1e-2, "z = {z}: {s}");
    }
}

/// Renders `ds` on a sphere under one directional light through the three paths and
/// returns the worst at-surface error against `albedo/pi E sum_l coeffs[l] P_l(n.l)`.
fn check(name: &str, ds: brdfkit::sh::ShDataset, coeffs: &[f64]) -> f64 {
    assert!(ds.cosine_included(), "acquired data sets store f_r cos");
    let bands = ds.bands();
    let l = unit([-0.5, 0.7, 0.6]);
    let e = DVec3::new(2.0, 3.0, 1.5);
    let scene = sphere_scene(
        32,
        48,
        48,
        Material::from(ds),
        vec![Light::Directional {
            to_light: l.as_vec3(),
            irradiance: e.as_vec3(),
        }],
    );
    // Every stored band is shaded (the acquisition declares no band threshold).
    let opts = RenderOptions {
        stats: true,
        ..RenderOptions::default()
    };
    let stats = render(&scene, &opts).stats.unwrap();
    assert_eq!((stats.sh_bands_stored, stats.sh_bands_used), (bands, bands));
    let l32 = l.as_vec3().as_dvec3();
    let series = |z: f64| -> f64 {
        coeffs
            .iter()
            .enumerate()
            .map(|(k, c)| c * legendre(k, z))
            .sum()
    };
    let expected = |h: &Hit| {
        let z = h.normal.dot(l32);
        if z <= 0.0 {
            DVec3::ZERO
        } else {
            DVec3::from(ALBEDO) / PI * e * series(z)
        }
    };
    let surfaces = renderer_surfaces(&scene);
    let mut worst = 0.0f64;
    for (path, img) in render_paths(&scene) {
        let err = compare(&img, &surfaces, |_| true, expected);
        eprintln!("{name} {bands} bands [{path}]: {err} (bound |d|/peak {TOLERANCE:e})");
        worst = worst.max(err.max_abs_over_peak);
    }
    worst
}

fn lambert() -> Lambert {
    Lambert {
        albedo: DVec3::from(ALBEDO).as_vec3(),
    }
}

#[test]
fn acquired_lambert_zero_extension_2_to_8_bands() {
    for bands in 2..=8 {
        let ds = acquire(&lambert(), &AcquireOptions::new(bands, 8, 4, Method::Zero)).unwrap();
        let worst = check("sh zero", ds, &clamped_cosine_coeffs(bands));
        assert!(worst <= TOLERANCE, "{bands} bands: {worst:.3e}");
    }
}

#[test]
fn acquired_lambert_even_extension_2_to_8_bands() {
    for bands in 2..=8 {
        let ds = acquire(&lambert(), &AcquireOptions::new(bands, 8, 4, Method::Even)).unwrap();
        let coeffs: Vec<f64> = clamped_cosine_coeffs(bands)
            .iter()
            .enumerate()
            .map(|(l, a)| if l % 2 == 0 { 2.0 * a } else { 0.0 })
            .collect();
        let worst = check("sh even", ds, &coeffs);
        assert!(worst <= TOLERANCE, "{bands} bands: {worst:.3e}");
    }
}

/// Monomial coefficients of `P_l` (Bonnet's recurrence on coefficient vectors).
fn legendre_poly(l: usize) -> Vec<f64> {
    let mut p0 = vec![1.0];
    let mut p1 = vec![0.0, 1.0];
    if l == 0 {
        return p0;
    }
    for k in 1..l {
        let kf = k as f64;
        let mut p2 = vec![0.0; k + 2];
        for (n, c) in p1.iter().enumerate() {
            p2[n + 1] += (2.0 * kf + 1.0) * c / (kf + 1.0);
        }
        for (n, c) in p0.iter().enumerate() {
            p2[n] -= kf * c / (kf + 1.0);
        }
        p0 = p1;
        p1 = p2;
    }
    p1
}

/// `integral_0^1 x^e P_a(x) P_b(x) dx` exactly from the monomial coefficients.
fn half_product(a: usize, b: usize, e: usize) -> f64 {
    let (pa, pb) = (legendre_poly(a), legendre_poly(b));
    let mut s = 0.0;
    for (i, ca) in pa.iter().enumerate() {
        for (j, cb) in pb.iter().enumerate() {
            s += ca * cb / (i + j + e + 1) as f64;
        }
    }
    s
}

/// The zonal Legendre coefficients (of `P_l`, not of `Y_l0`) of the Tikhonov-regularised
/// least-squares fit of `z` on the upper hemisphere with `bands` bands (`Method::Lsq`,
/// module doc of `brdfkit::acquire`): `(G + lambda I) c = b` over the orthonormal SH. The
/// target `z` is zonal and the hemisphere Gram matrix is block-diagonal in `m` (azimuthal
/// orthogonality), so only the `m = 0` block enters: with `Y_l0 = k_l P_l`,
/// `k_l = sqrt((2l+1)/(4 pi))`, `G_ab = 2 pi k_a k_b integral_0^1 P_a P_b`,
/// `b_a = 2 pi k_a integral_0^1 z P_a`; solved here by Cholesky in f64, independently of
/// the acquisition code.
fn lsq_coeffs(bands: usize, lambda: f64) -> Vec<f64> {
    let k = |l: usize| ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
    let n = bands;
    let mut g = vec![0.0; n * n];
    let mut b = vec![0.0; n];
    for a in 0..n {
        b[a] = 2.0 * PI * k(a) * half_product(a, 0, 1);
        for c in 0..n {
            g[a * n + c] = 2.0 * PI * k(a) * k(c) * half_product(a, c, 0);
        }
        g[a * n + a] += lambda;
    }
    // Cholesky G = L L^T, then two triangular solves.
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s = g[i * n + j] - (0..j).map(|q| l[i * n + q] * l[j * n + q]).sum::<f64>();
            l[i * n + j] = if i == j { s.sqrt() } else { s / l[j * n + j] };
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        y[i] = (b[i] - (0..i).map(|q| l[i * n + q] * y[q]).sum::<f64>()) / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (y[i] - (i + 1..n).map(|q| l[q * n + i] * x[q]).sum::<f64>()) / l[i * n + i];
    }
    // Coefficient of Y_l0 times k_l: coefficient of P_l.
    (0..n).map(|a| x[a] * k(a)).collect()
}

/// `Method::Lsq` (the default of `brdfkit acquire`, `lambda = DEFAULT_LAMBDA = 1e-6`)
/// against its own closed form ([`lsq_coeffs`]), bound [`TOLERANCE`]: the acquisition's
/// quadrature integrates the Gram matrix and the right-hand side exactly (polynomials of
/// degree <= 15 in `z` under 48 Gauss-Legendre nodes), so only f32 storage and shading
/// remain. On the upper hemisphere `z` is in the span of `l <= 1`, so the fit is the
/// untruncated Lambert image up to the Tikhonov bias; that distance is printed too (a
/// hemisphere-L2 bias of about `sqrt(lambda)/2` relative, pointwise up to ~1e-3 of the peak).
#[test]
fn acquired_lambert_least_squares_2_to_8_bands() {
    let lambda = brdfkit::acquire::DEFAULT_LAMBDA;
    for bands in 2..=8 {
        let method = Method::Lsq { lambda };
        let ds = acquire(&lambert(), &AcquireOptions::new(bands, 8, 4, method)).unwrap();
        let worst = check("sh lsq", ds.clone(), &lsq_coeffs(bands, lambda));
        assert!(worst <= TOLERANCE, "{bands} bands: {worst:.3e}");
        check(
            "sh lsq (distance to the untruncated image, not asserted)",
            ds,
            &[0.0, 1.0],
        );
    }
}

/// The check sees one band: a 3-band render against the 2-band expected image (the
/// residual of band 2, `a_2 = 5/16`) and against the untruncated Lambert image both fail.
#[test]
fn seeded_fault_wrong_band_count_fails() {
    let ds = acquire(&lambert(), &AcquireOptions::new(3, 8, 4, Method::Zero)).unwrap();
    let worst = check(
        "sh zero (expected with 2 bands)",
        ds.clone(),
        &clamped_cosine_coeffs(2),
    );
    assert!(
        worst > 100.0 * TOLERANCE,
        "a dropped band passed: {worst:.3e}"
    );
    // Untruncated: max(0, z) itself (a_1 = 1 alone is the series of z, wrong below 0
    // but the renderer only shades z > 0, where z = max(0, z)).
    let worst = check("sh zero (expected untruncated)", ds, &[0.0, 1.0]);
    assert!(
        worst > 100.0 * TOLERANCE,
        "the truncation residual was not needed: {worst:.3e}"
    );
}
