//! Acquisition (SH projection and least squares), error reports, ringing flag, D-BRDF fit,
//! material library and the scene's material kinds. Grids are small so the file runs in a
//! few seconds with the opt-level-2 test profile.
//!
//! (Past 400 lines because the acquisition tests share their band-limited sources and error
//! helpers, and one file keeps the SH projection and the D-BRDF fit, both ways of turning a
//! source into a material, side by side.)

use brdfkit::acquire::fit::{fit_dbrdf, FitOptions};
use brdfkit::acquire::{
    acquire, hemisphere_error, project_sphere_function, ringing_flagged, AcquireOptions, ErrorGrid,
    Method,
};
use brdfkit::brdf::{AshikhminShirley, BlinnPhong, Brdf, DBrdf, Lambert};
use brdfkit::conventions::{hemi_texel_angles_f64, local_direction_f64};
use brdfkit::sh::{eval_sh_f64, num_terms, sh_lm};
use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng};

const SMALL: ErrorGrid = ErrorGrid { n_mu: 16, n_az: 32 };

fn random_coeffs(bands: usize, seed: u64) -> Vec<DVec3> {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    (0..num_terms(bands))
        .map(|_| {
            DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            )
        })
        .collect()
}

fn sh_sum(c: &[DVec3], d: DVec3) -> DVec3 {
    let mut y = vec![0.0; c.len()];
    eval_sh_f64(d, &mut y);
    c.iter().zip(&y).map(|(c, y)| *c * *y).sum()
}

/// The sphere projection behind `Method::Zero` recovers a band-limited function's
/// coefficients exactly (to 1e-5), at every order from 1 to 10.
#[test]
fn band_limited_function_is_recovered_by_exact_projection() {
    for bands in 1..=10 {
        let c = random_coeffs(bands, bands as u64);
        let got = project_sphere_function(&|d| sh_sum(&c, d), bands, bands);
        for (k, (g, e)) in got.iter().zip(&c).enumerate() {
            assert!(
                (*g - *e).abs().max_element() < 1e-5,
                "bands {bands} k {k}: {g} vs {e}"
            );
        }
    }
}

/// A BRDF whose acquired value `f cos` is, for each view direction, a finite SH sum in `wi`
/// with only even-parity terms (`l + m` even, symmetric under z -> -z), coefficients
/// depending smoothly on `wo`.
struct EvenBandLimited {
    base: Vec<DVec3>,
}

impl EvenBandLimited {
    fn new(bands: usize) -> Self {
        let mut base = random_coeffs(bands, 77);
        for (k, b) in base.iter_mut().enumerate() {
            let (l, m) = sh_lm(k);
            if (l as i32 + m) % 2 != 0 {
                *b = DVec3::ZERO;
            }
        }
        EvenBandLimited { base }
    }
    fn coeffs(&self, wo: DVec3) -> Vec<DVec3> {
        self.base
            .iter()
            .enumerate()
            .map(|(k, b)| *b * (1.0 + wo.z + 0.1 * k as f64 * wo.x))
            .collect()
    }
}

impl Brdf for EvenBandLimited {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        sh_sum(&self.coeffs(wo.as_dvec3()), wi.as_dvec3()).as_vec3()
    }
    fn includes_cosine(&self) -> bool {
        true
    }
    fn name(&self) -> &str {
        "even-band-limited"
    }
}

/// Through the full `acquire` path (a `Brdf`, view texels, f32 storage): the even extension
/// recovers an even band-limited source's coefficients to 1e-5, and least squares its values
/// on the hemisphere to 1e-3 relative L2 (its Tikhonov bias).
#[test]
fn band_limited_brdf_is_recovered_by_even_extension_and_least_squares() {
    let bands = 6;
    let src = EvenBandLimited::new(bands);
    let (nu, nv) = (4, 2);
    let ds = acquire(&src, &AcquireOptions::new(bands, nu, nv, Method::Even)).unwrap();
    assert!(ds.cosine_included());
    for j in 0..nv {
        for i in 0..nu {
            let (p, a) = hemi_texel_angles_f64(i, j, nu, nv);
            let want = src.coeffs(local_direction_f64(p, a));
            for ch in 0..3 {
                for (k, w) in want.iter().enumerate() {
                    let got = ds.texel(i, j, ch)[k] as f64;
                    assert!(
                        (got - w[ch]).abs() < 1e-5 * (1.0 + w[ch].abs()),
                        "texel ({i},{j}) ch {ch} k {k}: {got} vs {}",
                        w[ch]
                    );
                }
            }
        }
    }
    // Least squares: the coefficients are not unique on the hemisphere (the Gram matrix is
    // nearly singular), so compare the reconstruction on the hemisphere.
    let ds = acquire(
        &src,
        &AcquireOptions::new(bands, nu, nv, Method::Lsq { lambda: 1e-8 }),
    )
    .unwrap();
    let r = hemisphere_error(&src, &ds, nu, nv, SMALL);
    assert!(r.rel_l2 < 1e-3, "{r:?}");
}

