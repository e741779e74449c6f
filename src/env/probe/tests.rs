//! Tests of the probe loader: cleaning, sizes, solid angles, orientation.

use super::*;

pub(crate) fn assets() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/probes")
}

/// The one original (uncleaned, DWAB) probe kept as a fixture: the Poly Haven sky as
/// `assets/probes/sky.exr` was before the cleaning (tests/data/probes/README.md).
pub(crate) fn dwab_original() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/probes/sky-dwab.exr")
}

#[test]
fn shipped_probes_are_stored_clean() {
    for name in ["city.exr", "studio.exr", "sky.exr"] {
        let path = assets().join(name);
        // The file itself holds no negative or non-finite channel: nothing for the loader
        // to clean, nothing to warn about.
        let (w, h, raw) = read::read_exr(&path, &LoadOptions::default()).unwrap();
        assert_eq!((w, h), (512, 256), "{name}");
        assert!(
            raw.iter()
                .all(|t| t.iter().all(|c| c.is_finite() && *c >= 0.0)),
            "{name}: a stored texel is negative or not finite"
        );
        let (p, rep) = Probe::load(&path, &LoadOptions::default()).unwrap();
        assert_eq!(rep.negative_texels, 0, "{name}");
        assert_eq!(rep.negative_power_moved, [0.0; 3], "{name}");
        assert_eq!(rep.negative_warning(name), None, "{name}");
        assert_eq!(p.texels(), &raw[..], "{name}: loading changed a texel");
    }
    // Sky above is brighter than ground below.
    let (p, _) = Probe::load(&assets().join("city.exr"), &LoadOptions::default()).unwrap();
    let (top, bottom) = (p.total_power_rows(0..128), p.total_power_rows(128..256));
    assert!(top > bottom, "{top} {bottom}");
}

#[test]
fn the_shipped_sky_is_its_original_cleaned_bit_for_bit() {
    // examples/clean_probes.rs wrote assets/probes/sky.exr from the original: the loader's
    // output on the original, stored losslessly. So renders keep the bits they had when the
    // original was shipped.
    let (cleaned, rep) = Probe::load(&dwab_original(), &LoadOptions::default()).unwrap();
    assert!(rep.negative_texels > 0, "the fixture is the dirty original");
    let (shipped, _) = Probe::load(&assets().join("sky.exr"), &LoadOptions::default()).unwrap();
    let bits =
        |p: &Probe| -> Vec<[u32; 3]> { p.texels().iter().map(|t| t.map(f32::to_bits)).collect() };
    assert!(
        bits(&cleaned) == bits(&shipped),
        "assets/probes/sky.exr is not the cleaned original"
    );
}

#[test]
fn sky_loads_with_its_sun_and_high_dynamic_range() {
    // assets/probes/README.md: max / median luminance 1.05e5 (cleaned, as the original).
    let (p, rep) = Probe::load(&assets().join("sky.exr"), &LoadOptions::default()).unwrap();
    assert_eq!((p.width(), p.height()), (512, 256));
    assert_eq!(rep.negative_texels, 0);
    let mut lum: Vec<f64> = p
        .texels()
        .iter()
        .map(|t| crate::env::luminance(*t))
        .collect();
    lum.sort_by(f64::total_cmp);
    let ratio = lum[lum.len() - 1] / lum[lum.len() / 2];
    assert!(ratio > 5e4, "max / median luminance {ratio}");
    let (top, bottom) = (p.total_power_rows(0..128), p.total_power_rows(128..256));
    assert!(top > bottom, "{top} {bottom}");
}

impl Probe {
    fn total_power_rows(&self, rows: std::ops::Range<usize>) -> f64 {
        rows.map(|r| {
            (0..self.width)
                .map(|c| self.texel(r, c)[1] as f64)
                .sum::<f64>()
                * self.solid_angle(r)
        })
        .sum()
    }
}

/// Exact solid angle of a texel in row `row` of a `w x h` probe, written out here from the
/// closed form `(2 pi / w)(cos(pi row / h) - cos(pi (row + 1) / h))`, not taken from the
/// loader.
fn omega(row: usize, w: usize, h: usize) -> f64 {
    let pi = std::f64::consts::PI;
    std::f64::consts::TAU / w as f64
        * ((pi * row as f64 / h as f64).cos() - (pi * (row + 1) as f64 / h as f64).cos())
}

