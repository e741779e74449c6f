use super::samples::{sample, SAMPLE_NAMES};
use super::tensor::{self, Dtype};
use super::warp::Table;
use super::*;
use crate::brdf::BlinnPhong;
use crate::conventions::local_direction_f64;
use glam::{DVec3, Vec3};
use std::path::Path;
use std::sync::OnceLock;

fn path() -> &'static Path {
    Path::new("/data/test.bsdf")
}

/// The three test materials, written once per test process.
fn samples() -> &'static Vec<(String, Vec<u8>, RglBrdf)> {
    static S: OnceLock<Vec<(String, Vec<u8>, RglBrdf)>> = OnceLock::new();
    S.get_or_init(|| {
        SAMPLE_NAMES
            .iter()
            .map(|n| {
                let s = sample(n).unwrap();
                let b = RglBrdf::from_bytes(&s.bytes, path()).unwrap();
                (n.to_string(), s.bytes, b)
            })
            .collect()
    })
}

#[test]
fn tensor_round_trip() {
    let bytes = tensor::write(&[
        ("a", Dtype::U8, vec![3], vec![1, 2, 3]),
        (
            "bb",
            Dtype::F32,
            vec![2, 1],
            [1.5f32, -2.0]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect(),
        ),
    ]);
    let f = tensor::parse(&bytes).unwrap();
    assert_eq!(f.len(), 2);
    assert_eq!((f[0].name.as_str(), f[0].data), ("a", &[1u8, 2, 3][..]));
    assert_eq!(f[1].shape, vec![2, 1]);
    assert_eq!(f[1].offset % 8, 0);
    assert_eq!(
        f32::from_le_bytes(f[1].data[4..8].try_into().unwrap()),
        -2.0
    );
}

/// The warp's sample and invert maps are inverse to each other, between parameter nodes
/// too (a table with two interpolated axes and uneven densities).
#[test]
fn warp_sample_inverts_invert() {
    let (nx, ny) = (7, 5);
    let axes = [vec![-1.0, 0.5, 2.0], vec![0.0, 1.0]];
    let data: Vec<f64> = (0..6 * nx * ny)
        .map(|k| 0.1 + ((k * 7919) % 97) as f64 / 30.0)
        .collect();
    for t in [&Table::<f64>::warp(&data, nx, ny, &axes).unwrap()] {
        let mut worst: f64 = 0.0;
        for k in 0..400 {
            let u = ((k * 37) % 101) as f64 / 100.0;
            let v = ((k * 53) % 103) as f64 / 102.0;
            let p = [-1.5 + (k % 9) as f64 * 0.5, (k % 5) as f64 * 0.3];
            let (x, y) = t.sample(u, v, &p);
            let (u2, v2) = t.invert(x, y, &p);
            worst = worst.max((u2 - u).abs()).max((v2 - v).abs());
        }
        assert!(worst < 1e-9, "round trip error {worst}");
    }
    let t32 = Table::<f32>::warp(&data, nx, ny, &axes).unwrap();
    let (u, v) = t32.invert(1.0, 1.0, &[0.0, 0.0]);
    assert!((u - 1.0).abs() < 1e-5 && (v - 1.0).abs() < 1e-5, "{u} {v}");
}

/// A flat spectrum is grey; the luminance of the converted colour is the D65-weighted
/// mean of the spectrum against y_bar (computed here from the CIE table directly).
#[test]
fn spectral_to_srgb() {
    let waves: Vec<f64> = (0..24).map(|k| 370.0 + 20.0 * k as f64).collect();
    let w = colour::srgb_weights(&waves);
    let flat: [f64; 3] = [0, 1, 2].map(|c| w.iter().map(|x| x[c]).sum());
    for c in flat {
        assert!((c - 1.0).abs() < 1e-12, "{flat:?}");
    }
    let s = |l: f64| 0.2 + 0.6 * (-((l - 520.0) / 40.0).powi(2)).exp();
    let rgb: [f64; 3] = [0, 1, 2].map(|c| w.iter().zip(&waves).map(|(x, &l)| x[c] * s(l)).sum());
    let y = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    let t = colour::cie_table();
    let lin = |l: f64| {
        let i = waves
            .iter()
            .filter(|&&v| v < l)
            .count()
            .clamp(1, waves.len() - 1);
        let (a, b) = (waves[i - 1], waves[i]);
        let u = ((l - a) / (b - a)).clamp(0.0, 1.0);
        s(a) * (1.0 - u) + s(b) * u
    };
    let num: f64 = t.iter().map(|r| lin(r[0]) * r[4] * r[2]).sum();
    let den: f64 = t.iter().map(|r| r[4] * r[2]).sum();
    assert!((y - num / den).abs() < 3e-3 * y, "Y {y} vs {}", num / den);
    assert!(
        rgb[1] > rgb[0] && rgb[1] > rgb[2],
        "a green spectrum is green: {rgb:?}"
    );
}

