//! Accuracy of transfer tables against an independent sum: every probe texel a light,
//! the data set's own f64 BRDF ([`crate::brdf::Brdf::eval_f64`]) in f64 frames (the
//! converged reference's arithmetic, not the table's), at random normal/view pairs; with
//! seeded faults that must fail the same check.

use super::build::texel_lights;
use super::*;
use crate::brdf::Brdf;
use crate::conventions::{hemi_texcoord, local_angles, ShadingFrame};
use crate::env::{LoadOptions, Probe};
use crate::sh::dataset::ShDataset;
use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng};

/// A 64 x 32 probe: a smooth sky gradient, a warm ground, and three small bright sources
/// (about 40% of the power), one of them 4 degrees from +y.
fn probe() -> Probe {
    let (w, h) = (64, 32);
    let mut texels = Vec::with_capacity(w * h);
    for row in 0..h {
        for col in 0..w {
            let v = (row as f32 + 0.5) / h as f32;
            let u = (col as f32 + 0.5) / w as f32;
            let mut t = if v < 0.5 {
                [0.4 + 0.6 * v, 0.6 + 0.4 * v, 1.0]
            } else {
                [0.5, 0.35 + 0.1 * (6.0 * u).sin(), 0.2]
            };
            for (sr, sc, e) in [(0usize, 5usize, 60.0f32), (9, 20, 25.0), (14, 45, 15.0)] {
                if row == sr && (col == sc || col == sc + 1) {
                    t = [e, 0.9 * e, 0.7 * e];
                }
            }
            texels.push(t);
        }
    }
    Probe::from_texels("synthetic", w, h, texels, &LoadOptions::default())
        .unwrap()
        .0
}

/// A 4-band data set on an 8 x 4 view grid with a glossy-looking coefficient pattern.
fn dataset(includes_cosine: bool) -> ShDataset {
    let (nu, nv, bands) = (8, 4, 4);
    let nt = bands * bands;
    let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
    let mut coeffs = Vec::with_capacity(nu * nv * 3 * nt);
    for _ in 0..nu * nv * 3 {
        for k in 0..nt {
            let l = (k as f64).sqrt() as usize;
            let scale = 0.6f32.powi(l as i32);
            let v = if k == 0 {
                0.5
            } else {
                rng.gen_range(-0.3..0.3) * scale
            };
            coeffs.push(v);
        }
    }
    ShDataset::new(nu, nv, bands, includes_cosine, "test", coeffs).unwrap()
}

/// Exact outgoing radiance: `sum_texels f(wi, wo) [cos] L Omega`, f64, the texels of
/// `lights` (every texel of the probe).
fn exact(ds: &ShDataset, lights: &crate::env::LightSet, n: Vec3, wo: DVec3) -> DVec3 {
    let f = ShadingFrame::from_normal(n);
    let (t, b, nn) = (f.t.as_dvec3(), f.b.as_dvec3(), f.n.as_dvec3());
    let mut sum = DVec3::ZERO;
    for i in 0..lights.len() {
        let d = lights.direction(i);
        let wi = DVec3::new(d.dot(t), d.dot(b), d.dot(nn));
        if wi.z > 0.0 {
            let v = ds.eval_f64(wi, wo);
            let v = if ds.includes_cosine() { v } else { v * wi.z };
            sum += v * lights.light_irradiance(i);
        }
    }
    sum
}

/// Relative RMSE (RGB, over pairs) of table + `k` exact texels against [`exact`] at 400
/// random normal/view pairs (normals uniform on the sphere, views uniform on the upper
/// hemisphere); the table built with `fault`.
fn error(includes_cosine: bool, k: usize, fault: BuildFault) -> f64 {
    error_in(includes_cosine, k, fault, -1.0, 0.0)
}

