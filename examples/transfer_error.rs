//! Error of `[env] method = "transfer"` against the converged reference, for people: a
//! table, one row per material and probe.
//!
//! ```sh
//! cargo run --release --example transfer_error -- [SIZE] [k=EXACT_LIGHTS] [m=MATERIAL] [PROBE...]
//! ```
//!
//! `k=` sets `exact_lights` (default 64, the `[env]` default); `m=` keeps one material (repeatable).
//! For every library SH material and Lambert (albedo 0.8) under each shipped probe (or the
//! ones named: `city`, `studio`, `sky`), renders a 256-segment sphere at SIZE x SIZE
//! (default 64) with the transfer method (default grid 128 x 65, 64 exact lights) and with
//! the converged reference ([`RenderOptions::converged_reference`] on `sampler = "full"`,
//! f64, every texel a light), and prints:
//! - rel RMSE: relative RMSE over the image ([`brdfkit::metrics::relative_rmse`]);
//! - p99: the 99th percentile over covered pixels of the per-pixel relative error
//!   `|x - r| / |r|` (RGB norms), pixels with `|r|` below 1% of the mean `|r|` left out;
//! - neg px: covered pixels whose reference has a negative channel, and p99 (>= 0): the p99
//!   over the other pixels. The two columns test one explanation of the p99: an SH fit of a
//!   glossy BRDF rings below zero away from its lobe, and under a few dominant lights
//!   (studio) the reference sums those negative lobes into pixels near or below zero,
//!   where any absolute error is a large relative one. Where p99 (>= 0) stays close to p99,
//!   the tail comes from elsewhere: bright texels not split off as exact lights whose
//!   horizon crossings fall between grid nodes, which bilinear interpolation smooths over
//!   ([`brdfkit::env::transfer`], "the K brightest texels"). The rel RMSE is relative to
//!   the image's energy, not to each pixel, so neither moves it much;
//! - pole +y / pole -y: relative RMSE of a 24 x 24 render of the sphere's top (bottom) seen
//!   along -y (+y) with a 4.9 degree field of view: every covered pixel's normal is within
//!   5 degrees of the pole (sphere of radius 1 seen from distance 3: a half-angle of 2.45
//!   degrees reaches the point of normal angle 5 degrees at height cos 5 = 0.996);
//! - build s: seconds to resolve the transfer scene (probe load and table build; tables are
//!   cached in a temporary directory for the run, so a basis already built under a probe
//!   shows its cached time).

use brdfkit::env::lightset::prepare::CacheDir;
use brdfkit::library::Representation;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;
use std::time::Instant;

/// Where the camera is: the whole sphere, or one pole.
#[derive(Clone, Copy)]
enum View {
    Sphere,
    Pole(f32),
}

fn scene(
    material: &str,
    probe: &str,
    method: &str,
    size: u32,
    view: View,
    k: usize,
    cache: &CacheDir,
) -> Scene {
    let sampler = if method == "lights" {
        "sampler = \"full\"\n".to_string()
    } else {
        format!("exact_lights = {k}\n")
    };
    let camera = match view {
        View::Sphere => String::new(),
        View::Pole(y) => format!(
            "[camera]\nposition = [0.0, {}, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\nfov_y_deg = 4.9\n",
            3.0 * y
        ),
    };
    let text = format!(
        "{camera}[mesh]\nsource = \"sphere\"\nsegments = 256\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\nmethod = \"{method}\"\n{sampler}\
         [render]\nwidth = {size}\nheight = {size}\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve_with_cache(&file, Path::new(env!("CARGO_MANIFEST_DIR")), cache).unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(64);
    let k: usize = args
        .iter()
        .find_map(|a| a.strip_prefix("k=")?.parse().ok())
        .unwrap_or(brdfkit::env::schema::DEFAULT_EXACT_LIGHTS);
    let only: Vec<&str> = args.iter().filter_map(|a| a.strip_prefix("m=")).collect();
    let mut probes: Vec<&str> = args
        .iter()
        .skip(1)
        .filter(|a| !a.contains('='))
        .map(|s| s.as_str())
        .collect();
    if probes.is_empty() {
        probes = vec!["city", "studio", "sky"];
    }
    let mut materials: Vec<(String, String)> = brdfkit::library::LIBRARY
        .iter()
        .filter(|e| matches!(e.representation, Representation::Sh { .. }))
        .map(|e| {
            (
                e.name.to_string(),
                format!("kind = \"library\"\nname = \"{}\"", e.name),
            )
        })
        .collect();
    materials.push((
        "lambert".into(),
        "kind = \"lambert\"\nalbedo = [0.8, 0.8, 0.8]".into(),
    ));
    materials.retain(|(n, _)| only.is_empty() || only.contains(&n.as_str()));
    let tmp = tempfile::tempdir().expect("a temporary cache directory");
    let cache = CacheDir::At {
        dir: tmp.path().to_path_buf(),
        max_bytes: u64::MAX,
    };
    let none = CacheDir::None;
    println!("exact_lights = {k}, {size} x {size}");
    println!(
        "| material | probe | rel RMSE | p99 | neg px | p99 (>= 0) | pole +y | pole -y | build s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for probe in &probes {
        for (name, spec) in &materials {
            let t0 = Instant::now();
            let tr = scene(spec, probe, "transfer", size, View::Sphere, k, &cache);
            let build = t0.elapsed().as_secs_f64();
            let got = render(&tr, &RenderOptions::default()).image;
            let reference = render(
                &scene(spec, probe, "lights", size, View::Sphere, k, &none),
                &RenderOptions::converged_reference(),
            )
            .image;
            let e = brdfkit::metrics::relative_rmse(&reference, &got, None);
            let q = brdfkit::metrics::relative_error_quantile(&reference, &got, 0.99, |_| true);
            let q_pos = brdfkit::metrics::relative_error_quantile(&reference, &got, 0.99, |r| {
                r.min_element() >= 0.0
            });
            let neg = reference
                .pixels
                .iter()
                .filter(|p| p.min_element() < 0.0)
                .count();
            let pole = |y: f32| {
                let top = render(
                    &scene(spec, probe, "transfer", 24, View::Pole(y), k, &cache),
                    &RenderOptions::default(),
                )
                .image;
                let top_ref = render(
                    &scene(spec, probe, "lights", 24, View::Pole(y), k, &none),
                    &RenderOptions::converged_reference(),
                )
                .image;
                brdfkit::metrics::relative_rmse(&top_ref, &top, None)
            };
            let (up, down) = (pole(1.0), pole(-1.0));
            println!(
                "| {name} | {probe} | {:.3}% | {:.2}% | {neg} | {:.2}% | {:.3}% | {:.3}% | {build:.2} |",
                e * 100.0,
                q * 100.0,
                q_pos * 100.0,
                up * 100.0,
                down * 100.0
            );
        }
    }
}
