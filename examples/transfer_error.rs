//! Error of `[env] method = "transfer"` against the converged reference, for people: the
//! table of issue 14 (deliverables 1 and 2).
//!
//! ```sh
//! cargo run --release --example transfer_error -- [SIZE] [k=EXACT_LIGHTS] [m=MATERIAL] [PROBE...]
//! ```
//!
//! `k=` sets `exact_lights` (default 16); `m=` keeps one material (repeatable).
//! For every library SH material and Lambert (albedo 0.8) under each shipped probe (or the
//! ones named: `city`, `studio`, `sky`), renders a 256-segment sphere at SIZE x SIZE
//! (default 64) with the transfer method (default grid 128 x 65, 16 exact lights) and with
//! the converged reference ([`RenderOptions::converged_reference`] on `sampler = "full"`,
//! f64, every texel a light), and prints:
//! - relative RMSE over the image ([`brdfkit::metrics::relative_rmse`]);
//! - p99: the 99th percentile over covered pixels of the per-pixel relative error
//!   `|x - r| / |r|` (RGB norms), pixels with `|r|` below 1% of the mean `|r|` left out;
//! - pole: relative RMSE of a second, 24 x 24 render of the sphere's top seen from above
//!   (fov 8 degrees: every pixel's normal within about 8 degrees of +y);
//! - build: seconds to resolve the transfer scene (probe load and table build).

use brdfkit::image_io::Image;
use brdfkit::library::Representation;
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;
use std::time::Instant;

fn scene(material: &str, probe: &str, method: &str, size: u32, top: bool, k: usize) -> Scene {
    let sampler = if method == "lights" {
        "sampler = \"full\"\n".to_string()
    } else {
        format!("exact_lights = {k}\n")
    };
    let camera = if top {
        "[camera]\nposition = [0.0, 3.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\nfov_y_deg = 8.0\n"
    } else {
        ""
    };
    let text = format!(
        "{camera}[mesh]\nsource = \"sphere\"\nsegments = 256\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\nmethod = \"{method}\"\n{sampler}\
         [render]\nwidth = {size}\nheight = {size}\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn p99(reference: &Image, img: &Image) -> f64 {
    let norms: Vec<f64> = reference
        .pixels
        .iter()
        .map(|p| p.as_dvec3().length())
        .collect();
    let covered: Vec<f64> = norms.iter().copied().filter(|&n| n > 0.0).collect();
    let mean = covered.iter().sum::<f64>() / covered.len().max(1) as f64;
    let mut rel: Vec<f64> = reference
        .pixels
        .iter()
        .zip(&img.pixels)
        .zip(&norms)
        .filter(|(_, &n)| n > 0.01 * mean)
        .map(|((r, x), &n)| (x.as_dvec3() - r.as_dvec3()).length() / n)
        .collect();
    rel.sort_by(f64::total_cmp);
    rel.get(((rel.len() as f64 * 0.99) as usize).min(rel.len().saturating_sub(1)))
        .copied()
        .unwrap_or(0.0)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(64);
    let k: usize = args
        .iter()
        .find_map(|a| a.strip_prefix("k=")?.parse().ok())
        .unwrap_or(16);
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
    println!("exact_lights = {k}");
    println!("| material | probe | rel RMSE | p99 | pole rel RMSE | build s | shade ms |");
    println!("|---|---|---|---|---|---|---|");
    for probe in &probes {
        for (name, spec) in &materials {
            let t0 = Instant::now();
            let tr = scene(spec, probe, "transfer", size, false, k);
            let build = t0.elapsed().as_secs_f64();
            let t1 = Instant::now();
            let got = render(&tr, &RenderOptions::default()).image;
            let shade = t1.elapsed().as_secs_f64() * 1e3;
            let reference = render(
                &scene(spec, probe, "lights", size, false, k),
                &RenderOptions::converged_reference(),
            )
            .image;
            let e = brdfkit::metrics::relative_rmse(&reference, &got, None);
            let q = p99(&reference, &got);
            let top = render(
                &scene(spec, probe, "transfer", 24, true, k),
                &RenderOptions::default(),
            )
            .image;
            let top_ref = render(
                &scene(spec, probe, "lights", 24, true, k),
                &RenderOptions::converged_reference(),
            )
            .image;
            let pole = brdfkit::metrics::relative_rmse(&top_ref, &top, None);
            println!(
                "| {name} | {probe} | {:.3}% | {:.2}% | {:.3}% | {build:.2} | {shade:.1} |",
                e * 100.0,
                q * 100.0,
                pole * 100.0
            );
        }
    }
}
