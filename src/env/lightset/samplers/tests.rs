//! Tests of the samplers against independent references (brute-force sums over texels,
//! chi-square against the analytic texel probabilities, the white furnace).
//!
//! One file past 400 lines because the tests share the probe fixtures (downsampled
//! assets, constant and single-hot-texel probes) and most check every sampler at once;
//! the utilities' own tests ([`Distribution2D`], the summed-area table) sit in their files.

use super::*;
use crate::brdf::{eval_cosine_weighted, Lambert};
use crate::conventions::{probe_direction, probe_uv, texel_center_f64, ShadingFrame};
use crate::env::lightset::reference::*;
use crate::env::*;
use glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::path::PathBuf;

fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/probes")
        .join(name)
}

fn load(name: &str) -> Probe {
    Probe::load(&asset(name), &LoadOptions::default())
        .unwrap()
        .0
}

/// Box-filters a probe by an integer factor, weighting by solid angle so power is kept.
fn downsample(p: &Probe, f: usize) -> Probe {
    let (w, h) = (p.width() / f, p.height() / f);
    let mut t = Vec::with_capacity(w * h);
    for r in 0..h {
        for c in 0..w {
            let mut acc = [0f64; 3];
            let mut om = 0.0;
            for rr in r * f..(r + 1) * f {
                let o = p.solid_angle(rr);
                for cc in c * f..(c + 1) * f {
                    let x = p.texel(rr, cc);
                    for k in 0..3 {
                        acc[k] += x[k] as f64 * o;
                    }
                    om += o;
                }
            }
            t.push([
                (acc[0] / om) as f32,
                (acc[1] / om) as f32,
                (acc[2] / om) as f32,
            ]);
        }
    }
    Probe::from_texels(&format!("{}/{f}", p.name()), w, h, t, &Default::default())
        .unwrap()
        .0
}

fn constant(w: usize, h: usize, v: f32) -> Probe {
    Probe::from_texels("const", w, h, vec![[v; 3]; w * h], &Default::default())
        .unwrap()
        .0
}

fn hot(w: usize, h: usize, row: usize, col: usize) -> Probe {
    let mut t = vec![[0.0; 3]; w * h];
    t[row * w + col] = [50.0, 20.0, 5.0];
    Probe::from_texels("hot", w, h, t, &Default::default())
        .unwrap()
        .0
}

fn all_samplers(n: usize) -> Vec<SamplerConfig> {
    vec![
        SamplerConfig::Uniform { n, seed: 7 },
        SamplerConfig::Importance { n, seed: 7 },
        SamplerConfig::Stratified { n, seed: 7 },
        SamplerConfig::MedianCut { n },
        SamplerConfig::Lloyd { n, iterations: 8 },
    ]
}

