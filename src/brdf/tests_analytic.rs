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
