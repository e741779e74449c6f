//! brdfkit's RGL reader against Mitsuba 3's (`measured` BSDF), on the same files.
//!
//! The peer images `tests/data/peer/rgl-*.exr` come from `scripts/peer/render_rgl_peer.py`:
//! Mitsuba reads the test materials of `brdfkit::brdf::rgl::samples` (written by
//! `examples/write_rgl.rs`; the JSON records each file's SHA-256, checked here against the
//! bytes the writer gives now) and renders them on the unit sphere of tests/integration/
//! peer.rs under one directional light and under the 128x64 `city` probe. Each scene is
//! rendered here with brdfkit's converged reference (`full` sampler, f64: what `render
//! --reference` does) and compared with the check of peer.rs: the ratio of means within
//! 6 standard errors of the peer's mean plus 2e-4, and per pixel and channel the
//! difference in units of the peer's measured noise (`max |z| <= 6`, `rms z <= 1.3`),
//! with the same stated allowances (tessellation, texel midpoint rule at the horizon).
//!
//! The two readers then differ only where the arithmetic does (f32 there, f64 here) and in
//! colour for the spectral file (held to a stated bound instead, [`SPECTRAL_RATIO`]): Mitsuba renders spectra under the probe's upsampled
//! spectra and converts to sRGB per sample, brdfkit converts the file once (D65 white,
//! src/brdf/rgl/colour.rs) and multiplies RGB. Seeded faults must fail the same check:
//! the jacobian flag cleared (the `D / (4 sigma)` factor of the evaluation left out) and
//! the anisotropic file's colour table turned by 90 degrees in the viewer's azimuth.
//!
//! `cargo test --release --test integration peer_rgl:: -- --nocapture` prints the table.

use crate::peer::{
    check_reference, compare_scene, load_peer, render_config, row, scene, Config, Stats,
};
use brdfkit::brdf::rgl::samples::sample;
use brdfkit::brdf::rgl::tensor;
use brdfkit::brdf::RglBrdf;
use brdfkit::material::Material;
use std::path::Path;

const SCENES: [&str; 6] = [
    "rgl-blinn-rgb-directional",
    "rgl-blinn-rgb-city",
    "rgl-aniso-rgb-directional",
    "rgl-aniso-rgb-city",
    "rgl-blinn-spectral-directional",
    "rgl-blinn-spectral-city",
];

fn sha256_hex(bytes: &[u8]) -> String {
    // The peer script's digest, recomputed with the system's sha256sum (no hashing crate).
    use std::io::Write;
    let mut child = std::process::Command::new("sha256sum")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("sha256sum");
    child.stdin.take().unwrap().write_all(bytes).unwrap();
    let out = child.wait_with_output().unwrap();
    String::from_utf8(out.stdout).unwrap()[..64].to_string()
}

/// The spectral file is held to a stated systematic bound, not to the noise: Mitsuba
/// multiplies the file's spectra by the lights' upsampled spectra per wavelength, brdfkit
/// the file's linear sRGB by the lights' RGB, and the two products differ for a saturated
/// reflectance under a coloured light. Measured: ratio of means 1.027 under the warm
/// directional light (irradiance 3.0/2.5/2.0 on the orange `kd`), 0.999 under `city`; rms
/// |b - p| / mean 3.8% and 1.3%. Bounds about 1.3x those.
const SPECTRAL_RATIO: f64 = 0.035;
const SPECTRAL_RMS: f64 = 0.05;

#[test]
fn rgl_reference_agrees_with_mitsuba_within_its_noise() {
    let mut failures = Vec::new();
    for name in SCENES {
        let peer = load_peer(name);
        let m = &peer.meta["material"];
        let bytes = sample(m["sample"].as_str().unwrap()).unwrap().bytes;
        assert_eq!(
            m["sha256"].as_str().unwrap(),
            sha256_hex(&bytes),
            "{name}: the writer no longer makes the file Mitsuba read"
        );
        let s = scene(&peer.meta, Config::Reference, None);
        let st = compare_scene(&render_config(&s, Config::Reference), &peer);
        println!("{}", row(name, "reference", &st));
        if name.contains("spectral") {
            // Spectra against RGB: see SPECTRAL_RATIO.
            let (dr, rms) = ((st.ratio_of_means - 1.0).abs(), st.rms_rel);
            if dr > SPECTRAL_RATIO || rms > SPECTRAL_RMS {
                failures.push(format!("{name}: ratio {} rms {rms}", st.ratio_of_means));
            }
        } else if let Err(e) = check_reference(&st) {
            failures.push(format!("{name}: {e}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `bytes` with field `name`'s data changed by `edit`.
fn with_field(bytes: &[u8], name: &str, edit: impl FnOnce(&mut [u8])) -> Vec<u8> {
    let f = tensor::parse(bytes)
        .unwrap()
        .into_iter()
        .find(|f| f.name == name)
        .unwrap();
    let (o, n) = (f.offset as usize, f.data.len());
    let mut b = bytes.to_vec();
    edit(&mut b[o..o + n]);
    b
}

fn fault_stats(peer_name: &str, sample_name: &str, bytes: &[u8], what: &str) -> Stats {
    let peer = load_peer(peer_name);
    let mut s = scene(&peer.meta, Config::Reference, None);
    s.material = Material::from(RglBrdf::from_bytes(bytes, Path::new(sample_name)).unwrap());
    let st = compare_scene(&render_config(&s, Config::Reference), &peer);
    println!("{}", row(peer_name, what, &st));
    st
}

#[test]
fn seeded_faults_fail_the_rgl_peer_check() {
    // The jacobian flag cleared: the D / (4 sigma) factor left out.
    let bytes = sample("blinn-rgb").unwrap().bytes;
    let b = with_field(&bytes, "jacobian", |d| d[0] = 0);
    let st = fault_stats("rgl-blinn-rgb-directional", "blinn-rgb", &b, "no-jacob");
    assert!(
        check_reference(&st).is_err(),
        "the jacobian flag ignored passes"
    );
    // The anisotropic file's colour table turned by 90 degrees in the viewer's azimuth
    // (17 nodes over 2 pi: slices shifted by 4).
    let bytes = sample("aniso-rgb").unwrap().bytes;
    let b = with_field(&bytes, "rgb", |d| {
        let slice = d.len() / 17;
        let old = d.to_vec();
        for p in 0..17 {
            let q = (p + 4) % 16;
            d[p * slice..(p + 1) * slice].copy_from_slice(&old[q * slice..(q + 1) * slice]);
        }
    });
    let st = fault_stats("rgl-aniso-rgb-directional", "aniso-rgb", &b, "turned");
    assert!(
        check_reference(&st).is_err(),
        "a table turned by 90 degrees passes"
    );
}
