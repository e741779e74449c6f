//! Tests of the D-BRDF: normalisation of the evaluated lookup, closed forms, the derived
//! lookup's error against the file's.

use super::*;
use rand::{Rng, SeedableRng};

/// `integral p(h) (h.n) dω_h` of the looked-up `p` by a midpoint rule over
/// (polar, azimuth), independent of both texel grids.
fn projected_integral(d: &DBrdf, np: usize, na: usize) -> f64 {
    let (dp, da) = (
        std::f64::consts::FRAC_PI_2 / np as f64,
        std::f64::consts::TAU / na as f64,
    );
    let mut integral = 0.0f64;
    for j in 0..np {
        let pol = (j as f64 + 0.5) * dp;
        let w = pol.cos() * pol.sin() * dp * da;
        for i in 0..na {
            let az = (i as f64 + 0.5) * da;
            integral += d.p(local_direction_f64(pol, az).as_vec3()) as f64 * w;
        }
    }
    integral
}

/// After [`DBrdf::normalize_projected`], `integral p(h) (h.n) dω_h = 1` for the `p` the
/// renderer evaluates (the derived octahedral table's lookup) of a random table, to the
/// derivation's quadrature (module doc) and the check's own midpoint rule (the bilinear
/// `p` has kinks, so that rule is O(h^2)). The file table keeps its closed-form
/// normalisation, and an unnormalised table keeps its integral through the derivation.
#[test]
fn normalisation_holds_for_the_evaluated_lookup() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(8);
    let (nu, nv) = (12, 6);
    let table: Vec<f32> = (0..nu * nv).map(|_| rng.gen_range(0.1..2.0)).collect();
    let mut d = DBrdf::new(nu, nv, table, Vec3::ONE);
    d.normalize_projected();
    let integral = projected_integral(&d, 1200, 2400);
    eprintln!(
        "12x6 random table: integral p (h.n) = 1 {:+.2e}",
        integral - 1.0
    );
    assert!(
        (integral - 1.0).abs() < 2e-5,
        "integral p (h.n) = {integral}"
    );
    assert!((d.file_projected_integral() - 1.0).abs() < 1e-6);
    // The rows' projected weights sum to integral_0^{pi/2} cos sin = 1/2.
    for nv in [1, 2, 7, 32] {
        let s: f64 = (0..nv).map(|j| polar_row_projected_weight(j, nv)).sum();
        assert!((s - 0.5).abs() < 1e-14, "nv = {nv}: {s}");
    }
    let raw = DBrdf::new(4, 2, vec![1.0; 8], Vec3::ONE);
    let integral = projected_integral(&raw, 600, 1200);
    assert!((integral - PI_F64).abs() < 1e-4, "{integral}");
}

const PI_F64: f64 = std::f64::consts::PI;

/// A constant table stays exactly constant (`1/pi` after normalisation) through the
/// derivation: the octahedral weights sum to `pi` exactly, so the scale is 1.
#[test]
fn constant_table_stays_one_over_pi() {
    for (nu, nv) in [(16, 8), (64, 32), (3, 1)] {
        let d = DBrdf::from_fn(nu, nv, Vec3::ONE, |_| 1.0);
        let want = (1.0 / PI_F64) as f32;
        for &v in d.octahedral_table() {
            assert!((v - want).abs() <= 1e-7 * want, "{nu}x{nv}: {v}");
        }
        assert!((d.octahedral_scale() - 1.0).abs() < 1e-6);
    }
}

/// The lookup's error against the file table's `GL_LINEAR` lookup (module doc, "The
/// lookup the renderer evaluates"): max and mean relative difference over 200k half
/// vectors uniform on the hemisphere, for the shipped D-BRDFs.
#[test]
fn octahedral_lookup_error_against_the_file_lookup() {
    let mut tables: Vec<(String, DBrdf)> = Vec::new();
    let lindt = match crate::library::build("lindt-paper").expect("library lindt-paper") {
        crate::material::Material::DBrdf(d) => (*d).clone(),
        crate::material::Material::LambertDbrdf(l) => l.lobe.clone(),
        other => panic!("lindt-paper is a D-BRDF fit, not {}", other.name()),
    };
    tables.push(("lindt-paper (library fit 64x32)".into(), lindt));
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("golden/lindt-paper-16x8.exr");
    let (f, _) = file::read_dbrdf(&path).expect("golden D-BRDF file");
    tables.push(("golden/lindt-paper-16x8.exr".into(), f));
    tables.push((
        "anisotropic Phong lobe 32x32 (n_u 40, n_v 10)".into(),
        crate::brdf::LambertDbrdf::anisotropic_phong(
            40.0,
            10.0,
            Vec3::splat(0.05),
            Vec3::splat(0.3),
        )
        .lobe,
    ));
    let mut rng = rand_pcg::Pcg64::seed_from_u64(15);
    for (name, d) in &tables {
        let (mut max_rel, mut sum_rel, mut count) = (0.0f64, 0.0f64, 0usize);
        let (mut max_abs_peak, mut worst_polar) = (0.0f64, 0.0f64);
        let (mut sum_rel_off_pole, mut count_off_pole, mut max_rel_off_pole) =
            (0.0, 0usize, 0.0f64);
        let pole = std::f64::consts::FRAC_PI_2 / d.grid().1 as f64;
        let peak = d.table().iter().copied().fold(0.0f32, f32::max) as f64;
        for _ in 0..200_000 {
            let z: f64 = rng.gen_range(0.0..1.0);
            let az: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
            let r = (1.0 - z * z).max(0.0).sqrt();
            let h = glam::DVec3::new(r * az.cos(), r * az.sin(), z);
            let old = d.file_p_f64(h);
            let new = d.p(h.as_vec3()) as f64;
            let diff = (new - old).abs();
            if diff / peak > max_abs_peak {
                max_abs_peak = diff / peak;
                worst_polar = z.acos().to_degrees();
            }
            if old > 1e-3 * peak {
                let rel = diff / old;
                if z.acos() > pole {
                    max_rel_off_pole = max_rel_off_pole.max(rel);
                    sum_rel_off_pole += rel;
                    count_off_pole += 1;
                }
                max_rel = max_rel.max(rel);
                sum_rel += rel;
                count += 1;
            }
        }
        let mean_rel = sum_rel / count.max(1) as f64;
        eprintln!(
            "{name}: n = {}, scale 1 {:+.1e}; |new - old| / old: max {max_rel:.3e}, \
             mean {mean_rel:.3e} (where old > 1e-3 peak); max |new - old| / peak {max_abs_peak:.3e} \
             at polar {worst_polar:.2} deg; beyond one file row of the pole: max {:.3e}, mean {:.3e}",
            d.octahedral_grid(),
            d.octahedral_scale() - 1.0,
            max_rel_off_pole,
            sum_rel_off_pole / count_off_pole.max(1) as f64
        );
        assert!(mean_rel < 0.01, "{name}: mean {mean_rel}");
        assert!(max_abs_peak < 0.25, "{name}: max/peak {max_abs_peak}");
    }
}