/// Largest polar angle (degrees) of the evaluation check. Beyond it, towards a grazing
/// light, the tables resolve the BRDF coarsely: there the warp packs the outgoing
/// directions far from the lobe into a few samples of the 32x32 grid (measured at 78
/// degrees: up to 45-65% error on the diffuse part of the test materials).
const MAX_POLAR: f64 = 70.0;

/// Relative error statistics of a file's evaluation against its analytic source over
/// pairs of directions (polar 0..[`MAX_POLAR`] degrees, all azimuths): (median, 95th percentile, of
/// |f - f_ref| / max(f_ref, floor)) of the luminance-weighted sum, in f64 and f32.
fn errors(b: &RglBrdf, src: &dyn Brdf, f32_path: bool) -> (f64, f64, f64) {
    let mut errs = Vec::new();
    let mut sum_abs = 0.0;
    let mut sum_ref = 0.0;
    let n = 24;
    for a in 0..n {
        for c in 0..n {
            let ti = (a as f64 + 0.5) / n as f64 * MAX_POLAR.to_radians();
            let to = (c as f64 + 0.5) / n as f64 * MAX_POLAR.to_radians();
            for k in 0..12 {
                let wi = local_direction_f64(ti, 0.3 + k as f64 * 0.55);
                let wo = local_direction_f64(to, 2.1 + k as f64 * 1.3);
                let lum = |v: DVec3| v.dot(DVec3::new(0.2126, 0.7152, 0.0722));
                let r = lum(src.eval_f64(wi, wo));
                let got = if f32_path {
                    lum(b.eval(wi.as_vec3(), wo.as_vec3()).as_dvec3())
                } else {
                    lum(b.eval_f64(wi, wo))
                };
                sum_abs += (got - r).abs();
                sum_ref += r;
                errs.push((got - r).abs() / r.max(0.05));
            }
        }
    }
    errs.sort_by(|x, y| x.partial_cmp(y).unwrap());
    (
        errs[errs.len() / 2],
        errs[errs.len() * 95 / 100],
        sum_abs / sum_ref,
    )
}

/// (median, 95th percentile, mean |error| / mean value) bounds per material, about 1.5x
/// the measured numbers (f64 and f32 alike): blinn-rgb 0.0026, 0.062, 0.0055; aniso-rgb
/// 0.017, 0.21, 0.028; blinn-spectral 0.015, 0.14, 0.016 (sharper lobe, exponent 40).
const BOUNDS: [(&str, f64, f64, f64); 3] = [
    ("blinn-rgb", 0.004, 0.09, 0.008),
    ("aniso-rgb", 0.026, 0.3, 0.04),
    ("blinn-spectral", 0.022, 0.2, 0.023),
];

fn within_bounds(name: &str, e: (f64, f64, f64)) -> bool {
    let (_, bm, bp, bmean) = BOUNDS.iter().find(|x| x.0 == name).unwrap();
    e.0 < *bm && e.1 < *bp && e.2 < *bmean
}

/// The files evaluate to the analytic BRDFs they were written from, within the table's
/// interpolation error (the measured numbers: `cargo test --release rgl -- --nocapture`),
/// in f64 and f32; and the f32 and f64 paths agree with each other.
#[test]
fn files_evaluate_to_their_analytic_source() {
    let measured: Vec<_> = samples()
        .iter()
        .map(|(name, _, b)| {
            let src = sample(name).unwrap().source;
            let e64 = errors(b, src.as_ref(), false);
            let e32 = errors(b, src.as_ref(), true);
            println!(
                "{name}: f64 median {:.4} p95 {:.4} mean {:.4}; f32 median {:.4} p95 {:.4} \
                 mean {:.4}",
                e64.0, e64.1, e64.2, e32.0, e32.1, e32.2
            );
            (name, e64, e32)
        })
        .collect();
    for (name, e64, e32) in measured {
        assert!(within_bounds(name, e64), "{name}: {e64:?}");
        assert!(
            (e32.2 - e64.2).abs() < 1e-3,
            "{name}: f32 {e32:?} f64 {e64:?}"
        );
    }
}

