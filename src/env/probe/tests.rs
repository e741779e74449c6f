//! Tests of the probe loader: cleaning, sizes, solid angles, orientation.

use super::*;

pub(crate) fn assets() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/probes")
}

#[test]
fn city_loads_clean_with_negatives_counted() {
    let (p, rep) = Probe::load(&assets().join("city.exr"), &LoadOptions::default()).unwrap();
    assert_eq!((p.width(), p.height()), (512, 256));
    // README: 0.12% of texels have a negative channel.
    let frac = rep.negative_texels as f64 / (512.0 * 256.0);
    assert!(frac > 0.0005 && frac < 0.003, "{frac}");
    assert!(p
        .texels()
        .iter()
        .all(|t| t.iter().all(|c| c.is_finite() && *c >= 0.0)));
    // Sky above is brighter than ground below.
    let (top, bottom) = (p.total_power_rows(0..128), p.total_power_rows(128..256));
    assert!(top > bottom, "{top} {bottom}");
}

#[test]
fn sky_loads_with_its_sun_and_high_dynamic_range() {
    // README: 0.01% negative texels, max / median luminance 1.05e5.
    let (p, rep) = Probe::load(&assets().join("sky.exr"), &LoadOptions::default()).unwrap();
    assert_eq!((p.width(), p.height()), (512, 256));
    assert!(rep.negative_texels > 0);
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

#[test]
fn negatives_clamped_and_counted() {
    let t = vec![[1.0, -2.0, 3.0], [-0.0, 0.5, 0.5], [-1.0, -1.0, -1.0]];
    let (p, rep) = Probe::from_texels("neg", 3, 1, t, &LoadOptions::default()).unwrap();
    assert_eq!(rep.negative_texels, 2);
    assert_eq!(p.texel(0, 0), [1.0, 0.0, 3.0]);
    assert_eq!(p.texel(0, 2), [0.0, 0.0, 0.0]);
    assert!(p.texel(0, 1)[0].is_sign_positive());
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
