use super::*;
use crate::brdf::{Lambert, Phong};
use rand::{Rng, SeedableRng};

#[test]
fn half_diff_round_trip_and_guards() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(1);
    for _ in 0..2000 {
        let th: f64 = rng.gen_range(0.0..1.5);
        let td: f64 = rng.gen_range(0.0..1.5);
        let pd: f64 = rng.gen_range(0.0..PI);
        let (wi, wo) = directions_from_half_diff(th, td, pd);
        let (a, b, c) = half_diff_angles(wi, wo).unwrap();
        assert!((a - th).abs() < 1e-9 && (b - td).abs() < 1e-9);
        assert!((c - pd).abs() < 1e-7 || td < 1e-6, "{c} vs {pd}");
    }
    // normal incidence and mirror configurations: no NaN
    let m = MerlBrdf::tabulate(&Lambert { albedo: Vec3::ONE });
    for (wi, wo) in [
        (Vec3::Z, Vec3::Z),
        (Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.6, 0.0, 0.8)),
        (Vec3::new(1.0, 0.0, 1e-7), Vec3::new(-1.0, 0.0, 1e-7)),
    ] {
        assert!(m.eval(wi, wo).is_finite());
    }
    assert!(half_diff_angles(DVec3::X, -DVec3::X).is_none());
}

#[test]
fn round_trip_of_analytic_model_within_tabulation_error() {
    let src = Phong {
        kd: Vec3::new(0.5, 0.3, 0.2),
        ks: Vec3::new(0.3, 0.4, 0.5),
        exponent: 4.0,
    };
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("rt.binary");
    MerlBrdf::tabulate(&src).write(&p).unwrap();
    assert_eq!(
        std::fs::metadata(&p).unwrap().len() as usize,
        MERL_FILE_SIZE
    );
    let m = MerlBrdf::read(&p).unwrap();
    std::fs::remove_file(&p).unwrap();
    // Nearest-bin tabulation: the bins are <= 1 degree in theta_d, phi_d and <= ~2
    // degrees in theta_h (sqrt spacing, widest near 90 degrees), so for this smooth
    // lobe (|d ln f / d angle| <= ~4 per radian) the relative error is bounded by
    // about 4 * 0.018 = 7%; directions are kept 10 degrees above the horizon so that
    // no bin straddles it.
    let mut rng = rand_pcg::Pcg64::seed_from_u64(2);
    let mut worst = 0.0f32;
    for _ in 0..5000 {
        let mut d = || {
            let z: f32 = rng.gen_range(0.18..1.0);
            let a: f32 = rng.gen_range(0.0..std::f32::consts::TAU);
            let s = (1.0 - z * z).sqrt();
            Vec3::new(s * a.cos(), s * a.sin(), z)
        };
        let (wi, wo) = (d(), d());
        let (a, b) = (m.eval(wi, wo), src.eval(wi, wo));
        let e = ((a - b).abs() / b).max_element();
        worst = worst.max(e);
    }
    eprintln!("MERL round trip: max relative error {worst}");
    assert!(worst < 0.07, "max relative error {worst}");
    // below the horizon is zero
    assert_eq!(m.eval(Vec3::new(0.0, 0.6, -0.8), Vec3::Z), Vec3::ZERO);
}

#[test]
fn malformed_files_are_rejected_with_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.binary");
    let good = MerlBrdf::tabulate(&Lambert { albedo: Vec3::ONE }).to_bytes();
    std::fs::write(&p, b"").unwrap();
    let e = MerlBrdf::read(&p).unwrap_err();
    assert!(matches!(e, MerlError::NoHeader { got: 0, .. }), "{e}");
    std::fs::write(&p, &good[..good.len() - 8]).unwrap();
    let e = MerlBrdf::read(&p).unwrap_err();
    assert!(e.to_string().contains("34992012"), "{e}");
    assert!(e.to_string().contains("bad.binary"), "{e}");
    let mut wrong = good.clone();
    wrong[8..12].copy_from_slice(&360i32.to_le_bytes());
    std::fs::write(&p, &wrong).unwrap();
    let e = MerlBrdf::read(&p).unwrap_err();
    assert!(
        matches!(
            e,
            MerlError::Dims {
                dims: [90, 90, 360],
                ..
            }
        ),
        "{e}"
    );
    let mut long = good;
    long.extend_from_slice(&[0u8; 8]);
    std::fs::write(&p, &long).unwrap();
    let e = MerlBrdf::read(&p).unwrap_err();
    assert!(matches!(e, MerlError::Size { .. }), "{e}");
    std::fs::remove_file(&p).unwrap();
    let e = MerlBrdf::read(&dir.path().join("absent.binary")).unwrap_err();
    assert!(
        matches!(
            e,
            MerlError::Io { .. } | MerlError::File(crate::error::FileError::Io { .. })
        ),
        "{e}"
    );
}