fn err(src: &dyn Brdf, bands: usize, method: Method) -> f64 {
    let ds = acquire(src, &AcquireOptions::new(bands, 4, 2, method)).unwrap();
    hemisphere_error(src, &ds, 4, 2, SMALL).rel_l2
}

/// For a smooth source the hemisphere error falls as the order grows, for every method.
#[test]
fn errors_fall_as_the_order_grows_for_a_smooth_source() {
    let src = BlinnPhong {
        kd: Vec3::new(0.5, 0.3, 0.2),
        ks: Vec3::splat(0.2),
        exponent: 4.0,
    };
    for method in [Method::Zero, Method::Lsq { lambda: 1e-6 }, Method::Even] {
        let e: Vec<f64> = [1, 2, 4, 8].iter().map(|&b| err(&src, b, method)).collect();
        for w in e.windows(2) {
            assert!(w[1] < w[0], "{method:?}: {e:?}");
        }
        assert!(e[3] < 0.1, "{method:?}: order 8 error {}", e[3]);
    }
}

/// Least squares on the hemisphere beats zero extension in hemisphere L2 on a glossy source.
#[test]
fn least_squares_beats_zero_extension_on_a_glossy_source() {
    let src = AshikhminShirley {
        nu: 60.0,
        nv: 60.0,
        rs: Vec3::splat(0.3),
        rd: Vec3::new(0.3, 0.1, 0.1),
    };
    for bands in [4, 8] {
        let z = err(&src, bands, Method::Zero);
        let l = err(&src, bands, Method::Lsq { lambda: 1e-6 });
        assert!(l < z, "bands {bands}: lsq {l} vs zero {z}");
    }
}

/// Ringing is flagged for a sharp specular source at 8 bands and not for Lambert.
#[test]
fn ringing_is_flagged_for_specular_not_lambert() {
    let spec = AshikhminShirley {
        nu: 500.0,
        nv: 500.0,
        rs: Vec3::splat(0.8),
        rd: Vec3::ZERO,
    };
    let lam = Lambert {
        albedo: Vec3::new(0.8, 0.5, 0.2),
    };
    for method in [Method::Zero, Method::Lsq { lambda: 1e-6 }] {
        let ds = acquire(&spec, &AcquireOptions::new(8, 4, 2, method)).unwrap();
        let r = hemisphere_error(&spec, &ds, 4, 2, SMALL);
        assert!(ringing_flagged(&r), "{method:?} specular: {r:?}");
        let ds = acquire(&lam, &AcquireOptions::new(8, 4, 2, method)).unwrap();
        let r = hemisphere_error(&lam, &ds, 4, 2, SMALL);
        assert!(!ringing_flagged(&r), "{method:?} lambert: {r:?}");
        assert!(r.rel_l2 < 0.05, "{method:?} lambert: {r:?}");
    }
}

fn fit_opts() -> FitOptions {
    FitOptions {
        nu: 32,
        nv: 16,
        view: (8, 4),
        grid: ErrorGrid { n_mu: 24, n_az: 48 },
    }
}

/// A D-BRDF source is recovered by the fit: small error and the right Fresnel colour.
#[test]
fn dbrdf_fit_recovers_a_dbrdf_source() {
    let rs = Vec3::new(0.2, 0.5, 0.8);
    let src = DBrdf::from_fn(32, 16, rs, |h| h.z.powi(20) + 0.05);
    let fit = fit_dbrdf(&src, &fit_opts()).unwrap();
    assert!(fit.report.rel_l2 < 0.05, "{:?}", fit.report);
    assert!(
        (fit.brdf.rs - rs).abs().max_element() < 0.05,
        "{}",
        fit.brdf.rs
    );
}

