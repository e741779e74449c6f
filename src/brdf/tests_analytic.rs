//! Shared checks for the analytic models: reciprocity and white-furnace energy bounds.

use super::ashikhmin_shirley::AshikhminShirley;
use super::dbrdf::DBrdf;
use super::phong::Phong;
use super::{Brdf, Lambert};
use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng};
use std::f64::consts::PI;

fn rand_hemi(rng: &mut impl Rng) -> Vec3 {
    let z: f32 = rng.gen_range(0.02..1.0);
    let a: f32 = rng.gen_range(0.0..std::f32::consts::TAU);
    let s = (1.0 - z * z).sqrt();
    Vec3::new(s * a.cos(), s * a.sin(), z)
}

fn models() -> Vec<Box<dyn Brdf>> {
    let aniso = |h: Vec3| {
        let s2 = (h.x * h.x + h.y * h.y).max(1e-12);
        let e = (10.0 * h.x * h.x + 100.0 * h.y * h.y) / s2;
        h.z.max(0.0).powf(e)
    };
    vec![
        Box::new(Phong {
            kd: Vec3::new(0.5, 0.3, 0.1),
            ks: Vec3::new(0.4, 0.5, 0.6),
            exponent: 30.0,
        }),
        Box::new(AshikhminShirley {
            nu: 10.0,
            nv: 200.0,
            rs: Vec3::new(0.05, 0.5, 0.9),
            rd: Vec3::new(0.8, 0.4, 0.1),
        }),
        Box::new(DBrdf::from_fn(64, 32, Vec3::new(0.04, 0.5, 1.0), aniso)),
    ]
}

#[test]
fn analytic_models_are_reciprocal() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
    for m in models() {
        for _ in 0..3000 {
            let (a, b) = (rand_hemi(&mut rng), rand_hemi(&mut rng));
            let (x, y) = (m.eval(a, b), m.eval(b, a));
            let tol = 1e-5 * x.abs().max(y.abs()).max_element().max(1e-3);
            assert!(
                (x - y).abs().max_element() <= tol,
                "{}: f({a},{b}) = {x} vs {y}",
                m.name()
            );
            assert!(x.min_element() >= 0.0 && x.is_finite());
        }
        let below = Vec3::new(0.3, 0.2, -0.5).normalize();
        assert_eq!(m.eval(below, Vec3::Z), Vec3::ZERO);
        assert_eq!(m.eval(Vec3::Z, below), Vec3::ZERO);
    }
}

/// Directional albedo `integral f(wi, wo) wi.z dω_i` (RGB, max channel) by a midpoint rule
/// over the *half vector* (`dω_i = 4 (wo.h) dω_h`), which resolves specular lobes around n.
pub(crate) fn albedo_max(m: &dyn Brdf, wo: Vec3, n_pol: usize, n_az: usize) -> f64 {
    let wod = wo.as_dvec3();
    let mut acc = DVec3::ZERO;
    for j in 0..n_pol {
        let (t0, t1) = (
            j as f64 / n_pol as f64 * PI / 2.0,
            (j + 1) as f64 / n_pol as f64 * PI / 2.0,
        );
        let th = 0.5 * (t0 + t1);
        let dw = (t0.cos() - t1.cos()) * 2.0 * PI / n_az as f64;
        for i in 0..n_az {
            let ph = (i as f64 + 0.5) / n_az as f64 * 2.0 * PI;
            let h = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            let oh = wod.dot(h);
            if oh <= 0.0 {
                continue;
            }
            let wi = 2.0 * oh * h - wod;
            if wi.z <= 0.0 {
                continue;
            }
            let f = m.eval(wi.as_vec3(), wo).as_dvec3();
            let c = if m.includes_cosine() { 1.0 } else { wi.z };
            acc += f * c * 4.0 * oh * dw;
        }
    }
    acc.max_element()
}