/// [`error`] with normals drawn uniformly from the caps `|n.y| >= min_abs_y` (-1: the
/// whole sphere).
/// The probe turned by `rotation` radians about +y.
fn error_in(
    includes_cosine: bool,
    k: usize,
    fault: BuildFault,
    min_abs_y: f32,
    rotation: f64,
) -> f64 {
    let p = probe().with_rotation(rotation);
    let ds = dataset(includes_cosine);
    let basis = TransferBasis::Sh {
        bands: 4,
        cosine: !includes_cosine,
    };
    let all: Vec<usize> = (0..p.width() * p.height()).collect();
    let every = texel_lights(&p, &all, 1.0);
    let split = brightest_texels(&p, k);
    let exact_lights = texel_lights(&p, &split, 1.0);
    let table = build_table(&p, basis, (32, 33), &split, 1.0, &Progress::hidden(), fault).unwrap();
    let mut rng = rand_pcg::Pcg64::seed_from_u64(11);
    let (mut num, mut den) = (0.0, 0.0);
    let mut c = vec![0.0f32; 3 * 16];
    for _ in 0..400 {
        let mut y: f32 = rng.gen_range(min_abs_y.max(-1.0)..1.0);
        if min_abs_y > 0.0 && rng.gen_bool(0.5) {
            y = -y;
        }
        let a: f32 = rng.gen_range(0.0..std::f32::consts::TAU);
        let r = (1.0 - y * y).max(0.0).sqrt();
        let n = Vec3::new(r * a.cos(), y, r * a.sin());
        let wz: f32 = rng.gen_range(0.05..1.0);
        let wa: f32 = rng.gen_range(0.0..std::f32::consts::TAU);
        let wr = (1.0 - wz * wz).sqrt();
        let wo = Vec3::new(wr * wa.cos(), wr * wa.sin(), wz);
        let want = exact(&ds, &every, n, wo.as_dvec3());
        let (pp, aa) = local_angles(wo);
        let (s, t) = hemi_texcoord(pp, aa);
        ds.lookup_coeffs(s, t, ds.coeff_lookup, &mut c);
        let got = table.radiance(n, &c).as_dvec3() + exact(&ds, &exact_lights, n, wo.as_dvec3());
        num += (got - want).length_squared();
        den += want.length_squared();
    }
    crate::metrics::relative_l2(num, den)
}

/// Bound of the check: 1.5% relative RMSE on this 32 x 33 table of a 64 x 32 probe (the
/// shipped 128 x 65 default on 512 x 256 probes is measured in the report, not here).
const BOUND: f64 = 0.015;

#[test]
fn table_matches_the_exact_texel_sum() {
    for cosine_in_data in [true, false] {
        for k in [0, 4] {
            let e = error(cosine_in_data, k, BuildFault::None);
            eprintln!("includes_cosine {cosine_in_data}, exact lights {k}: rel RMSE {e:.5}");
            assert!(
                e < BOUND,
                "rel RMSE {e} >= {BOUND} (cosine {cosine_in_data}, k {k})"
            );
        }
    }
}

/// Near the poles (normals within 3 degrees of +-y), where a lat-long grid's nodes crowd
/// and the shading frame spins with the azimuth: the same bound.
#[test]
fn table_matches_near_the_poles() {
    let cap = 3f32.to_radians().cos();
    for cosine_in_data in [true, false] {
        let e = error_in(cosine_in_data, 4, BuildFault::None, cap, 0.0);
        eprintln!("near the poles, includes_cosine {cosine_in_data}: rel RMSE {e:.5}");
        assert!(e < BOUND, "near-pole rel RMSE {e} >= {BOUND}");
    }
}

/// A probe rotated by 0.7 rad (not a multiple of the grid's azimuth step): the lookup
/// undoes the rotation; the same bound.
#[test]
fn rotated_probe_matches() {
    let e = error_in(true, 4, BuildFault::None, -1.0, 0.7);
    eprintln!("rotated probe: rel RMSE {e:.5}");
    assert!(e < BOUND, "rotated rel RMSE {e} >= {BOUND}");
}

#[test]
fn seeded_faults_fail_the_check() {
    for fault in [BuildFault::TransposedAxes, BuildFault::NoHemisphereClip] {
        let e = error(true, 4, fault);
        eprintln!("{fault:?}: rel RMSE {e:.4}");
        assert!(e > BOUND, "{fault:?} passed the check: rel RMSE {e}");
    }
}