/// The D-BRDF fit of a glossy Ashikhmin-Shirley source is within 26 % relative L2 (the two
/// models differ in their denominators and AS has a diffuse term the D-BRDF lacks). The fit
/// works on the file table (nearest texel of the half vector's angles) while the renderer
/// evaluates the octahedral table derived from it (`brdf::dbrdf`), which is continuous at
/// the pole where the file lookup is not: 0.2501 with that lookup, under 0.25 before.
#[test]
fn dbrdf_fit_of_ashikhmin_shirley_is_within_stated_error() {
    let src = AshikhminShirley {
        nu: 100.0,
        nv: 100.0,
        rs: Vec3::new(0.8, 0.6, 0.3),
        rd: Vec3::splat(0.05),
    };
    let fit = fit_dbrdf(&src, &fit_opts()).unwrap();
    assert!(fit.report.rel_l2 < 0.26, "{:?}", fit.report);
    // And it beats the SH acquisition at 8 bands on this sharp source.
    let ds = acquire(&src, &AcquireOptions::new(8, 8, 4, Method::Zero)).unwrap();
    let sh = hemisphere_error(&src, &ds, 8, 4, fit_opts().grid);
    assert!(fit.report.rel_l2 < sh.rel_l2, "{:?} vs {sh:?}", fit.report);
}

/// A sharp Blinn-Phong lobe over a faint Lambert base (the glossy MERL test source of
/// `examples/measured_error.rs`: `ks = 0.6`, exponent 80, `kd = 0.02`) and its MERL table are
/// fitted within 0.15 relative L2 (0.124 and 0.123 on these small grids), with `R_s = 1`
/// (the source has no Fresnel rise). The
/// lobe falls faster at grazing than the D-BRDF's `1 / D`, so the unconstrained `(c, R_s)`
/// least squares has `c <= 0`; the fit used to fall back to `R_s = 0.05` there (a 20-fold
/// Fresnel rise towards grazing) and was off by 0.61. Seeded fault: that fallback's
/// Fresnel on the fitted table, at the best `c` of a scan, is above twice the bound (0.52).
#[test]
fn dbrdf_fit_of_a_sharp_blinn_phong_lobe_and_its_merl_table() {
    let src = BlinnPhong {
        kd: Vec3::splat(0.02),
        ks: Vec3::splat(0.6),
        exponent: 80.0,
    };
    let table = brdfkit::brdf::MerlBrdf::tabulate(&src);
    let opts = fit_opts();
    const BOUND: f64 = 0.15;
    let fit = fit_dbrdf(&src, &opts).unwrap();
    assert!(fit.report.rel_l2 < BOUND, "{:?}", fit.report);
    assert_eq!(fit.brdf.rs, Vec3::ONE);
    let of_table = fit_dbrdf(&table, &opts).unwrap();
    assert!(of_table.report.rel_l2 < BOUND, "{:?}", of_table.report);
    let mut fault = fit.brdf.clone();
    fault.rs = Vec3::splat(0.05);
    let best = (0..41)
        .map(|k| {
            fault.c = fit.brdf.c * 20.0 * 10f32.powf((k as f32 - 20.0) / 20.0);
            hemisphere_error(&src, &fault, opts.view.0, opts.view.1, opts.grid).rel_l2
        })
        .fold(f64::INFINITY, f64::min);
    assert!(best > 2.0 * BOUND, "seeded fault not caught: {best}");
    eprintln!(
        "sharp Blinn-Phong fit rel L2 {:.4}, of its MERL table {:.4}, R_s = 0.05 at best c {best:.4}",
        fit.report.rel_l2, of_table.report.rel_l2
    );
}

/// Every library material builds, is finite and lit (no black teapot), and its source model
/// exists.
#[test]
fn library_materials_build_finite_and_lit() {
    for m in brdfkit::library::LIBRARY {
        let b = brdfkit::library::build(m.name).unwrap();
        assert!(brdfkit::brdf::stand_ins::source_model(m.name).is_some());
        let wo = local_direction_f64(0.5, 1.0).as_vec3();
        let mut sum = Vec3::ZERO;
        for (p, a) in [
            (0.3f64, 0.0f64),
            (0.6, 2.0),
            (0.9, 4.0),
            (0.5, 1.0 + std::f64::consts::PI),
        ] {
            let v = brdfkit::brdf::eval_cosine_weighted(
                b.as_brdf(),
                local_direction_f64(p, a).as_vec3(),
                wo,
            );
            assert!(v.is_finite(), "{}: {v}", m.name);
            sum += v;
        }
        assert!(sum.max_element() > 0.01, "{}: {sum}", m.name);
    }
    assert!(brdfkit::library::build("no-such").is_err());
}

