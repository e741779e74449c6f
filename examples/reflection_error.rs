//! Error of `[env] method = "reflection"` against the converged reference, for people: a
//! table, one row per material and probe, over all pixels and over the grazing band.
//!
//! ```sh
//! cargo run --release --example reflection_error -- [SIZE] [m=MATERIAL ...] [PROBE...]
//! ```
//!
//! For Blinn-Phong exponents 50, 200 and 500 (the scene format's other defaults) and the
//! library's isotropic D-BRDF `gold-dust-paint` (a Lambert + D-BRDF fit), the SH data set
//! `magenta-plastic` for contrast (its `auto` method is the transfer table: an SH set
//! includes the cosine and states no Lambertian term, so its diffuse part stays in the
//! series), and the anisotropic `lindt-paper` (refused), or the ones named by `m=`, under
//! each shipped probe (or the ones named: `city`, `studio`, `sky`), renders a 256-segment sphere at SIZE x SIZE
//! (default 96) with the default reflection table (64 x 64 cells, 13 + 1 slices, 64 exact
//! lights, residual 256 wide) and with the converged reference
//! ([`RenderOptions::converged_reference`] on `sampler = "full"`: f64, every texel a light),
//! and prints:
//! - relative RMSE over the image ([`brdfkit::metrics::relative_rmse`]) and p99, the 99th
//!   percentile of the per-pixel relative error `|x - r| / |r|` (RGB norms, pixels with `|r|`
//!   below 1% of the mean left out: [`brdfkit::metrics::relative_error_quantile`]);
//! - the same over the pixels whose view polar angle is above 70 degrees (the grazing band,
//!   from the `view-polar` AOV) and their share of the covered pixels;
//! - the bake's own measured error (camera-weighted samples; [`ReflectionTable::error`]), the
//!   bake time and the table's size.

use brdfkit::aov::{self, Aov};
use brdfkit::render::{rasterize, render, RenderOptions};
use brdfkit::scene::{Scene, SceneFile};
use std::path::Path;
use std::time::Instant;

fn scene(material: &str, probe: &str, env: &str, size: u32) -> Scene {
    try_scene(material, probe, env, size).unwrap()
}

fn try_scene(material: &str, probe: &str, env: &str, size: u32) -> brdfkit::error::Result<Scene> {
    let text = format!(
        "[mesh]\nsource = \"sphere\"\nsegments = 256\n[material]\n{material}\n\
         [env]\nfile = \"assets/probes/{probe}.exr\"\n{env}\n\
         [render]\nwidth = {size}\nheight = {size}\n"
    );
    let file = SceneFile::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Scene::resolve(&file, Path::new(env!("CARGO_MANIFEST_DIR")))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(96);
    let mut probes: Vec<&str> = args
        .iter()
        .skip(1)
        .filter(|a| !a.contains('='))
        .map(|s| s.as_str())
        .collect();
    let only: Vec<&str> = args.iter().filter_map(|a| a.strip_prefix("m=")).collect();
    if probes.is_empty() {
        probes = vec!["city", "studio", "sky"];
    }
    let materials = [
        ("blinn-phong-50", "kind = \"blinn-phong\"\nexponent = 50"),
        ("blinn-phong-200", "kind = \"blinn-phong\"\nexponent = 200"),
        ("blinn-phong-500", "kind = \"blinn-phong\"\nexponent = 500"),
        (
            "gold-dust-paint",
            "kind = \"library\"\nname = \"gold-dust-paint\"",
        ),
        (
            "magenta-plastic",
            "kind = \"library\"\nname = \"magenta-plastic\"",
        ),
        // Anisotropic (exponents 30 and 90): refused, a row says so.
        ("lindt-paper", "kind = \"library\"\nname = \"lindt-paper\""),
    ];
    println!(
        "| material | probe | rel RMSE | p99 | >70 deg rel RMSE | >70 deg p99 | >70 deg pixels | \
         bake: rel RMSE / p99 | bake s | MB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for probe in &probes {
        for (name, material) in materials {
            if !only.is_empty() && !only.contains(&name) {
                continue;
            }
            let t0 = Instant::now();
            let s = match try_scene(material, probe, "method = \"reflection\"", size) {
                Ok(s) => s,
                Err(e) => {
                    println!("| {name} | {probe} | refused: {e} |");
                    continue;
                }
            };
            let bake = t0.elapsed().as_secs_f64();
            let reference = render(
                &scene(material, probe, "sampler = \"full\"", size),
                &RenderOptions::converged_reference(),
            )
            .image;
            let got = render(&s, &RenderOptions::default()).image;
            let vis = rasterize(&s, false);
            let polar = aov::compute(&s, &vis, Aov::ViewPolar);
            let covered: Vec<bool> = reference.pixels.iter().map(|p| p.length() > 0.0).collect();
            let grazing: Vec<bool> = polar
                .pixels
                .iter()
                .zip(&covered)
                .map(|(p, &c)| c && p.x > 70.0 / 90.0)
                .collect();
            let all = brdfkit::metrics::relative_rmse(&reference, &got, None);
            let p99 = brdfkit::metrics::relative_error_quantile(&reference, &got, 0.99, |_| true);
            let g = brdfkit::metrics::relative_rmse(&reference, &got, Some(&grazing));
            // The grazing band's p99: the same quantile over the band's pixels alone.
            let mask = |img: &brdfkit::image_io::Image| {
                let mut m = img.clone();
                for (p, &k) in m.pixels.iter_mut().zip(&grazing) {
                    if !k {
                        *p = glam::Vec3::ZERO;
                    }
                }
                m
            };
            let gp99 = brdfkit::metrics::relative_error_quantile(
                &mask(&reference),
                &mask(&got),
                0.99,
                |_| true,
            );
            let share = grazing.iter().filter(|&&k| k).count() as f64
                / covered.iter().filter(|&&k| k).count().max(1) as f64;
            let t = s.environment.reflection_table().unwrap();
            let e = t.error();
            println!(
                "| {name} | {probe} | {:.3}% | {:.2}% | {:.3}% | {:.2}% | {:.1}% | {:.3}% / {:.2}% | {bake:.1} | {:.1} |",
                100.0 * all,
                100.0 * p99,
                100.0 * g,
                100.0 * gp99,
                100.0 * share,
                100.0 * e.rel_rmse,
                100.0 * e.p99,
                t.bytes() as f64 / 1e6
            );
        }
    }
}