#[test]
fn white_furnace_albedo_at_most_one() {
    let furnace: Vec<Box<dyn Brdf>> = vec![
        Box::new(Lambert { albedo: Vec3::ONE }),
        Box::new(Phong {
            kd: Vec3::splat(0.3),
            ks: Vec3::splat(0.7),
            exponent: 20.0,
        }),
        Box::new(Phong {
            kd: Vec3::ZERO,
            ks: Vec3::ONE,
            exponent: 1.0,
        }),
        Box::new(AshikhminShirley {
            nu: 10.0,
            nv: 100.0,
            rs: Vec3::ONE,
            rd: Vec3::ZERO,
        }),
        Box::new(AshikhminShirley {
            nu: 50.0,
            nv: 50.0,
            rs: Vec3::splat(0.05),
            rd: Vec3::ONE,
        }),
        Box::new(DBrdf::from_fn(64, 32, Vec3::ONE, |h| h.z.powf(20.0))),
        Box::new(DBrdf::from_fn(64, 32, Vec3::ONE, |_| 1.0)),
    ];
    for m in &furnace {
        let mut worst = 0.0f64;
        for k in 0..12 {
            let pol = (k as f32 + 0.5) / 12.0 * 1.5;
            let wo = Vec3::new(pol.sin() * 0.6, pol.sin() * 0.8, pol.cos());
            let a = albedo_max(m.as_ref(), wo, 160, 160);
            worst = worst.max(a);
        }
        eprintln!("white furnace: {} max albedo {worst:.5}", m.name());
        assert!(worst <= 1.0 + 5e-3, "{}: max albedo {worst}", m.name());
    }
    // The Lambert check shows the quadrature itself is accurate (albedo exactly 1).
    let a = albedo_max(
        &Lambert { albedo: Vec3::ONE },
        Vec3::new(0.0, 0.6, 0.8),
        160,
        160,
    );
    assert!((a - 1.0).abs() < 2e-3, "quadrature error {a}");
}

/// `Brdf::eval_f64` agrees with the f32 `eval` to f32 rounding, amplified by the model's
/// condition number: `|f64 - f32| <= 32 eps (1 + k) |f|` with `eps = 2^-24` and `k` the
/// largest exponent the model raises a cosine to (the relative error of `x^k` is `k` times
/// that of `x`); the D-BRDF's `k` is its table's (anisotropic Phong up to 100) exponent.
/// Same f32 directions promoted for both, random over the hemisphere down to z = 0.02.
/// Relative to `max(|f|, 1e-3 peak)`: where a tabulated lobe spans many orders of magnitude
/// inside one texel, a value near zero is a blend dominated by a texel of tiny weight, and
/// its relative error is that of the weight, not of the value.
#[test]
fn eval_f64_agrees_with_eval_to_f32_rounding() {
    let aniso = |h: Vec3| {
        let s2 = (h.x * h.x + h.y * h.y).max(1e-12);
        let e = (10.0 * h.x * h.x + 100.0 * h.y * h.y) / s2;
        h.z.max(0.0).powf(e)
    };
    let cases: Vec<(Box<dyn Brdf>, f64)> = vec![
        (
            Box::new(Lambert {
                albedo: Vec3::new(0.8, 0.5, 0.2),
            }),
            0.0,
        ),
        (
            Box::new(super::BlinnPhong {
                kd: Vec3::new(0.5, 0.3, 0.1),
                ks: Vec3::new(0.4, 0.5, 0.6),
                exponent: 60.0,
            }),
            60.0,
        ),
        (
            Box::new(Phong {
                kd: Vec3::new(0.5, 0.3, 0.1),
                ks: Vec3::new(0.4, 0.5, 0.6),
                exponent: 30.0,
            }),
            30.0,
        ),
        (
            Box::new(AshikhminShirley {
                nu: 10.0,
                nv: 200.0,
                rs: Vec3::new(0.05, 0.5, 0.9),
                rd: Vec3::new(0.8, 0.4, 0.1),
            }),
            200.0,
        ),
        (
            Box::new(DBrdf::from_fn(64, 32, Vec3::new(0.04, 0.5, 1.0), aniso)),
            100.0,
        ),
        (Box::new(DBrdf::from_fn(16, 8, Vec3::ONE, |_| 1.0)), 0.0),
    ];
    let eps = f32::EPSILON as f64 / 2.0;
    let mut rng = rand_pcg::Pcg64::seed_from_u64(17);
    for (m, k) in &cases {
        let pairs: Vec<(DVec3, DVec3)> = (0..5000)
            .map(|_| {
                let (wi, wo) = (rand_hemi(&mut rng), rand_hemi(&mut rng));
                (
                    m.eval(wi, wo).as_dvec3(),
                    m.eval_f64(wi.as_dvec3(), wo.as_dvec3()),
                )
            })
            .collect();
        let peak = pairs
            .iter()
            .map(|(_, b)| b.abs().max_element())
            .fold(0.0f64, f64::max);
        let mut worst = 0.0f64;
        for (a, b) in &pairs {
            let scale = b.abs().max_element().max(1e-3 * peak);
            worst = worst.max((*a - *b).abs().max_element() / scale);
        }
        let bound = 32.0 * eps * (1.0 + k);
        eprintln!(
            "{}: eval_f64 vs eval max rel {worst:.3e} (bound {bound:.3e})",
            m.name()
        );
        assert!(worst <= bound, "{}: {worst:.3e} > {bound:.3e}", m.name());
        // Below the horizon: exactly zero, as eval.
        let below = DVec3::new(0.3, 0.2, -0.5).normalize();
        assert_eq!(m.eval_f64(below, DVec3::Z), DVec3::ZERO);
        assert_eq!(m.eval_f64(DVec3::Z, below), DVec3::ZERO);
    }
}