fn assert_power(probe: &Probe, ls: &LightSet, what: &str) {
    let want = probe.total_power();
    let got = ls.total_irradiance();
    for k in 0..3 {
        let rel = (got[k] - want[k]).abs() / want[k].abs().max(1e-300);
        assert!(
            rel < 1e-5,
            "{what}: channel {k} {got} vs {want} (rel {rel:e})"
        );
    }
    for i in 0..ls.len() {
        let p = ls.light_irradiance(i);
        assert!(
            p.min_element() >= 0.0 && p.is_finite(),
            "{what}: light {i} {p}"
        );
        assert!((ls.direction(i).length() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn total_power_preserved_by_every_sampler() {
    let probes = [
        downsample(&load("city.exr"), 4),
        downsample(&load("studio.exr"), 4),
        constant(3, 2, 0.25),
    ];
    for p in &probes {
        for n in [1, 7, 16, 128, 1024] {
            for cfg in all_samplers(n) {
                let ls = cfg.run(p);
                assert_power(p, &ls, &format!("{} {cfg:?}", p.name()));
                if p.width() * p.height() >= n {
                    assert_eq!(ls.len(), n, "{cfg:?}");
                }
            }
        }
        assert_power(p, &full_probe(p), "full");
    }
    // Full resolution, a few N.
    let city = load("city.exr");
    for cfg in all_samplers(16) {
        assert_power(&city, &cfg.run(&city), &format!("city {cfg:?}"));
    }
}

#[test]
fn full_probe_matches_exact_reference() {
    let p = downsample(&load("studio.exr"), 8);
    let normals = fibonacci_sphere(32);
    let reference = reference_irradiance_many(&p, &normals);
    let full = full_probe(&p);
    assert!(irradiance_error(&full, &normals, &reference) < 1e-6);
    for (n, r) in normals.iter().zip(&reference) {
        // The per-row f64 form agrees with the tabulated form.
        assert!((reference_irradiance(&p, *n) - *r).length() <= 1e-9 * r.length());
    }
}

/// Brute-force weight (luminance x solid angle) of a texel rectangle.
fn brute_energy(p: &Probe, r0: usize, r1: usize, c0: usize, c1: usize) -> f64 {
    let mut e = 0.0;
    for r in r0..r1 {
        for c in c0..c1 {
            e += luminance(p.texel(r, c)) * p.solid_angle(r);
        }
    }
    e
}

#[test]
fn median_cut_balances_halves_and_tiles_the_image() {
    for p in [
        downsample(&load("city.exr"), 4),
        downsample(&load("studio.exr"), 4),
    ] {
        let total = brute_energy(&p, 0, p.height(), 0, p.width());
        for n in [1, 7, 16, 128] {
            let mc = median_cut(&p, n);
            assert_eq!(mc.regions.len(), n);
            assert_eq!(mc.lights.len(), n);
            assert_eq!(mc.cuts.len(), n - 1);
            let mut count = vec![0u32; p.width() * p.height()];
            for r in &mc.regions {
                for row in r.row0..r.row1 {
                    for col in r.col0..r.col1 {
                        count[row * p.width() + col] += 1;
                    }
                }
            }
            assert!(count.iter().all(|&c| c == 1), "regions must tile, n = {n}");
            for cut in &mc.cuts {
                let q = cut.parent;
                let (a, b, s0, s1) = match cut.axis {
                    CutAxis::Rows => (
                        brute_energy(&p, q.row0, cut.at, q.col0, q.col1),
                        brute_energy(&p, cut.at, q.row1, q.col0, q.col1),
                        brute_energy(&p, cut.at - 1, cut.at, q.col0, q.col1),
                        brute_energy(&p, cut.at, cut.at + 1, q.col0, q.col1),
                    ),
                    CutAxis::Cols => (
                        brute_energy(&p, q.row0, q.row1, q.col0, cut.at),
                        brute_energy(&p, q.row0, q.row1, cut.at, q.col1),
                        brute_energy(&p, q.row0, q.row1, cut.at - 1, cut.at),
                        brute_energy(&p, q.row0, q.row1, cut.at, cut.at + 1),
                    ),
                };
                assert!(
                    (a - b).abs() <= s0.max(s1) + 1e-9 * total,
                    "{} n={n} cut {cut:?}: halves {a} {b}, strips {s0} {s1}",
                    p.name()
                );
            }
        }
    }
}

/// Chi-square goodness of fit of texel counts against expected counts, pooling bins with
/// expected count below 5 into one. Returns the p-value.
fn chi_square_p(counts: &[u64], expected: &[f64]) -> f64 {
    let mut chi = 0.0;
    let mut bins = 0usize;
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (&o, &e) in counts.iter().zip(expected) {
        if e == 0.0 {
            assert_eq!(o, 0, "sample in a zero-probability texel");
            continue;
        }
        if e < 5.0 {
            pool_o += o as f64;
            pool_e += e;
        } else {
            chi += (o as f64 - e).powi(2) / e;
            bins += 1;
        }
    }
    if pool_e > 0.0 {
        chi += (pool_o - pool_e).powi(2) / pool_e;
        bins += 1;
    }
    if bins < 2 {
        return 1.0;
    }
    ChiSquared::new((bins - 1) as f64).unwrap().sf(chi)
}

/// Draws `n` samples, checks each maps back to its texel, and returns the chi-square
/// p-value of the texel histogram against the analytic texel probabilities.
fn importance_histogram_p(p: &Probe, n: usize, seed: u64) -> f64 {
    let s = ImportanceSampler::new(p).unwrap();
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut counts = vec![0u64; p.width() * p.height()];
    for _ in 0..n {
        let (row, col) = s.sample_texel(rng.gen(), rng.gen());
        counts[row * p.width() + col] += 1;
        assert_eq!(s.texel_of(s.direction(row, col)), (row, col));
    }
    let expected: Vec<f64> = (0..p.height())
        .flat_map(|r| (0..p.width()).map(move |c| (r, c)))
        .map(|(r, c)| s.texel_probability(r, c) * n as f64)
        .collect();
    // Analytic probability from scratch: weight / total, independent of the CDFs.
    let total = brute_energy(p, 0, p.height(), 0, p.width());
    for r in 0..p.height() {
        for c in 0..p.width() {
            let want = luminance(p.texel(r, c)) * p.solid_angle(r) / total;
            assert!((s.texel_probability(r, c) - want).abs() <= 1e-12);
        }
    }
    chi_square_p(&counts, &expected)
}

#[test]
fn importance_histogram_matches_pdf_chi_square() {
    // Significance: reject at p < 1e-4 (fixed seeds, 1e6 samples each).
    const N: usize = 1_000_000;
    let city = downsample(&load("city.exr"), 8); // 64x32
    let pc = importance_histogram_p(&city, N, 1);
    assert!(pc > 1e-4, "city p = {pc}");
    let c32 = constant(3, 2, 1.0);
    let pk = importance_histogram_p(&c32, N, 2);
    assert!(pk > 1e-4, "constant p = {pk}");
    // Seam: only the first and last columns lit.
    let mut t = vec![[0.0; 3]; 16 * 8];
    for r in 0..8 {
        t[r * 16] = [1.0; 3];
        t[r * 16 + 15] = [2.0; 3];
    }
    let seam = Probe::from_texels("seam", 16, 8, t, &Default::default())
        .unwrap()
        .0;
    let ps = importance_histogram_p(&seam, N, 3);
    assert!(ps > 1e-4, "seam p = {ps}");
    // Single hot texel: every sample lands in it (chi-square is degenerate there).
    let h = hot(16, 8, 3, 11);
    let s = ImportanceSampler::new(&h).unwrap();
    let mut rng = Pcg64::seed_from_u64(4);
    for _ in 0..N / 10 {
        assert_eq!(s.sample_texel(rng.gen(), rng.gen()), (3, 11));
    }
    assert_eq!(s.sample_texel(0.0, 0.0), (3, 11));
    assert_eq!(
        s.sample_texel(1.0 - f64::EPSILON, 1.0 - f64::EPSILON),
        (3, 11)
    );
}

#[test]
fn pdf_integrates_to_one_and_matches_texel_probability() {
    let p = downsample(&load("studio.exr"), 8).with_rotation(0.9);
    let s = ImportanceSampler::new(&p).unwrap();
    let mut total = 0.0;
    for r in 0..p.height() {
        for c in 0..p.width() {
            let d = p.direction(r, c);
            total += s.pdf(d) * p.solid_angle(r);
            assert_eq!(s.texel_of(d), (r, c));
        }
    }
    assert!((total - 1.0).abs() < 1e-9, "{total}");
    // Uniform sampler: map and inverse round trip, constant pdf.
    for (a, b) in [(0.1, 0.2), (0.7, 0.95), (0.5, 0.0)] {
        let d = uniform_direction(a, b);
        let (a2, b2) = uniform_inverse(d);
        assert!((a - a2).abs() < 1e-12 && (b - b2).abs() < 1e-12);
        assert!((uniform_pdf(d) * 4.0 * std::f64::consts::PI - 1.0).abs() < 1e-15);
    }
}

#[test]
fn importance_invert_round_trips_and_agrees_with_pdf() {
    // pbrt-style round trip on a rotated probe: the uniforms that chose a direction lie in
    // that direction's inverse rectangle, and the rectangle's area is the pdf (1/sr) times
    // the texel's solid angle (both equal weight / total, the pdf computed from the
    // weights, the area from the CDFs).
    let p = downsample(&load("studio.exr"), 8).with_rotation(0.9);
    let s = ImportanceSampler::new(&p).unwrap();
    let mut rng = Pcg64::seed_from_u64(21);
    for _ in 0..20_000 {
        let (a, b): (f64, f64) = (rng.gen(), rng.gen());
        let (row, col) = s.sample_texel(a, b);
        let d = s.direction(row, col);
        let [ra, rb] = s.invert(d).expect("a sampled texel has weight");
        assert!(
            ra.contains(&a) && rb.contains(&b),
            "({a}, {b}) -> ({row}, {col})"
        );
        let area = (ra.end - ra.start) * (rb.end - rb.start);
        let want = s.pdf(d) * p.solid_angle(row);
        assert!((area - want).abs() <= 1e-12, "{area} vs {want}");
    }
    // A black texel has no rectangle.
    let h = hot(16, 8, 3, 11);
    let s = ImportanceSampler::new(&h).unwrap();
    assert!(s.invert(h.direction(3, 10)).is_none());
    assert_eq!(s.invert(h.direction(3, 11)).unwrap(), [0.0..1.0, 0.0..1.0]);
}

#[test]
fn no_half_texel_offset_and_no_seam() {
    let (w, h) = (16, 8);
    let p = constant(w, h, 1.0);
    for r in 0..h {
        for c in 0..w {
            let (u, v) = probe_uv(p.direction(r, c));
            assert!((u - texel_center_f64(c, w)).abs() < 1e-12);
            assert!((v - texel_center_f64(r, h)).abs() < 1e-12);
        }
    }
    // Just inside either side of the azimuth wrap.
    let eps = 1e-9;
    assert_eq!(p.texel_of(probe_direction(1.0 - eps, 0.5)), (4, w - 1));
    assert_eq!(p.texel_of(probe_direction(eps, 0.5)), (4, 0));
    // Texel edges: u = 1/16 belongs to column 1, not 0.
    assert_eq!(p.texel_of(probe_direction(1.0 / 16.0 + eps, 0.3)).1, 1);
    // Median-cut light of a hot texel sits at its centre, not its corner.
    let hp = hot(w, h, 2, 5);
    let mc = median_cut(&hp, 4);
    let lit: Vec<usize> = (0..mc.lights.len())
        .filter(|&i| mc.lights.light_irradiance(i).x > 0.0)
        .collect();
    assert_eq!(lit.len(), 1);
    let (u, v) = hp.uv_of(mc.lights.direction(lit[0]));
    assert!((u - 5.5 / 16.0).abs() < 1e-6 && (v - 2.5 / 8.0).abs() < 1e-6);
}

#[test]
fn thin_probes_work() {
    for (w, h) in [(1, 5), (5, 1), (1, 1)] {
        let t: Vec<[f32; 3]> = (0..w * h).map(|i| [1.0 + i as f32, 1.0, 0.5]).collect();
        let p = Probe::from_texels("thin", w, h, t, &Default::default())
            .unwrap()
            .0;
        for n in [1, 3, 16] {
            for cfg in all_samplers(n) {
                let ls = cfg.run(&p);
                assert_power(&p, &ls, &format!("{w}x{h} {cfg:?}"));
            }
        }
        let s = ImportanceSampler::new(&p).unwrap();
        let mut rng = Pcg64::seed_from_u64(9);
        for _ in 0..1000 {
            let (r, c) = s.sample_texel(rng.gen(), rng.gen());
            assert!(r < h && c < w);
            assert_eq!(s.texel_of(s.direction(r, c)), (r, c));
        }
    }
}

#[test]
fn single_hot_texel_gets_all_power() {
    let (row, col) = (5, 13);
    let p = hot(32, 16, row, col).with_rotation(0.3);
    let d = p.direction(row, col);
    for n in [1, 7, 16, 128] {
        for cfg in all_samplers(n) {
            let ls = cfg.run(&p);
            assert_power(&p, &ls, &format!("hot {cfg:?}"));
            let lit: Vec<usize> = (0..ls.len())
                .filter(|&i| ls.light_irradiance(i) != glam::DVec3::ZERO)
                .collect();
            if let SamplerConfig::Uniform { .. } = cfg {
                // Uniform directions cannot land on the texel; the one light nearest to
                // it carries everything.
                assert_eq!(lit.len(), 1, "{cfg:?}");
                let best = (0..ls.len())
                    .max_by(|&a, &b| {
                        d.dot(ls.direction(a))
                            .partial_cmp(&d.dot(ls.direction(b)))
                            .unwrap()
                    })
                    .unwrap();
                assert_eq!(lit[0], best);
                continue;
            }
            for i in lit {
                let ang = ls.direction(i).dot(d).clamp(-1.0, 1.0).acos();
                assert!(ang < 1e-4, "{cfg:?}: light {i} {ang} rad off");
            }
        }
    }
}

/// Mean relative error of the Lambertian response `sum f cos power` against albedo x L
/// over 64 normals, for a constant probe of radiance L (white furnace).
fn furnace_error(ls: &LightSet, l: f64, albedo: f64) -> f64 {
    let brdf = Lambert {
        albedo: Vec3::splat(albedo as f32),
    };
    let normals = fibonacci_sphere(64);
    let mut err = 0.0;
    for n in &normals {
        let f = ShadingFrame::from_normal(n.as_vec3());
        let wo = Vec3::Z;
        let mut lo = 0.0f64;
        for i in 0..ls.len() {
            let wi = f.to_local(ls.direction(i).as_vec3());
            lo += eval_cosine_weighted(&brdf, wi, wo).x as f64 * ls.light_irradiance(i).x;
        }
        err += (lo - albedo * l).abs() / (albedo * l);
    }
    err / normals.len() as f64
}

#[test]
fn white_furnace_error_shrinks_with_n() {
    let (l, albedo) = (1.5, 0.7);
    let p = constant(128, 64, l as f32);
    // The texel reference itself is within 1e-3 of albedo x L.
    let exact = reference_lambert(
        &p,
        glam::DVec3::new(0.3, 0.8, -0.2).normalize(),
        glam::DVec3::splat(albedo),
    );
    assert!((exact.x - albedo * l).abs() < 1e-3 * albedo * l, "{exact}");
    for make in [
        |n| SamplerConfig::Uniform { n, seed: 3 },
        |n| SamplerConfig::Importance { n, seed: 3 },
        |n| SamplerConfig::Stratified { n, seed: 3 },
        |n| SamplerConfig::MedianCut { n },
        |n| SamplerConfig::Lloyd { n, iterations: 8 },
    ] {
        let errs: Vec<f64> = [16, 128, 1024]
            .iter()
            .map(|&n| furnace_error(&make(n).run(&p), l, albedo))
            .collect();
        let name = make(1).name();
        assert!(errs[0] > errs[1] && errs[1] > errs[2], "{name}: {errs:?}");
        assert!(errs[2] < 0.05, "{name}: {errs:?}");
    }
}

#[test]
fn same_seed_same_bits_and_seeds_differ() {
    let p = downsample(&load("city.exr"), 8);
    for (a, b) in [
        (
            SamplerConfig::Uniform { n: 64, seed: 11 },
            SamplerConfig::Uniform { n: 64, seed: 12 },
        ),
        (
            SamplerConfig::Importance { n: 64, seed: 11 },
            SamplerConfig::Importance { n: 64, seed: 12 },
        ),
        (
            SamplerConfig::Stratified { n: 64, seed: 11 },
            SamplerConfig::Stratified { n: 64, seed: 12 },
        ),
    ] {
        let x = a.run(&p);
        let y = a.run(&p);
        let bits = |ls: &LightSet| {
            ls.dir_x
                .iter()
                .chain(&ls.dir_y)
                .chain(&ls.dir_z)
                .chain(&ls.irradiance_r)
                .chain(&ls.irradiance_g)
                .chain(&ls.irradiance_b)
                .map(|v| v.to_bits())
                .collect::<Vec<u32>>()
        };
        assert_eq!(bits(&x), bits(&y), "{a:?}");
        assert_ne!(bits(&x), bits(&b.run(&p)), "{a:?} vs {b:?}");
    }
}

#[test]
fn lloyd_beats_median_cut_on_real_probes() {
    let normals = fibonacci_sphere(256);
    for name in ["city.exr", "studio.exr"] {
        let p = load(name);
        let reference = reference_irradiance_many(&p, &normals);
        for n in [16, 128] {
            let mc = irradiance_error(&median_cut(&p, n).lights, &normals, &reference);
            let ll = irradiance_error(&lloyd(&p, n, 16), &normals, &reference);
            assert!(ll < mc, "{name} N={n}: lloyd {ll} vs median cut {mc}");
        }
    }
}

#[test]
fn voronoi_samplers_invert_to_their_cells() {
    // Each light of uniform and Lloyd carries exactly the power of the texels whose
    // nearest light it is (recomputed here by brute force in f64).
    let p = downsample(&load("city.exr"), 8);
    for cfg in [
        SamplerConfig::Uniform { n: 37, seed: 5 },
        SamplerConfig::Lloyd {
            n: 37,
            iterations: 6,
        },
    ] {
        let ls = cfg.run(&p);
        let mut power = vec![glam::DVec3::ZERO; ls.len()];
        for r in 0..p.height() {
            for c in 0..p.width() {
                let t = p.texel(r, c);
                let k = ls.nearest(p.direction(r, c)).unwrap();
                power[k] +=
                    glam::DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * p.solid_angle(r);
            }
        }
        for (i, want) in power.iter().enumerate() {
            let got = ls.light_irradiance(i);
            assert!(
                (got - *want).length() <= 1e-4 * want.length().max(1e-3 * p.total_power().length()),
                "{cfg:?} light {i}: {got} vs {want}"
            );
        }
    }
}