/// Lambert: the irradiance table against [`crate::env::lightset::reference_irradiance`] (the
/// light-set module's exact texel sum, an independent peer).
#[test]
fn irradiance_table_matches_reference_irradiance() {
    let p = probe();
    let table = build_table(
        &p,
        TransferBasis::Irradiance,
        (32, 33),
        &[],
        1.0,
        &Progress::hidden(),
        BuildFault::None,
    )
    .unwrap();
    let normals = crate::env::lightset::fibonacci_sphere(300);
    let reference = crate::env::lightset::reference_irradiance_many(&p, &normals);
    let got: Vec<DVec3> = normals
        .iter()
        .map(|n| table.radiance(n.as_vec3(), &[1.0, 1.0, 1.0]).as_dvec3())
        .collect();
    let (num, den) = crate::metrics::squared_error_sums(&got, &reference);
    let e = crate::metrics::relative_l2(num, den);
    eprintln!("irradiance rel RMSE {e:.5}");
    assert!(e < 0.01, "irradiance rel RMSE {e}");
}

/// The same table for 1 and 2 threads, bit for bit.
#[test]
fn build_is_deterministic_across_thread_counts() {
    let p = probe();
    let basis = TransferBasis::Sh {
        bands: 3,
        cosine: false,
    };
    let build = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                build_table(
                    &p,
                    basis,
                    (16, 9),
                    &[3],
                    1.0,
                    &Progress::hidden(),
                    BuildFault::None,
                )
                .unwrap()
            })
    };
    assert_eq!(build(1), build(2));
}

/// `p`'s table for `basis` on a 16 x 9 grid without texels 5 and 70, built on a one-thread
/// pool whose thread has `switch(true)` run before and `switch(false)` after (build.rs's
/// test-only switches are thread-local).
fn build_on_one_thread(
    p: &Probe,
    basis: TransferBasis,
    fault: BuildFault,
    switch: impl Fn(bool) + Sync,
) -> TransferTable {
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    one_thread.install(|| {
        switch(true);
        let t = build_table(p, basis, (16, 9), &[5, 70], 1.0, &Progress::hidden(), fault);
        switch(false);
        t.unwrap()
    })
}

/// The same table, bit for bit, on every kernel path this CPU runs: the multiply-adds on
/// the f64 lanes (`correlate.rs`) against the portable path's per-lane scalar code, on an
/// SH basis with an odd number of terms (one weight row transformed alone), one with the
/// cosine, and the irradiance; the 64-texel-wide probe leaves 33 frequencies, so the
/// padded lane group is exercised too.
#[test]
fn lane_paths_give_the_same_table() {
    use crate::lanes::KernelPath;
    let p = probe();
    for (k, skipped) in KernelPath::unavailable() {
        eprintln!("kernel path {} not run here (needs {skipped})", k.name());
    }
    for basis in [
        TransferBasis::Sh {
            bands: 3,
            cosine: false,
        },
        TransferBasis::Sh {
            bands: 4,
            cosine: true,
        },
        TransferBasis::Irradiance,
    ] {
        let bits = |path: KernelPath| {
            let t = build_on_one_thread(&p, basis, BuildFault::None, |on| {
                build::LANE_PATH.with(|l| l.set(on.then_some(path)))
            });
            t.values().iter().map(|v| v.to_bits()).collect::<Vec<u32>>()
        };
        let oracle = bits(KernelPath::Portable);
        for path in KernelPath::available() {
            assert!(bits(path) == oracle, "{basis:?}: {} differs", path.name());
        }
    }
}

/// The FFT build (the correlation theorem, `build.rs`) against the direct sum it replaces,
/// on an SH basis with the cosine and the irradiance: every value within 1e-6 of the
/// table's largest magnitude (both are f64 sums rounded to f32; measured below). A seeded
/// transposed axis in the FFT build is far outside the same bound.
#[test]
fn fft_build_matches_the_direct_sum() {
    let p = probe();
    for basis in [
        TransferBasis::Sh {
            bands: 4,
            cosine: true,
        },
        TransferBasis::Irradiance,
    ] {
        let build = |direct: bool, fault| {
            build_on_one_thread(&p, basis, fault, |on| {
                build::DIRECT_SUM.with(|d| d.set(on && direct))
            })
        };
        let direct = build(true, BuildFault::None);
        let worst = |t: &TransferTable| {
            let scale = direct.values().iter().fold(0.0f32, |m, v| m.max(v.abs()));
            t.values()
                .iter()
                .zip(direct.values())
                .map(|(a, b)| (a - b).abs() / scale)
                .fold(0.0f32, f32::max)
        };
        let e = worst(&build(false, BuildFault::None));
        eprintln!("{basis:?}: FFT vs direct, largest difference / largest value {e:.2e}");
        assert!(e < 1e-6, "{basis:?}: {e}");
        let f = worst(&build(false, BuildFault::TransposedAxes));
        assert!(f > 1e-2, "{basis:?}: seeded fault {f}");
    }
}

