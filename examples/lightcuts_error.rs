//! Error of `[env] method = "lightcuts"` against the converged reference, for people: a
//! table, one row per material, probe and `cut_error`.
//!
//! ```sh
//! cargo run --release --example lightcuts_error -- [SIZE] [e=CUT_ERROR ...] [PROBE...]
//! ```
//!
//! For Blinn-Phong exponent 200 and the library D-BRDF (`lindt-paper`) under each shipped
//! probe (or the ones named: `city`, `studio`, `sky`), renders a 256-segment sphere at
//! SIZE x SIZE (default 64) with light cuts at each `cut_error` given (default 0.01;
//! `cut_max` default) and with the converged reference
//! ([`RenderOptions::converged_reference`] on `sampler = "full"`, f64, every texel a light),
//! and prints:
//! - relative RMSE over the image ([`brdfkit::metrics::relative_rmse`]);
//! - p99: the 99th percentile over covered pixels of the per-pixel relative error
//!   `|x - r| / |r|` (RGB norms), pixels with `|r|` below 1% of the mean `|r|` left out
//!   (as `examples/transfer_error.rs`);
//! - the mean and largest cut (clusters per pixel) and the pixels `cut_max` stopped.

use brdfkit::render::{rasterize, render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use brdfkit::shade::{shade, ShadeOptions};
use std::path::Path;

fn scene(material: &str, probe: &str, env: &str, size: u32) -> Scene {
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 256\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\n{env}\n\
         [render]\nwidth = {size}\nheight = {size}\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(64);
    let mut errors: Vec<f32> = args
        .iter()
        .filter_map(|a| a.strip_prefix("e=")?.parse().ok())
        .collect();
    if errors.is_empty() {
        errors.push(0.01);
    }
    let mut probes: Vec<&str> = args
        .iter()
        .skip(1)
        .filter(|a| !a.contains('='))
        .map(|s| s.as_str())
        .collect();
    if probes.is_empty() {
        probes = vec!["city", "studio", "sky"];
    }
    let materials = [
        ("blinn-phong-200", "kind = \"blinn-phong\"\nexponent = 200"),
        ("lindt-paper", "kind = \"library\"\nname = \"lindt-paper\""),
    ];
    println!("| material | probe | cut_error | rel RMSE | p99 | mean cut | largest | capped |");
    println!("|---|---|---|---|---|---|---|---|");
    for probe in &probes {
        for (name, material) in materials {
            let reference = render(
                &scene(material, probe, "sampler = \"full\"", size),
                &RenderOptions::converged_reference(),
            )
            .image;
            for e in &errors {
                let s = scene(
                    material,
                    probe,
                    &format!("method = \"lightcuts\"\ncut_error = {e}"),
                    size,
                );
                let vis = rasterize(&s, false);
                let shaded = shade(&s, &vis, &ShadeOptions::default());
                let c = shaded.report.cuts;
                println!(
                    "| {name} | {probe} | {e} | {:.3}% | {:.2}% | {:.1} | {} | {} |",
                    100.0 * brdfkit::metrics::relative_rmse(&reference, &shaded.image, None),
                    100.0
                        * brdfkit::metrics::relative_error_quantile(
                            &reference,
                            &shaded.image,
                            0.99,
                            |_| true
                        ),
                    c.mean(),
                    c.largest,
                    c.capped
                );
            }
        }
    }
}