/// A seeded fault must fail the same check: the Blinn-Phong file against a source with
/// exponent 22 instead of 20, or with a diffuse colour 5% brighter.
#[test]
fn seeded_faults_fail_the_evaluation_check() {
    let (_, _, b) = &samples()[0];
    let wrong = BlinnPhong {
        kd: Vec3::new(0.3, 0.2, 0.1),
        ks: Vec3::splat(0.5),
        exponent: 22.0,
    };
    let e = errors(b, &wrong, false);
    assert!(!within_bounds("blinn-rgb", e), "exponent 22 passes: {e:?}");
    let wrong_kd = BlinnPhong {
        kd: Vec3::new(0.3, 0.2, 0.1) * 1.05,
        ks: Vec3::splat(0.5),
        exponent: 20.0,
    };
    let e = errors(b, &wrong_kd, false);
    assert!(
        !within_bounds("blinn-rgb", e),
        "kd 5% brighter passes: {e:?}"
    );
}

/// Isotropic files depend on the azimuths only through their difference; the
/// anisotropic one does not.
#[test]
fn isotropy_is_what_the_file_says() {
    for (name, _, b) in samples() {
        let wi = local_direction_f64(0.6, 0.4);
        let wo = local_direction_f64(0.5, 2.9);
        let turn = |v: DVec3, a: f64| {
            let (s, c) = a.sin_cos();
            DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
        };
        let f0 = b.eval_f64(wi, wo);
        let f1 = b.eval_f64(turn(wi, 1.1), turn(wo, 1.1));
        let rel = (f0 - f1).abs().max_element() / f0.max_element();
        assert_eq!(b.is_isotropic(), name != "aniso-rgb");
        if b.is_isotropic() {
            assert!(rel < 1e-9, "{name}: {rel}");
        } else {
            assert!(rel > 0.05, "{name}: {rel}");
        }
    }
}

/// The offset of field `name`'s header entry's offset value, and its shape values.
fn header_pos(bytes: &[u8], name: &str) -> (usize, usize) {
    let mut pos = 18;
    loop {
        let nl = u16::from_le_bytes(bytes[pos..pos + 2].try_into().unwrap()) as usize;
        let n = std::str::from_utf8(&bytes[pos + 2..pos + 2 + nl]).unwrap();
        let rank_at = pos + 2 + nl;
        let rank = u16::from_le_bytes(bytes[rank_at..rank_at + 2].try_into().unwrap()) as usize;
        let offset_at = rank_at + 3;
        if n == name {
            return (offset_at, offset_at + 8);
        }
        pos = offset_at + 8 + 8 * rank;
    }
}

fn data_of(bytes: &[u8], name: &str) -> usize {
    let (o, _) = header_pos(bytes, name);
    u64::from_le_bytes(bytes[o..o + 8].try_into().unwrap()) as usize
}