/// Per channel signed integral `sum v x omega`, in f64.
fn signed_power(t: &[[f32; 3]], w: usize, h: usize) -> [f64; 3] {
    let mut p = [0.0; 3];
    for (i, v) in t.iter().enumerate() {
        for c in 0..3 {
            p[c] += v[c] as f64 * omega(i / w, w, h);
        }
    }
    p
}

/// The cleaning contract: no channel negative, and each channel's signed integral kept to
/// `1e-6` relative (of the channel's absolute mass, so a channel near zero is not
/// divided by ~0).
fn check_cleaned(raw: &[[f32; 3]], cleaned: &[[f32; 3]], w: usize, h: usize) -> Result<(), String> {
    if let Some(i) = cleaned.iter().position(|t| t.iter().any(|&c| c < 0.0)) {
        return Err(format!("texel {i} negative: {:?}", cleaned[i]));
    }
    let (before, after) = (signed_power(raw, w, h), signed_power(cleaned, w, h));
    for c in 0..3 {
        let scale: f64 = raw
            .iter()
            .enumerate()
            .map(|(i, v)| (v[c] as f64).abs() * omega(i / w, w, h))
            .sum();
        let rel = (after[c] - before[c]).abs() / scale.max(f64::MIN_POSITIVE);
        if rel > 1e-6 {
            return Err(format!(
                "channel {c}: signed power {} -> {} (relative change {rel:.3e} > 1e-6)",
                before[c], after[c]
            ));
        }
    }
    Ok(())
}

/// The seeded fault: plain clamping, what the loader did before (see `clean.rs`).
fn clamp_only(raw: &[[f32; 3]]) -> Vec<[f32; 3]> {
    raw.iter().map(|t| t.map(|c| c.max(0.0))).collect()
}

#[test]
fn dwab_ringing_keeps_signed_power_and_ends_non_negative() {
    // The real DWAB ringing of the original sky probe (tests/data/probes/README.md: a few
    // texels around the sun at -3394, 13.5% of the luminance power).
    let path = dwab_original();
    let (w, h, raw) = read::read_exr(&path, &LoadOptions::default()).unwrap();
    let (p, rep) = Probe::load(&path, &LoadOptions::default()).unwrap();
    check_cleaned(&raw, p.texels(), w, h).unwrap_or_else(|e| panic!("{e}"));
    // The report: texels counted, power moved = the negative mass, computed here.
    let negatives = raw.iter().filter(|t| t.iter().any(|&c| c < 0.0)).count();
    assert!(negatives > 0, "the fixture has negative texels");
    assert_eq!(rep.negative_texels, negatives);
    for c in 0..3 {
        let neg: f64 = raw
            .iter()
            .enumerate()
            .map(|(i, v)| (-(v[c] as f64)).max(0.0) * omega(i / w, w, h))
            .sum();
        assert!(
            (rep.negative_power_moved[c] - neg).abs() <= 1e-12 * neg.max(1.0),
            "channel {c}: {} vs {neg}",
            rep.negative_power_moved[c]
        );
        assert_eq!(rep.negative_power_unplaced[c], 0.0);
    }
    // Ringing this strong moves a large share of the power: more than 10% of it.
    let (moved, total) = rep.luminance_power_moved();
    assert!(moved > 0.1 * total, "{moved} of {total}");
    // The seeded fault, plain clamping, breaks the contract on the real file.
    let err = check_cleaned(&raw, &clamp_only(&raw), w, h)
        .expect_err("clamping must not keep the signed power");
    assert!(err.contains("relative change"), "{err}");
    // One line naming the probe as given.
    let warning = rep.negative_warning("probes/sky-dwab.exr").unwrap();
    assert!(
        warning.starts_with("probes/sky-dwab.exr: ")
            && warning.contains("% of the probe's")
            && !warning.contains('\n'),
        "{warning}"
    );
}