/// The residual's downsampling factor: the smallest that brings the width to at most
/// `max(max_width, 4 nu)` with whole texels per node shift, else the largest below.
#[test]
fn residual_factor_keeps_whole_shifts() {
    use build::residual_factor;
    assert_eq!(residual_factor(512, 256, 128, 512), 1);
    assert_eq!(residual_factor(1024, 512, 128, 512), 2);
    assert_eq!(residual_factor(4096, 2048, 128, 512), 8);
    assert_eq!(residual_factor(8192, 4096, 128, 512), 16);
    // 3200 / 7 is not whole, 3200 / 25 = 128 is under 4 nodes' texels: 3200 / 5 = 640.
    assert_eq!(residual_factor(3200, 1600, 128, 512), 5);
    // A grid wider than the limit's quarter keeps four texels per node.
    assert_eq!(residual_factor(4096, 2048, 256, 512), 4);
    // No admissible factor (the height): the full probe.
    assert_eq!(residual_factor(4096, 2047, 128, 512), 1);
    assert_eq!(residual_factor(64, 32, 8, usize::MAX), 1);
}

/// A table from the residual downsampled 2 x 2 against the one from the full residual, on
/// the 64 x 32 probe (its bright texels split off): every value within 1% of the table's
/// largest magnitude (measured: 5.3e-3 for 4 bands, 3.7e-3 for the irradiance). A seeded
/// transposed axis is far outside.
#[test]
fn downsampled_residual_matches_the_full_one() {
    let p = probe();
    let exact = brightest_texels(&p, 6);
    for basis in [
        TransferBasis::Sh {
            bands: 4,
            cosine: true,
        },
        TransferBasis::Irradiance,
    ] {
        let table = |max_width, fault| {
            build::build_table_from_residual(
                &p,
                basis,
                (8, 9),
                (&exact, max_width),
                1.0,
                &Progress::hidden(),
                fault,
            )
            .unwrap()
        };
        let full = table(usize::MAX, BuildFault::None);
        let scale = full.values().iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let worst = |t: &TransferTable| {
            t.values()
                .iter()
                .zip(full.values())
                .map(|(a, b)| (a - b).abs() / scale)
                .fold(0.0f32, f32::max)
        };
        let e = worst(&table(32, BuildFault::None));
        eprintln!(
            "{basis:?}: 32 x 16 residual vs 64 x 32, largest difference / largest value {e:.2e}"
        );
        assert!(e < 1e-2, "{basis:?}: {e}");
        let f = worst(&table(32, BuildFault::TransposedAxes));
        assert!(f > 5e-2, "{basis:?}: seeded fault {f}");
    }
}

/// The bounded-heap choice of the brightest texels against a full sort (weight descending,
/// index ascending), on a probe with many equal texels (ties decided by index).
#[test]
fn brightest_texels_agree_with_a_full_sort() {
    let (w, h) = (64, 32);
    let texels: Vec<[f32; 3]> = (0..w * h)
        .map(|i| {
            let v = ((i * 7919) % 13) as f32;
            [v, v * 0.5, 1.0]
        })
        .collect();
    let (p, _) = Probe::from_texels("ties", w, h, texels, &LoadOptions::default()).unwrap();
    let mut order: Vec<(f64, usize)> = p
        .texels()
        .iter()
        .enumerate()
        .map(|(i, t)| (crate::env::luminance(*t) * p.solid_angle(i / w), i))
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    for k in [0, 1, 5, 64, 300, w * h, w * h + 10] {
        let want: Vec<usize> = order.iter().take(k).map(|o| o.1).collect();
        assert_eq!(brightest_texels(&p, k), want, "k = {k}");
    }
}