/// The f64 evaluations are f64 arithmetic, not promoted f32: on directions that are not
/// f32 numbers, they match the formulas written here in f64 to 1e-12 (a promoted f32
/// result is ~1e-7 off). A constant-table D-BRDF with `R_s = 1` is `1 / (4 pi (a + b - ab))`
/// (module doc of `dbrdf`): its table lookup weights are f32, so 1e-6 there.
#[test]
fn eval_f64_is_f64_arithmetic() {
    use super::BlinnPhong;
    let mut rng = rand_pcg::Pcg64::seed_from_u64(23);
    let rand_hemi_f64 = |rng: &mut rand_pcg::Pcg64| {
        let z: f64 = rng.gen_range(0.05..1.0);
        let a: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        DVec3::new(s * a.cos(), s * a.sin(), z)
    };
    let bp = BlinnPhong {
        kd: Vec3::new(0.5, 0.3, 0.1),
        ks: Vec3::new(0.4, 0.5, 0.6),
        exponent: 60.0,
    };
    let ph = Phong {
        kd: Vec3::new(0.5, 0.3, 0.1),
        ks: Vec3::new(0.4, 0.5, 0.6),
        exponent: 30.0,
    };
    let lam = Lambert {
        albedo: Vec3::new(0.8, 0.5, 0.2),
    };
    let db = DBrdf::from_fn(16, 8, Vec3::ONE, |_| 1.0);
    let (mut w_bp, mut w_ph, mut w_db, mut promoted) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..2000 {
        let (wi, wo) = (rand_hemi_f64(&mut rng), rand_hemi_f64(&mut rng));
        let rel = |a: DVec3, b: DVec3| (a - b).abs().max_element() / b.abs().max_element();
        let h = (wi + wo).normalize();
        let exp_bp =
            bp.kd.as_dvec3() / PI + bp.ks.as_dvec3() * (68.0 / (8.0 * PI) * h.z.powf(60.0));
        w_bp = w_bp.max(rel(bp.eval_f64(wi, wo), exp_bp));
        promoted = promoted.max(rel(bp.eval(wi.as_vec3(), wo.as_vec3()).as_dvec3(), exp_bp));
        let r = DVec3::new(-wi.x, -wi.y, wi.z);
        let exp_ph = ph.kd.as_dvec3() / PI
            + ph.ks.as_dvec3() * (32.0 / (2.0 * PI) * r.dot(wo).max(0.0).powf(30.0));
        w_ph = w_ph.max(rel(ph.eval_f64(wi, wo), exp_ph));
        assert_eq!(lam.eval_f64(wi, wo), lam.albedo.as_dvec3() / PI);
        let (a, b) = (wi.z, wo.z);
        let exp_db = DVec3::splat(1.0 / (4.0 * PI * (a + b - a * b)));
        w_db = w_db.max(rel(db.eval_f64(wi, wo), exp_db));
    }
    eprintln!("f64 evals against f64 formulas: blinn-phong {w_bp:.3e}, phong {w_ph:.3e}, constant d-brdf {w_db:.3e}; promoted f32 blinn-phong {promoted:.3e}");
    assert!(w_bp < 1e-12 && w_ph < 1e-12, "{w_bp:.3e} {w_ph:.3e}");
    assert!(w_db < 1e-6, "{w_db:.3e}");
    assert!(
        promoted > 1e-9,
        "the check cannot tell f32 from f64: {promoted:.3e}"
    );
}