#[test]
fn negative_texel_mass_comes_from_its_3x3_window_by_power() {
    // 8x4 probe, all 1 except texel (1, 3) = -0.5. Its 3x3 window (rows 0-2, cols 2-4) has
    // 3 texels of row 0 and 5 of rows 1-2 (rows 1 and 2 have the same solid angle), positive
    // mass S = 3 omega0 + 5 omega1 >= 0.5 omega1, so those 8 texels are scaled by
    // k = 1 - 0.5 omega1 / S and every other texel keeps 1.
    let (w, h) = (8, 4);
    let mut t = vec![[1.0f32; 3]; w * h];
    t[w + 3] = [-0.5, 1.0, -0.5];
    let (p, rep) = Probe::from_texels("hand", w, h, t.clone(), &LoadOptions::default()).unwrap();
    let (o0, o1) = (omega(0, w, h), omega(1, w, h));
    let k = 1.0 - 0.5 * o1 / (3.0 * o0 + 5.0 * o1);
    for row in 0..h {
        for col in 0..w {
            let in_window = row <= 2 && (2..=4).contains(&col) && (row, col) != (1, 3);
            let want_rb = if (row, col) == (1, 3) {
                0.0
            } else if in_window {
                k
            } else {
                1.0
            };
            let got = p.texel(row, col);
            assert!(
                (got[0] as f64 - want_rb).abs() < 1e-7 && (got[2] as f64 - want_rb).abs() < 1e-7,
                "({row}, {col}): {got:?}, want {want_rb}"
            );
            assert_eq!(got[1], 1.0, "({row}, {col}): green untouched");
        }
    }
    assert_eq!(rep.negative_texels, 1);
    assert!((rep.negative_power_moved[0] - 0.5 * o1).abs() < 1e-15);
    assert_eq!(rep.negative_power_moved[1], 0.0);
    check_cleaned(&t, p.texels(), w, h).unwrap();
}

#[test]
fn too_little_mass_nearby_widens_the_window() {
    // One row (every texel the same solid angle 4 pi / 8): [1, 1, 1, -3, 1, 1, 1, 1]. The
    // radius-1 window holds mass 2 < 3; radius 2 holds 4, so its four texels are scaled
    // by 1 - 3/4 and the rest keep 1.
    let mut t = vec![[1.0f32; 3]; 8];
    t[3] = [-3.0; 3];
    let (p, rep) = Probe::from_texels("widen", 8, 1, t.clone(), &LoadOptions::default()).unwrap();
    let want = [1.0, 0.25, 0.25, 0.0, 0.25, 0.25, 1.0, 1.0];
    for (col, &v) in want.iter().enumerate() {
        assert_eq!(p.texel(0, col), [v; 3], "col {col}");
    }
    assert!((rep.negative_power_moved[0] - 3.0 * 4.0 * std::f64::consts::PI / 8.0).abs() < 1e-12);
    check_cleaned(&t, p.texels(), 8, 1).unwrap();
    assert!(check_cleaned(&t, &clamp_only(&t), 8, 1).is_err());
    // -0.0 is no negative mass and ends +0.0.
    let (p, rep) = Probe::from_texels(
        "z",
        2,
        1,
        vec![[-0.0, 1.0, 1.0]; 2],
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(rep.negative_texels, 0);
    assert!(p.texel(0, 0)[0].is_sign_positive());
}

#[test]
fn a_channel_with_negative_total_ends_black_and_reports_the_unplaced_power() {
    let t = vec![[1.0, 1.0, 1.0], [-3.0, 1.0, 1.0], [1.0, 1.0, 1.0], [1.0; 3]];
    let (p, rep) = Probe::from_texels("neg", 4, 1, t, &LoadOptions::default()).unwrap();
    assert!(p.texels().iter().all(|t| t[0] == 0.0 && t[1] == 1.0));
    let lune = std::f64::consts::PI; // 4 pi / 4
    assert!(
        (rep.negative_power_unplaced[0] - 0.0).abs() < 1e-12,
        "{rep:?}"
    );
    // 3 lunes of +1 against one of -3: exactly balanced, nothing unplaced; now unbalance.
    let t = vec![[1.0, 1.0, 1.0], [-4.0, 1.0, 1.0], [1.0, 1.0, 1.0], [1.0; 3]];
    let (p, rep) = Probe::from_texels("neg", 4, 1, t, &LoadOptions::default()).unwrap();
    assert!(p.texels().iter().all(|t| t[0] == 0.0));
    assert!(
        (rep.negative_power_unplaced[0] - lune).abs() < 1e-12,
        "{rep:?}"
    );
    assert!(
        (rep.negative_power_moved[0] - 3.0 * lune).abs() < 1e-12,
        "{rep:?}"
    );
    assert!(rep
        .negative_warning("neg")
        .unwrap()
        .contains("could not be placed"));
}

#[test]
fn non_finite_is_an_error_naming_file_and_count_unless_zeroed() {
    let t = vec![[1.0, f32::NAN, 3.0], [f32::INFINITY, 0.5, 0.5], [1.0; 3]];
    let err = Probe::from_texels("bad.exr", 3, 1, t.clone(), &LoadOptions::default()).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("bad.exr") && msg.contains("2 non-finite"),
        "{msg}"
    );
    let opts = LoadOptions {
        zero_non_finite: true,
        ..Default::default()
    };
    let (p, rep) = Probe::from_texels("bad.exr", 3, 1, t, &opts).unwrap();
    assert_eq!(rep.non_finite_zeroed, 2);
    assert_eq!(p.texel(0, 0), [0.0; 3]);
    assert_eq!(p.texel(0, 2), [1.0; 3]);
}