/// Scene material kinds: library names resolve, unknown names and missing files give errors
/// naming the field.
#[test]
fn scene_material_kinds_name_their_fields() {
    use brdfkit::scene::{Scene, SceneFile};
    use std::path::Path;
    let f = SceneFile::parse("[material]\nkind = \"library\"\nname = \"magenta-plastic\"\n[mesh]\nsource = \"sphere\"\nsegments = 4\n").unwrap();
    Scene::resolve(&f, Path::new(".")).unwrap();
    let f = SceneFile::parse("[material]\nkind = \"library\"\nname = \"nope\"\n").unwrap();
    let e = Scene::resolve(&f, Path::new("."))
        .err()
        .unwrap()
        .to_string();
    assert!(e.starts_with("material.name:"), "{e}");
    let f = SceneFile::parse("[material]\nkind = \"sh-file\"\npath = \"missing.exr\"\n").unwrap();
    let e = Scene::resolve(&f, Path::new("."))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.starts_with("material.path:") && e.contains("missing.exr"),
        "{e}"
    );
    let e = brdfkit::scene::MaterialSpec::from_cli("nope-not-a-file")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("--material:"), "{e}");
}

/// Each library material has the representation its own acquisition recommends (the rule
/// of examples/library_fit.rs): an SH entry's least-squares fit at its band count is not
/// flagged for ringing and has weighted rel L2 below 0.1; a D-BRDF entry's SH fit at 8 bands
/// would be flagged or coarser than that, so SH would not do. The one exception is the
/// entry that keeps the thesis's ringing SH (Fig. 3.12) on purpose, which must still ring.
#[test]
fn library_representations_follow_their_acquisition() {
    use brdfkit::brdf::stand_ins::source_model;
    use brdfkit::library::{Representation, LIBRARY, VIEW_GRID};
    let (nu, nv) = VIEW_GRID;
    for m in LIBRARY {
        let bands = match m.representation {
            Representation::Sh { bands } => bands,
            Representation::Dbrdf => 8,
        };
        let src = source_model(m.name).unwrap();
        let lsq = Method::Lsq {
            lambda: brdfkit::acquire::DEFAULT_LAMBDA,
        };
        let ds = acquire(src.as_ref(), &AcquireOptions::new(bands, nu, nv, lsq)).unwrap();
        let r = hemisphere_error(src.as_ref(), &ds, nu, nv, SMALL);
        let sh_fits = !ringing_flagged(&r) && r.rel_l2 < 0.1;
        if let Representation::Sh { .. } = m.representation {
            // What the library renders: the same fit held to f cos >= 0, which costs
            // accuracy (dips pinned to zero flatten the lobe's skirt): at most 0.15 here
            // (blue silk, the sharpest, measures 0.12 in examples/library_fit.rs). What a
            // user sees is the render's error, examples/library_error.rs.
            let opts = AcquireOptions::new(bands, nu, nv, brdfkit::library::LIBRARY_METHOD);
            let lib = acquire(src.as_ref(), &opts).unwrap();
            let rl = hemisphere_error(src.as_ref(), &lib, nu, nv, SMALL);
            if m.name != brdfkit::library::THESIS_RINGING {
                assert!(rl.rel_l2 < 0.15, "{}: {rl:?}", m.name);
                assert!(rl.min_over_peak > -0.01, "{}: {rl:?}", m.name);
            }
        }
        match (m.name, m.representation) {
            ("gold-dust-paint-sh-ringing", _) => {
                assert!(ringing_flagged(&r), "{}: {r:?}", m.name)
            }
            (_, Representation::Sh { .. }) => {
                assert!(sh_fits, "{} at {bands} bands: {r:?}", m.name)
            }
            (_, Representation::Dbrdf) => {
                assert!(!sh_fits, "{} would fit as SH at 8 bands: {r:?}", m.name)
            }
        }
    }
}

/// The non-negative window ([`Method::Positive`]) never reconstructs below zero, on the
/// source that rings worst in the library (gold dust paint, A-S exponent 250) at 8 bands,
/// where least squares rings by more than the flag's threshold; and its weights are those
/// of `((1 + t) / 2)^7` (`w_1 = 7/9`, `w_7 = 7! 8! / 15!`).
#[test]
fn positive_window_does_not_ring() {
    use brdfkit::brdf::stand_ins::source_model;
    let w = brdfkit::acquire::positive_window(8);
    assert!(
        (w[0] - 1.0).abs() < 1e-15 && (w[1] - 7.0 / 9.0).abs() < 1e-15,
        "{w:?}"
    );
    let w7 = (1..=7).product::<u64>() as f64 * (1..=8).product::<u64>() as f64
        / (1..=15).product::<u64>() as f64;
    assert!((w[7] - w7).abs() < 1e-15 * w7, "{} vs {w7}", w[7]);
    let src = source_model("gold-dust-paint").unwrap();
    let (nu, nv) = (8, 4);
    let lsq = acquire(
        src.as_ref(),
        &AcquireOptions::new(8, nu, nv, Method::Lsq { lambda: 1e-6 }),
    )
    .unwrap();
    let r = hemisphere_error(src.as_ref(), &lsq, nu, nv, SMALL);
    assert!(ringing_flagged(&r), "{r:?}");
    let pos = acquire(
        src.as_ref(),
        &AcquireOptions::new(8, nu, nv, Method::Positive),
    )
    .unwrap();
    let r = hemisphere_error(src.as_ref(), &pos, nu, nv, SMALL);
    assert!(r.worst_min_over_peak > -1e-5, "{r:?}");
    assert!(r.share_below_zero < 1e-3, "{r:?}");
}

