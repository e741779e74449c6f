//! Each library material's representation error where a user sees it: the converged render
//! of its representation (the SH data set or D-BRDF fit `brdfkit render` shades) against
//! the converged render of its source model (the analytic stand-in,
//! `brdfkit::library::source_material`), under each shipped probe.
//!
//! ```sh
//! cargo run --release --example library_error -- [SIZE] [MATERIAL...]
//! ```
//!
//! Renders a 128-segment sphere at SIZE x SIZE (default 48) with
//! `RenderOptions::converged_reference()` on `sampler = "full"` (f64, every probe texel a
//! light, no culling) for both, and prints one row per material and probe:
//! - relative RMSE over the image (`brdfkit::metrics::relative_rmse`);
//! - p99: the 99th percentile over covered pixels of `|x - r| / |r|` (RGB norms), pixels
//!   with `|r|` below 1% of the mean `|r|` left out (as `examples/transfer_error.rs`);
//! - the representation's negative pixels (`brdfkit::metrics::negative_pixels`).
//!
//! The converged render removes every error of the fast path, so what is left is the
//! representation's alone.

use brdfkit::library::{source_material, LIBRARY};
use brdfkit::render::{render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;

fn scene(material: &str, probe: &str, size: u32) -> Scene {
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 128\n\
         [material]\nkind = \"library\"\nname = \"{material}\"\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\nsampler = \"full\"\n\
         [render]\nwidth = {size}\nheight = {size}\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(48);
    let named: Vec<&str> = args
        .iter()
        .filter(|a| a.parse::<u32>().is_err())
        .map(String::as_str)
        .collect();
    println!("| material | probe | rel RMSE | p99 | negative pixels |");
    println!("|---|---|---|---|---|");
    for m in LIBRARY {
        if !named.is_empty() && !named.contains(&m.name) {
            continue;
        }
        for probe in ["city", "studio", "sky"] {
            let repr = scene(m.name, probe, size);
            let mut src = repr.clone();
            src.material = source_material(m.name).expect("library entries have sources");
            let opts = RenderOptions::converged_reference();
            let r = render(&src, &opts).image;
            let x = render(&repr, &opts).image;
            let neg = brdfkit::metrics::negative_pixels(&x);
            println!(
                "| {} | {probe} | {:.2}% | {:.2}% | {} |",
                m.name,
                100.0 * brdfkit::metrics::relative_rmse(&r, &x, None),
                100.0 * brdfkit::metrics::relative_error_quantile(&r, &x, 0.99, |_| true),
                neg.pixels
            );
        }
    }
}