/// Hostile input: each case fails with one line naming the file and the field.
#[test]
fn hostile_files_are_refused_naming_the_field() {
    let good = &samples()[0].1;
    let mut cases: Vec<(&str, Vec<u8>, &str)> = Vec::new();
    cases.push(("empty", vec![], "shorter than the 18-byte"));
    cases.push(("truncated header", good[..40].to_vec(), "field"));
    cases.push((
        "truncated data",
        good[..good.len() - 100].to_vec(),
        "does not fit",
    ));
    let mut b = good.clone();
    b[..12].copy_from_slice(b"tensor_filf\0");
    cases.push(("wrong magic", b, "not a tensor file"));
    let mut b = good.clone();
    b[12] = 2;
    cases.push(("version", b, "version 2.0"));
    let mut b = good.clone();
    b[14..18].copy_from_slice(&1_000_000u32.to_le_bytes());
    cases.push(("field count", b, "1000000 fields"));
    let mut b = good.clone();
    let (_, shape) = header_pos(&b, "rgb");
    b[shape..shape + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    cases.push(("absurd shape", b, "field `rgb`: shape"));
    let mut b = good.clone();
    let (_, shape) = header_pos(&b, "vndf");
    b[shape + 16..shape + 24].copy_from_slice(&(1u64 << 40).to_le_bytes());
    cases.push(("huge shape", b, "field `vndf`: shape"));
    let mut b = good.clone();
    let (off, _) = header_pos(&b, "ndf");
    b[off..off + 8].copy_from_slice(&(u64::MAX - 3).to_le_bytes());
    cases.push(("absurd offset", b, "field `ndf`: shape"));
    let mut b = good.clone();
    let d = data_of(&b, "vndf") + 4 * 40;
    b[d..d + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    cases.push(("NaN vndf", b, "field `vndf`: element 40 is NaN"));
    let mut b = good.clone();
    let d = data_of(&b, "rgb") + 4 * 7;
    b[d..d + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    cases.push(("Inf rgb", b, "field `rgb`: element 7 is inf"));
    let mut b = good.clone();
    let d = data_of(&b, "sigma");
    b[d..d + 4].copy_from_slice(&0f32.to_le_bytes());
    cases.push(("zero sigma", b, "field `sigma`: element 0 is 0"));
    let mut b = good.clone();
    let d = data_of(&b, "theta_i") + 4;
    b[d..d + 4].copy_from_slice(&0f32.to_le_bytes());
    cases.push(("theta order", b, "field `theta_i`: not strictly increasing"));
    let mut b = good.clone();
    let d = data_of(&b, "vndf");
    for k in 0..32 * 32 {
        b[d + 4 * k..d + 4 * k + 4].copy_from_slice(&0f32.to_le_bytes());
    }
    cases.push(("zero vndf slice", b, "field `vndf`: slice 0"));
    let mut b = good.clone();
    let (off, _) = header_pos(&b, "ndf");
    b[off - 1] = 11;
    cases.push(("dtype", b, "field `ndf`: dtype float64"));
    b = good.clone();
    let (off, _) = header_pos(&b, "ndf");
    b[off - 1] = 99;
    cases.push(("dtype code", b, "field `ndf`: unknown dtype code 99"));
    let mut b = good.clone();
    let (off, _) = header_pos(&b, "jacobian");
    // rename `jacobian` to `jacobiaN`: missing
    b[off - 3 - 1] = b'N';
    cases.push(("missing field", b, "field `jacobian`: missing"));
    let mut b = good.clone();
    let d = data_of(&b, "ndf") + 4 * 3;
    b[d..d + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    cases.push(("NaN ndf", b, "field `ndf`: element 3 is NaN"));
    let mut b = good.clone();
    let d = data_of(&b, "sigma") + 4 * 5;
    b[d..d + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    cases.push(("NaN sigma", b, "field `sigma`: element 5 is NaN"));
    let spectral = &samples()[2].1;
    let mut b = spectral.clone();
    let d = data_of(&b, "spectra") + 4 * 11;
    b[d..d + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    cases.push(("NaN spectra", b, "field `spectra`: element 11 is NaN"));
    let mut b = spectral.clone();
    let d = data_of(&b, "wavelengths") + 4 * 2;
    b[d..d + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    cases.push((
        "NaN wavelengths",
        b,
        "field `wavelengths`: element 2 is NaN",
    ));
    let mut b = good.clone();
    let (_, shape) = header_pos(&b, "vndf");
    // [n_phi, n_theta, h, w] with n_theta 15 instead of 16 (the data still fits)
    b[shape + 8..shape + 16].copy_from_slice(&15u64.to_le_bytes());
    cases.push((
        "shape against theta_i",
        b,
        "field `vndf`: shape [1, 15, 32, 32]",
    ));
    // Every case is tried and every miss reported (a panic counts as a miss), so that a
    // guard taken out shows as its own case failing.
    let mut missed = Vec::new();
    for (what, bytes, want) in &cases {
        let got = std::panic::catch_unwind(|| {
            RglBrdf::from_bytes(bytes, path())
                .map(|_| ())
                .map_err(|e| e.to_string())
        });
        match got {
            Err(_) => missed.push(format!("{what}: panicked")),
            Ok(Ok(())) => missed.push(format!("{what}: accepted")),
            Ok(Err(e)) => {
                println!("{what}: {e}");
                let one_line = e.starts_with("/data/test.bsdf: ") && !e.contains('\n');
                if !one_line || !e.contains(want) {
                    missed.push(format!("{what}: {e:?} (expected one line with {want:?})"));
                }
            }
        }
    }
    assert!(missed.is_empty(), "{}", missed.join("\n"));
}

/// The fuzz target's seeds: each small material is read, and fits the fuzz runs'
/// `-max_len=4096`.
#[test]
fn tiny_samples_are_valid_fuzz_seeds() {
    for name in SAMPLE_NAMES {
        let s = super::samples::tiny_sample(name).unwrap();
        let b = RglBrdf::from_bytes(&s.bytes, path()).unwrap();
        println!("{name}: {} bytes", s.bytes.len());
        assert!(s.bytes.len() <= 4096, "{name}: {} bytes", s.bytes.len());
        assert_eq!(b.is_isotropic(), name != "aniso-rgb");
        assert_eq!(b.wavelengths.is_some(), name == "blinn-spectral");
    }
}