/// The view weights are the projected solid angle shares: they sum to 1 and the last row
/// of an 8-row grid (78.75-90 deg) gets `1 - sin^2(78.75 deg)` of it.
#[test]
fn view_texel_weights_are_projected_solid_angle() {
    use brdfkit::acquire::view_texel_weight;
    let (nu, nv) = (16, 8);
    let sum: f64 = (0..nv)
        .map(|j| nu as f64 * view_texel_weight(j, nu, nv))
        .sum();
    assert!((sum - 1.0).abs() < 1e-12, "{sum}");
    let last = nu as f64 * view_texel_weight(nv - 1, nu, nv);
    let expect = 1.0 - (78.75f64).to_radians().sin().powi(2);
    assert!((last - expect).abs() < 1e-12, "{last} vs {expect}");
}

/// The Lambert + D-BRDF fit recovers a known base and lobe: a [`LambertDbrdf`] source
/// (rd (0.3, 0.2, 0.05) under an anisotropic Phong lobe) fits far closer than the D-BRDF
/// alone, with its base found to within 0.02 per channel; the library's D-BRDF entries
/// render that fit, which is below [`BASE_FIT_BOUND`] and never worse than the D-BRDF alone.
#[test]
fn a_lambert_base_under_the_dbrdf_lobe_is_fitted() {
    use brdfkit::acquire::fit::fit_lambert_dbrdf;
    use brdfkit::brdf::stand_ins::source_model;
    let rd = Vec3::new(0.3, 0.2, 0.05);
    let src = brdfkit::brdf::LambertDbrdf::anisotropic_phong(30.0, 90.0, Vec3::splat(0.6), rd);
    let opts = FitOptions::default();
    let alone = fit_dbrdf(&src, &opts).unwrap();
    let with_base = fit_lambert_dbrdf(&src, &opts).unwrap();
    eprintln!(
        "lobe over rd {rd}: D-BRDF alone rel L2 {:.4}, with base {:.4} (rd {})",
        alone.report.rel_l2, with_base.report.rel_l2, with_base.brdf.rd
    );
    assert!(
        (with_base.brdf.rd - rd).abs().max_element() < 0.02,
        "{}",
        with_base.brdf.rd
    );
    assert!(with_base.report.rel_l2 < 0.2 * alone.report.rel_l2);
    for m in brdfkit::library::LIBRARY
        .iter()
        .filter(|m| m.representation == brdfkit::library::Representation::Dbrdf)
    {
        let src = source_model(m.name).unwrap();
        let alone = fit_dbrdf(src.as_ref(), &opts).unwrap();
        let with_base = fit_lambert_dbrdf(src.as_ref(), &opts).unwrap();
        eprintln!(
            "{}: D-BRDF alone rel L2 {:.4}, with base {:.4} (rd {})",
            m.name, alone.report.rel_l2, with_base.report.rel_l2, with_base.brdf.rd
        );
        assert!(with_base.report.rel_l2 < BASE_FIT_BOUND, "{}", m.name);
        assert!(with_base.report.rel_l2 <= alone.report.rel_l2, "{}", m.name);
        match brdfkit::library::build(m.name).unwrap() {
            brdfkit::material::Material::LambertDbrdf(l) => assert_eq!(l.rd, with_base.brdf.rd),
            brdfkit::material::Material::DBrdf(_) => {
                assert_eq!(with_base.brdf.rd, Vec3::ZERO, "{}", m.name)
            }
            other => panic!("{} renders as {}", m.name, other.name()),
        }
    }
}

/// Weighted relative L2 of `f cos` the library's D-BRDF entries are fitted to.
const BASE_FIT_BOUND: f64 = 0.05;