#[test]
fn empty_and_oversized_rejected() {
    let e = Probe::from_texels("empty.hdr", 0, 4, vec![], &LoadOptions::default());
    let msg = e.unwrap_err().to_string();
    assert!(msg.contains("empty.hdr") && msg.contains("empty"), "{msg}");
    let opts = LoadOptions {
        max_texels: 10,
        ..Default::default()
    };
    let e = Probe::from_texels("big", 4, 4, vec![[0.0; 3]; 16], &opts).unwrap_err();
    assert!(matches!(e, ProbeError::TooLarge { .. }));
    let e = Probe::load(&assets().join("city.exr"), &opts).unwrap_err();
    assert!(e.to_string().contains("city.exr"), "{e}");
}

#[test]
fn missing_file_and_bad_extension_name_the_file() {
    let e = Probe::load(Path::new("/nonexistent/x.exr"), &LoadOptions::default());
    assert!(e.unwrap_err().to_string().contains("/nonexistent/x.exr"));
    let e = Probe::load(Path::new("probe.png"), &LoadOptions::default());
    assert!(matches!(e, Err(ProbeError::UnsupportedFormat { .. })));
}

#[test]
fn radiance_hdr_round_trip_matches_exr_layout() {
    // Write a small non-square .hdr with image's encoder and check orientation: the
    // first row written is row 0 (+y pole).
    let (w, h) = (5usize, 3usize);
    let data: Vec<image::Rgb<f32>> = (0..w * h)
        .map(|i| image::Rgb([i as f32, 0.5, 1.0 / (1.0 + i as f32)]))
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.hdr");
    let f = std::fs::File::create(&path).unwrap();
    image::codecs::hdr::HdrEncoder::new(f)
        .encode(&data, w, h)
        .unwrap();
    let (p, rep) = Probe::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!((p.width(), p.height(), rep.negative_texels), (w, h, 0));
    for i in 0..w * h {
        let t = p.texel(i / w, i % w);
        // RGBE keeps ~1% precision.
        assert!(
            (t[0] - i as f32).abs() <= 0.01 * i as f32 + 1e-6,
            "{i} {t:?}"
        );
    }
}

#[test]
fn one_row_probe_sits_on_equator() {
    let (p, _) =
        Probe::from_texels("row", 4, 1, vec![[1.0; 3]; 4], &LoadOptions::default()).unwrap();
    assert!(p.direction(0, 0).y.abs() < 1e-12);
    let omega = p.solid_angle(0);
    assert!((omega - std::f64::consts::PI).abs() < 1e-12);
    assert!((p.total_power().x - 4.0 * std::f64::consts::PI).abs() < 1e-9);
}

#[test]
fn rotation_round_trips_texels() {
    let (p, _) =
        Probe::from_texels("r", 8, 4, vec![[1.0; 3]; 32], &LoadOptions::default()).unwrap();
    let p = p.with_rotation(0.7);
    for row in 0..4 {
        for col in 0..8 {
            assert_eq!(p.texel_of(p.direction(row, col)), (row, col));
        }
    }
    // Column 0 of an unrotated probe faces +z; rotated by pi/2 it faces +x-ish.
    let q = p.clone().with_rotation(std::f64::consts::FRAC_PI_2);
    let d0 = q.direction(1, 0);
    assert!(d0.x > 0.0 && d0.z.abs() < d0.x);
}
